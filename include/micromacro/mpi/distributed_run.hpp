#pragma once
// A scene run over MPI ranks with the serial engine: each rank runs a BasicSimulation on the
// particles its subdomain owns followed by the ghosts of its halo (in an open box: a ghost
// across a periodic boundary sits at its image), and after every particle pass refreshes the
// ghosts from their owners before the forces are computed. The forces, laws, springs and
// integrator are the serial ones: the integrator policy drives this class through the same
// stages (kick_drift_kick, compute_forces, kick_force_change) it drives the engine through. A
// ghost's own force is incomplete and never used: its state is overwritten at every refresh.
//
// Not built yet: redistribution. The run stops with an error once a particle has moved half the
// skin since the start (a real run would then hand particles to their new owners and rebuild the
// halos, carrying each pair's spring along), and walls are not supported.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <optional>
#include <utility>
#include <vector>

#include <mpi.h>

#include "micromacro/core/dim_traits.hpp"
#include "micromacro/core/domain.hpp"
#include "micromacro/core/error.hpp"
#include "micromacro/engine/simulation.hpp"
#include "micromacro/mpi/communicator.hpp"
#include "micromacro/mpi/halo.hpp"

namespace micromacro::mpi {

template <class Sim>
class DistributedRun {
public:
    static constexpr int dim = Sim::dimension;
    static_assert(!Sim::has_walls, "DistributedRun: walls across ranks are not built yet");
    static_assert(Sim::rotation, "DistributedRun: needs a law with rotation (the records carry angular velocities)");

    /// Splits `whole` (the same scene on every rank: particles, law, dt, skin, a box) over the
    /// ranks of `parent`. The halo is the largest contact distance plus the skin.
    DistributedRun(MPI_Comm parent, const Sim& whole)
        : comm_(parent, whole.domain()), local_(whole.law()), skin_(whole.skin()), dt_(whole.time_step()) {
        const auto& p = whole.particles();
        double largest_radius = 0.0;
        for (std::size_t i = 0; i < p.size(); ++i) largest_radius = std::max(largest_radius, double(p.radius()[i]));
        std::vector<ParticleRecord> owned;
        for (std::size_t i = 0; i < p.size(); ++i)
            if (comm_.split().owns(p.position()[i])) owned.push_back(record(p, i, p.id(i)));
        halo_.emplace(comm_, owned, 2.0 * largest_radius + skin_);
        for (const auto* set : std::array<const std::vector<ParticleRecord>*, 2>{&owned, &halo_->ghosts()})
            for (const ParticleRecord& r : *set) {
                Vec<dim> x;
                for (int a = 0; a < dim; ++a) x[a] = r.x[a];
                const std::size_t i = local_.particles().add(x, r.radius, r.mass, r.inertia);
                write_motion(i, r);
                global_.push_back(r.id);
            }
        owned_ = owned.size();
        start_.assign(local_.particles().position().begin(), local_.particles().position().begin() + owned_);
        local_.set_time_step(dt_);
        local_.set_skin(skin_);
        local_.set_auto_sort(false);     // the first owned_ particles stay the owned ones
        local_.set_track_energy(false);  // the books would count the ghosts' contacts too
        local_.prepare();
        rebuilds_ = local_.neighbor_rebuilds();
    }

    const CartesianComm<dim>& comm() const { return comm_; }
    /// The engine of this rank: its particles [0, owned()) are this rank's, the rest ghosts.
    const Sim& local() const { return local_; }
    std::size_t owned() const { return owned_; }
    /// The global id of local particle i (the whole scene's particle id).
    Index global_id(std::size_t i) const { return global_[local_.particles().id(i)]; }

    void step() { typename Sim::IntegratorPolicy{}.step(*this, dt_); }
    void run(std::size_t steps) {
        for (std::size_t k = 0; k < steps; ++k) step();
    }

    // ---- the stages the integrator policy calls ------------------------------------------------
    void kick_drift_kick(double h_before, double dt, double h_after, double h_closing = 0.0) {
        local_.kick_drift_kick(h_before, dt, h_after, h_closing);
        refresh_ghosts();
    }
    void compute_forces() { local_.compute_forces(); }
    void kick_force_change(double h) { local_.kick_force_change(h); }

private:
    template <class Particles>
    static ParticleRecord record(const Particles& p, std::size_t i, Index id) {
        ParticleRecord r{id, double(p.radius()[i]), double(p.mass()[i]), double(p.template get<field::Inertia>()[i]), {}, {}, {}};
        for (int a = 0; a < dim; ++a) {
            r.x[a] = p.position()[i][a];
            r.v[a] = p.velocity()[i][a];
        }
        const auto& w = p.template get<field::AngularVelocity>()[i];
        if constexpr (dim == 2) r.w[2] = w;
        else
            for (int a = 0; a < 3; ++a) r.w[a] = w[a];
        return r;
    }

    void write_motion(std::size_t i, const ParticleRecord& r) {
        auto& p = local_.particles();
        for (int a = 0; a < dim; ++a) {
            p.position()[i][a] = r.x[a];
            p.velocity()[i][a] = r.v[a];
        }
        auto& w = p.template get<field::AngularVelocity>()[i];
        if constexpr (dim == 2) w = r.w[2];
        else
            for (int a = 0; a < 3; ++a) w[a] = r.w[a];
    }

    /// The ghosts from their owners' present state; stops the run once redistribution would be due.
    void refresh_ghosts() {
        const auto& p = local_.particles();
        std::vector<ParticleRecord> owned;
        owned.reserve(owned_);
        double largest_move = 0.0;
        for (std::size_t i = 0; i < owned_; ++i) {
            owned.push_back(record(p, i, global_[i]));
            largest_move = std::max(largest_move, (p.position()[i] - start_[i]).norm());
        }
        // The engine rebuilt its lists in the pass if its particles (the ghosts as it integrated
        // them, before this refresh) had moved half the skin: due only where redistribution is.
        // Both are decided over every rank at once, so that every rank stops together.
        const double here[2] = {largest_move, local_.neighbor_rebuilds() != rebuilds_ ? 1.0 : 0.0};
        double everywhere[2] = {0.0, 0.0};
        check(MPI_Allreduce(here, everywhere, 2, MPI_DOUBLE, MPI_MAX, comm_.comm()), "MPI_Allreduce (largest move)");
        if (2.0 * everywhere[0] >= skin_ || everywhere[1] > 0.0)
            micromacro::detail::throw_input_error("a particle has moved ", everywhere[0], " m, about half the skin of ", skin_,
                                                  " m: handing particles to new ranks is not built yet; run fewer steps or "
                                                  "give a larger skin");
        halo_->refresh(comm_, owned);
        const auto& ghosts = halo_->ghosts();
        for (std::size_t k = 0; k < ghosts.size(); ++k) write_motion(owned_ + k, ghosts[k]);
    }

    CartesianComm<dim> comm_;
    Sim local_;
    std::optional<Halo<dim>> halo_;  // built in the constructor
    std::vector<Index> global_;    // by local id (the order added): owned, then ghosts
    std::vector<Vec<dim>> start_;  // the owned particles' positions at the start
    std::size_t owned_ = 0, rebuilds_ = 0;
    double skin_, dt_;
};

}  // namespace micromacro::mpi
