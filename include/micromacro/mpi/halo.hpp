#pragma once
// Ghost particles: copies of the particles within a halo width of a rank's subdomain, from the
// ranks that own them, placed where this rank sees them (shifted by a box length across a
// periodic boundary). The exchange runs axis by axis, each axis both ways, and passes on the
// ghosts already received, so that particles diagonally across a corner arrive too (as in
// LAMMPS's Comm::borders): afterwards a rank holds every particle image whose position lies
// within `width` of its subdomain (the subdomain grown by `width` on every side with a
// neighbour), each once. Needs a halo no wider than a slab (CartesianSplit::check_halo).
#include <array>
#include <cstddef>
#include <type_traits>
#include <vector>

#include <mpi.h>

#include "micromacro/core/index.hpp"
#include "micromacro/mpi/communicator.hpp"

namespace micromacro::mpi {

/// What a rank needs of a particle it does not own to compute the forces on its own ones: plain
/// numbers (sent as bytes), 3 components whatever the dimension (2D: z = 0; angular velocity:
/// z only in 2D).
struct ParticleRecord {
    Index id;                   ///< the particle's global id
    double radius, mass, inertia;
    std::array<double, 3> x, v, w;
};
static_assert(std::is_trivially_copyable_v<ParticleRecord>);

namespace detail {
/// Sends `out` to rank `to` and returns what rank `from` sends (either may be MPI_PROC_NULL).
inline std::vector<ParticleRecord> shift(MPI_Comm comm, const std::vector<ParticleRecord>& out, int to, int from) {
    unsigned long long sending = out.size(), receiving = 0;
    check(MPI_Sendrecv(&sending, 1, MPI_UNSIGNED_LONG_LONG, to, 0, &receiving, 1, MPI_UNSIGNED_LONG_LONG, from, 0, comm,
                       MPI_STATUS_IGNORE),
          "MPI_Sendrecv (halo counts)");
    std::vector<ParticleRecord> in(receiving);
    const int out_bytes = static_cast<int>(out.size() * sizeof(ParticleRecord));
    const int in_bytes = static_cast<int>(in.size() * sizeof(ParticleRecord));
    check(MPI_Sendrecv(out.data(), out_bytes, MPI_BYTE, to, 1, in.data(), in_bytes, MPI_BYTE, from, 1, comm, MPI_STATUS_IGNORE),
          "MPI_Sendrecv (halo particles)");
    return in;
}
}  // namespace detail

/// The ghosts of this rank: every image of another rank's particle (or, with one slab on a
/// periodic axis, of its own) within `width` of this rank's subdomain. `owned` are the
/// particles this rank owns, at positions inside its subdomain.
template <int dim>
std::vector<ParticleRecord> exchange_halo(const CartesianComm<dim>& comm, const std::vector<ParticleRecord>& owned, double width) {
    const CartesianSplit<dim>& split = comm.split();
    split.check_halo(width);
    std::vector<ParticleRecord> ghosts;
    for (int a = 0; a < dim; ++a) {
        const double lo = split.sub_lo(a), hi = split.sub_hi(a), length = split.hi[a] - split.lo[a];
        // What goes down (to the rank below) and up, chosen from the owned particles and the
        // ghosts received along the earlier axes, before this axis's ghosts are added.
        std::array<std::vector<ParticleRecord>, 2> out;
        for (const auto* set : std::array<const std::vector<ParticleRecord>*, 2>{&owned, &ghosts})
            for (const ParticleRecord& p : *set) {
                if (p.x[a] < lo + width) out[0].push_back(p);
                if (p.x[a] >= hi - width) out[1].push_back(p);
            }
        // Across the box's ends a periodic axis wraps: the image arrives a box length away.
        if (split.coords[a] == 0)
            for (auto& p : out[0]) p.x[a] += length;
        if (split.coords[a] == split.dims[a] - 1)
            for (auto& p : out[1]) p.x[a] -= length;
        const auto from_above = detail::shift(comm.comm(), out[0], comm.neighbour(a, -1), comm.neighbour(a, +1));
        const auto from_below = detail::shift(comm.comm(), out[1], comm.neighbour(a, +1), comm.neighbour(a, -1));
        ghosts.insert(ghosts.end(), from_above.begin(), from_above.end());
        ghosts.insert(ghosts.end(), from_below.begin(), from_below.end());
    }
    return ghosts;
}

}  // namespace micromacro::mpi
