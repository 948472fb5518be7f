#pragma once
// Ghost particles: copies of the particles within a halo width of a rank's subdomain, from the
// ranks that own them, at their owners' positions in the whole box (wrapped into it, as the
// serial engine keeps them): a rank's engine runs in the whole box and measures a pair across a
// periodic boundary by the minimum image, as the serial engine does. An axis of one slab has
// none: open, it has no neighbour; periodic, the rank's engine wraps it itself. Building a Halo
// (LAMMPS's Comm::borders) runs axis by axis, each axis both ways, and passes on the ghosts
// already received, so that particles diagonally across a corner arrive too: afterwards a rank
// holds, once each, every particle of another rank with an image within `width` of its
// subdomain (the subdomain grown by `width` on every side with a neighbour). Where both
// neighbours along an axis are one rank (two slabs of a periodic axis) a particle near both
// faces goes once: its one copy serves both sides by the minimum image.
// refresh() (LAMMPS's forward_comm) sends the same particles' new states along the same swaps,
// for the steps until the next rebuild. Needs a halo no wider than a slab
// (CartesianSplit::check_halo).
#include <algorithm>
#include <array>
#include <cstddef>
#include <type_traits>
#include <vector>

#include <mpi.h>

#include "micromacro/core/dim_traits.hpp"
#include "micromacro/core/index.hpp"
#include "micromacro/mpi/communicator.hpp"
#include "micromacro/particles/particles.hpp"

namespace micromacro::mpi {

/// What a rank needs of a particle it does not own to compute the forces on its own ones: plain
/// numbers (sent as bytes), 3 components whatever the dimension (2D: z = 0; angular velocity:
/// z only in 2D).
struct ParticleRecord {
    Index id;                   ///< the particle's global id
    Index place = 0;            ///< its place in the serial run's numbering (DistributedRun sums forces in that order)
    double radius, mass, inertia;
    std::array<double, 3> x, v, w;
};
static_assert(std::is_trivially_copyable_v<ParticleRecord>);

/// What a refresh sends of a ghost: its motion only (40 bytes in 2D, 72 in 3D against the
/// record's 104).
template <int dim>
struct Motion {
    std::array<double, dim> x, v;
    std::array<double, dim == 2 ? 1 : 3> w;
    static Motion of(const ParticleRecord& r) {
        Motion m;
        for (int a = 0; a < dim; ++a) m.x[a] = r.x[a], m.v[a] = r.v[a];
        for (std::size_t a = 0; a < m.w.size(); ++a) m.w[a] = r.w[3 - m.w.size() + a];
        return m;
    }
    /// The angular velocity as the engine stores it.
    Angular<dim> angular() const {
        if constexpr (dim == 2) return w[0];
        else return Vec<3>(w[0], w[1], w[2]);
    }
    void write_to(ParticleRecord& r) const {
        for (int a = 0; a < dim; ++a) r.x[a] = x[a], r.v[a] = v[a];
        for (std::size_t a = 0; a < w.size(); ++a) r.w[3 - w.size() + a] = w[a];
    }
};

/// A position or velocity as a record's 3 numbers (2D: z = 0).
template <int dim>
std::array<double, 3> record_vector(const Vec<dim>& v) {
    return {v[0], v[1], dim == 3 ? v[dim - 1] : 0.0};
}
/// An angular velocity or torque as a record's 3 numbers (2D: the z component), and back.
template <int dim>
std::array<double, 3> record_angular(const Angular<dim>& w) {
    if constexpr (dim == 2) return {0.0, 0.0, w};
    else return {w[0], w[1], w[2]};
}
/// A record's position or velocity as a vector.
template <int dim>
Vec<dim> vector_of_record(const std::array<double, 3>& v) {
    Vec<dim> x;
    for (int a = 0; a < dim; ++a) x[a] = v[a];
    return x;
}
template <int dim>
Angular<dim> angular_of_record(const std::array<double, 3>& w) {
    if constexpr (dim == 2) return w[2];
    else return Vec<3>(w[0], w[1], w[2]);
}

/// Particle i of a particle set with rotation as a record, with the global id `id` and the
/// place `place` in the serial numbering.
template <int dim, class Real>
ParticleRecord record_of(const Particles<dim, true, Real>& p, std::size_t i, Index id, Index place = 0) {
    return {id,
            place,
            double(p.radius()[i]),
            double(p.mass()[i]),
            double(p.template get<field::Inertia>()[i]),
            record_vector<dim>(convert<double>(p.position()[i])),
            record_vector<dim>(convert<double>(p.velocity()[i])),
            record_angular<dim>(convert<double>(p.template get<field::AngularVelocity>()[i]))};
}

/// Particle i's motion as a refresh sends it, read from the arrays (no radius, mass or id).
template <int dim, class Real>
Motion<dim> motion_of(const Particles<dim, true, Real>& p, std::size_t i) {
    Motion<dim> m;
    const Vec<dim> x = convert<double>(p.position()[i]), v = convert<double>(p.velocity()[i]);
    for (int a = 0; a < dim; ++a) m.x[a] = x[a], m.v[a] = v[a];
    const auto w = record_angular<dim>(convert<double>(p.template get<field::AngularVelocity>()[i]));
    for (std::size_t a = 0; a < m.w.size(); ++a) m.w[a] = w[3 - m.w.size() + a];
    return m;
}

namespace halo_detail {
/// Sends `out` to rank `to` and receives what rank `from` sends (either may be MPI_PROC_NULL)
/// into `in`, which the caller sized to the count that comes (a refresh's buffers, kept from
/// step to step).
template <class T>
void shift_into(MPI_Comm comm, const std::vector<T>& out, int to, int from, std::vector<T>& in) {
    const int out_bytes = static_cast<int>(out.size() * sizeof(T));
    const int in_bytes = static_cast<int>(in.size() * sizeof(T));
    check(MPI_Sendrecv(out.data(), out_bytes, MPI_BYTE, to, 1, in.data(), in_bytes, MPI_BYTE, from, 1, comm, MPI_STATUS_IGNORE),
          "MPI_Sendrecv (halo particles)");
}
/// The same returning what comes; `expected`: its count, when known (a refresh), else it is
/// sent first.
template <class T>
std::vector<T> shift(MPI_Comm comm, const std::vector<T>& out, int to, int from, long long expected = -1) {
    unsigned long long sending = out.size(), receiving = expected < 0 ? 0 : static_cast<unsigned long long>(expected);
    if (expected < 0)
        check(MPI_Sendrecv(&sending, 1, MPI_UNSIGNED_LONG_LONG, to, 0, &receiving, 1, MPI_UNSIGNED_LONG_LONG, from, 0, comm,
                           MPI_STATUS_IGNORE),
              "MPI_Sendrecv (halo counts)");
    std::vector<T> in(receiving);
    shift_into(comm, out, to, from, in);
    return in;
}
}  // namespace halo_detail

template <int dim>
class Halo {
public:
    /// The ghosts of this rank: every particle of another rank with an image within `width` of
    /// this rank's subdomain along the axes of more than one slab, once, at its own position.
    /// `owned` are the particles this rank owns, at positions inside its subdomain.
    Halo(const CartesianComm<dim>& comm, const std::vector<ParticleRecord>& owned, double width) {
        const CartesianSplit<dim>& split = comm.split();
        split.check_halo(width);
        owned_count_ = owned.size();
        for (int a = 0; a < dim; ++a) {
            if (split.dims[a] == 1) continue;  // no neighbour, or one periodic slab the rank's engine wraps itself
            const double lo = split.sub_lo(a), hi = split.sub_hi(a);
            // What goes down (to the rank below) and up, chosen from the owned particles and the
            // ghosts received along the earlier axes, before this axis's ghosts are added; to a
            // rank that is both neighbours, once.
            const bool one_neighbour = comm.neighbour(a, -1) == comm.neighbour(a, +1);
            Swap down{a, -1, {}, 0, 0}, up{a, +1, {}, 0, 0};
            const std::size_t known = owned.size() + ghosts_.size();
            for (std::size_t k = 0; k < known; ++k) {
                const ParticleRecord& p = k < owned.size() ? owned[k] : ghosts_[k - owned.size()];
                const bool goes_down = p.x[a] < lo + width;
                if (goes_down) down.sent.push_back(k);
                if (p.x[a] >= hi - width && !(one_neighbour && goes_down)) up.sent.push_back(k);
            }
            for (Swap* s : {&down, &up}) {
                s->received_begin = ghosts_.size();
                const auto in = send(comm, *s, [&](std::size_t k) { return owned[k]; }, -1);
                s->received_count = in.size();
                ghosts_.insert(ghosts_.end(), in.begin(), in.end());
                swaps_.push_back(std::move(*s));
            }
        }
    }

    const std::vector<ParticleRecord>& ghosts() const { return ghosts_; }

    /// The ghosts' positions, velocities and angular velocities from their owners' present ones
    /// (sent as Motion):
    /// `owned` lists the same particles in the same order as when the halo was built.
    void refresh(const CartesianComm<dim>& comm, const std::vector<ParticleRecord>& owned) {
        refresh(comm,
                [&](std::size_t k) { return Motion<dim>::of(k < owned_count_ ? owned[k] : ghosts_[k - owned_count_]); },
                [&](std::size_t g, const Motion<dim>& m) { m.write_to(ghosts_[g]); });
    }
    /// The same where the particles live elsewhere (an engine's arrays, the owned particles
    /// followed by the ghosts in the order of ghosts()), so that only the particles sent are read,
    /// and only their motion: `read(k)` is the present motion of particle k in that numbering,
    /// owned or ghost (motion_of), and `write(g, m)` stores ghost g's. This form leaves ghosts()
    /// as it was.
    template <class Read, class Write>
        requires std::is_invocable_r_v<Motion<dim>, Read, std::size_t> && std::is_invocable_v<Write, std::size_t, const Motion<dim>&>
    void refresh(const CartesianComm<dim>& comm, Read&& read, Write&& write) {
        for (const Swap& s : swaps_) {
            sent_.clear();
            for (const std::size_t k : s.sent) sent_.push_back(read(k));
            received_.resize(s.received_count);
            halo_detail::shift_into(comm.comm(), sent_, comm.neighbour(s.axis, s.direction), comm.neighbour(s.axis, -s.direction),
                                    received_);
            for (std::size_t k = 0; k < received_.size(); ++k) write(s.received_begin + k, received_[k]);
        }
    }

    /// A value per particle from the owners to the ghosts (LAMMPS's forward_comm of a per-atom
    /// quantity): `owned` by owned index, the ghosts' in the order of ghosts().
    template <class T>
        requires std::is_trivially_copyable_v<T>
    std::vector<T> forward(const CartesianComm<dim>& comm, const std::vector<T>& owned) const {
        std::vector<T> ghost(ghosts_.size());
        for (const Swap& s : swaps_) {
            std::vector<T> out;
            out.reserve(s.sent.size());
            for (const std::size_t k : s.sent) out.push_back(k < owned_count_ ? owned[k] : ghost[k - owned_count_]);
            const auto in = halo_detail::shift(comm.comm(), out, comm.neighbour(s.axis, s.direction),
                                               comm.neighbour(s.axis, -s.direction), static_cast<long long>(s.received_count));
            std::copy(in.begin(), in.end(), ghost.begin() + static_cast<std::ptrdiff_t>(s.received_begin));
        }
        return ghost;
    }

    /// What a refresh sends from this rank: bytes and messages (one per swap with a neighbour).
    std::size_t bytes_per_refresh() const {
        std::size_t n = 0;
        for (const Swap& s : swaps_) n += s.sent.size() * sizeof(Motion<dim>);
        return n;
    }
    std::size_t messages_per_refresh(const CartesianComm<dim>& comm) const {
        std::size_t n = 0;
        for (const Swap& s : swaps_) n += comm.neighbour(s.axis, s.direction) != MPI_PROC_NULL;
        return n;
    }

private:
    /// One exchange across a face: which of the owned and ghost particles go (their indices in
    /// owned followed by ghosts) along `axis`, and where what comes back lands in the ghosts.
    struct Swap {
        int axis, direction;
        std::vector<std::size_t> sent;
        std::size_t received_begin, received_count;
    };

    template <class Owned>
    std::vector<ParticleRecord> send(const CartesianComm<dim>& comm, const Swap& s, Owned&& owned, long long expected) const {
        std::vector<ParticleRecord> out;
        out.reserve(s.sent.size());
        for (const std::size_t k : s.sent) out.push_back(k < owned_count_ ? owned(k) : ghosts_[k - owned_count_]);
        return halo_detail::shift(comm.comm(), out, comm.neighbour(s.axis, s.direction), comm.neighbour(s.axis, -s.direction),
                                  expected);
    }

    std::vector<Swap> swaps_;
    std::vector<ParticleRecord> ghosts_;
    std::size_t owned_count_ = 0;
    std::vector<Motion<dim>> sent_, received_;  // a refresh's buffers, kept from step to step
};

}  // namespace micromacro::mpi
