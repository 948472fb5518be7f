#pragma once
// A scene run over MPI ranks with the serial engine: each rank runs a BasicSimulation on the
// particles its subdomain owns followed by the ghosts of its halo (a ghost across a periodic
// boundary between ranks sits at its image; an axis of one periodic slab stays periodic in the
// rank's engine, so one rank runs the serial engine on the serial box), and after every
// particle pass refreshes the ghosts from their owners before the forces are computed. The forces, laws, springs and
// integrator are the serial ones: the integrator policy drives this class through the same
// stages (kick_drift_kick, compute_forces, kick_force_change) it drives the engine through. A
// ghost's own force is incomplete and never used: its state is overwritten at every refresh.
//
// Once a particle has moved half the skin since the last distribution (or a rank's engine has
// rebuilt its lists on its own), every rank redistributes, in the step, between the particle
// pass and the forces: the particles go to the ranks that own their positions now, each with its
// last force and torque (the integrator's closing kick needs them) and each pair's spring with
// it, the halos are built again and each rank's engine is rebuilt on its new particles. The
// exchange gathers every rank's particles on every rank (MPI_Allgatherv): simple and exact, but
// its cost grows with the whole scene, not with the halo; passing them to the neighbouring ranks
// only is the next step, as are walls.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <map>
#include <optional>
#include <type_traits>
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
    using History = typename Sim::History;
    using Law = std::remove_cvref_t<decltype(std::declval<const Sim&>().law())>;
    static_assert(!Sim::has_walls, "DistributedRun: walls across ranks are not built yet");
    static_assert(Sim::rotation && Law::has_history,
                  "DistributedRun: needs a law with rotation and springs (the records carry angular velocities)");

    /// Splits `whole` (the same scene on every rank: particles, law, dt, skin, a box) over the
    /// ranks of `parent` and computes the first forces. The skin is the scene's, or the engine's
    /// default (a fifth of the mean radius); the halo is the largest contact distance plus it.
    DistributedRun(MPI_Comm parent, const Sim& whole)
        : comm_(parent, whole.domain()), box_(whole.domain()), law_(whole.law()), skin_(whole.skin()), dt_(whole.time_step()) {
        const auto& p = whole.particles();
        double largest_radius = 0.0, radii = 0.0;
        for (std::size_t i = 0; i < p.size(); ++i) {
            largest_radius = std::max(largest_radius, double(p.radius()[i]));
            radii += double(p.radius()[i]);
        }
        if (!(skin_ > 0.0) && p.size() > 0) skin_ = 0.2 * radii / double(p.size());
        width_ = 2.0 * largest_radius + skin_;
        std::vector<State> all;
        for (std::size_t i = 0; i < p.size(); ++i) {
            State s{record(p, i, p.id(i)), {}, {}};
            Vec<dim> x = p.position()[i];
            box_.wrap(x);  // as the serial engine does before its first step
            for (int a = 0; a < dim; ++a) s.r.x[a] = x[a];
            all.push_back(s);
        }
        distribute(all, {}, true);
    }

    const CartesianComm<dim>& comm() const { return comm_; }
    /// The engine of this rank: its particles [0, owned()) are this rank's, the rest ghosts.
    const Sim& local() const { return *local_; }
    std::size_t owned() const { return owned_; }
    /// The global id of local particle i (the whole scene's particle id).
    Index global_id(std::size_t i) const { return global_[local_->particles().id(i)]; }
    /// How often the particles were handed to new ranks.
    std::size_t redistributions() const { return redistributions_; }
    /// This rank's halo traffic per step: bytes and messages it sends to refresh the ghosts.
    std::size_t halo_bytes_per_step() const { return halo_->bytes_per_refresh(); }
    std::size_t halo_messages_per_step() const { return halo_->messages_per_refresh(comm_); }

    void step() { typename Sim::IntegratorPolicy{}.step(*this, dt_); }
    /// `steps` steps, each closing kick merged into the next step's pass as the engine's run()
    /// does: the same bits as calling step() that often, a pass over the particles less per step.
    void run(std::size_t steps) {
        if (steps > 0) typename Sim::IntegratorPolicy{}.run(*this, dt_, steps);
    }

    // ---- the stages the integrator policy calls ------------------------------------------------
    void kick_drift_kick(double h_before, double dt, double h_after, double h_closing = 0.0) {
        local_->kick_drift_kick(h_before, dt, h_after, h_closing);
        refresh_or_redistribute();
    }
    void compute_forces() { local_->compute_forces(); }
    void kick_force_change(double h) { local_->kick_force_change(h); }

private:
    /// A particle with what its new rank needs mid-step: its state and its last force and torque.
    struct State {
        ParticleRecord r;
        std::array<double, 3> force, torque;
    };
    /// A pair's spring by the pair's global ids (a < b), as a sees it.
    struct PairHistory {
        Index a, b;
        History h;
    };

    template <class Particles>
    static ParticleRecord record(const Particles& p, std::size_t i, Index id) {
        ParticleRecord r{id, double(p.radius()[i]), double(p.mass()[i]), double(p.template get<field::Inertia>()[i]), {}, {}, {}};
        for (int a = 0; a < dim; ++a) {
            r.x[a] = p.position()[i][a];
            r.v[a] = p.velocity()[i][a];
        }
        r.w = angular(p.template get<field::AngularVelocity>()[i]);
        return r;
    }
    static std::array<double, 3> angular(const Angular<dim>& w) {
        if constexpr (dim == 2) return {0.0, 0.0, w};
        else return {w[0], w[1], w[2]};
    }
    static Angular<dim> angular(const std::array<double, 3>& w) {
        if constexpr (dim == 2) return w[2];
        else return Vec<3>(w[0], w[1], w[2]);
    }

    void write_motion(std::size_t i, const ParticleRecord& r) {
        auto& p = local_->particles();
        for (int a = 0; a < dim; ++a) {
            p.position()[i][a] = r.x[a];
            p.velocity()[i][a] = r.v[a];
        }
        p.template get<field::AngularVelocity>()[i] = angular(r.w);
    }

    /// After a particle pass: the ghosts from their owners' present state, or, once a particle
    /// has moved half the skin or an engine has rebuilt its lists from ghosts it integrated
    /// itself, a redistribution. Decided over every rank at once.
    void refresh_or_redistribute() {
        const auto& p = local_->particles();
        // The engine's own largest move since the distribution (its last rebuild): its ghosts'
        // are one step's integration off, but each ghost's owner counts it exactly.
        const double here[2] = {local_->largest_move(), local_->neighbor_rebuilds() != rebuilds_ ? 1.0 : 0.0};
        double everywhere[2] = {0.0, 0.0};
        check(MPI_Allreduce(here, everywhere, 2, MPI_DOUBLE, MPI_MAX, comm_.comm()), "MPI_Allreduce (largest move)");
        if (2.0 * everywhere[0] >= skin_ || everywhere[1] > 0.0) {
            redistribute();
            return;
        }
        halo_->refresh(comm_, [&](std::size_t i) { return record(p, i, global_[i]); });
        const auto& ghosts = halo_->ghosts();
        for (std::size_t k = 0; k < ghosts.size(); ++k) write_motion(owned_ + k, ghosts[k]);
    }

    /// Every rank's particles (position wrapped into the box, last force and torque) and the
    /// springs of their pairs, gathered on every rank and distributed afresh.
    void redistribute() {
        const auto& p = local_->particles();
        std::vector<State> mine;
        for (std::size_t i = 0; i < owned_; ++i) {
            State s{record(p, i, global_[i]), {}, angular(p.template get<field::Torque>()[i])};
            Vec<dim> x = p.position()[i];
            box_.wrap(x);
            for (int a = 0; a < dim; ++a) s.r.x[a] = x[a], s.force[a] = p.force()[i][a];
            mine.push_back(s);
        }
        std::vector<PairHistory> springs;
        local_->visit_pair_histories([&](Index i, Index j, const History& h) {
            if (i >= owned_ && j >= owned_) return;  // between two ghosts: another rank's
            const Index a = global_id(i), b = global_id(j);
            springs.push_back(a < b ? PairHistory{a, b, h} : PairHistory{b, a, seen_from_partner(h)});
        });
        const auto all = gather(mine), all_springs = gather(springs);
        std::map<std::pair<Index, Index>, History> by_pair;
        for (const PairHistory& s : all_springs) by_pair.emplace(std::pair{s.a, s.b}, s.h);  // a pair on two ranks: the first
        distribute(all, by_pair, false);
        ++redistributions_;
    }

    /// Everyone's `items` on every rank, in rank order.
    template <class T>
    std::vector<T> gather(const std::vector<T>& items) const {
        int ranks = 0;
        check(MPI_Comm_size(comm_.comm(), &ranks), "MPI_Comm_size");
        const int bytes = static_cast<int>(items.size() * sizeof(T));
        std::vector<int> counts(ranks), offsets(ranks, 0);
        check(MPI_Allgather(&bytes, 1, MPI_INT, counts.data(), 1, MPI_INT, comm_.comm()), "MPI_Allgather (counts)");
        for (int r = 1; r < ranks; ++r) offsets[r] = offsets[r - 1] + counts[r - 1];
        std::vector<T> all((offsets.back() + counts.back()) / sizeof(T));
        check(MPI_Allgatherv(items.data(), bytes, MPI_BYTE, all.data(), counts.data(), offsets.data(), MPI_BYTE, comm_.comm()),
              "MPI_Allgatherv");
        return all;
    }

    /// This rank's engine on the particles of `all` it owns and the ghosts of its new halo, each
    /// pair's spring from `springs` (the others start anew). `first`: the run's start, whose
    /// forces are computed; else mid-step, where the last forces and torques are restored for
    /// the integrator's closing kick and the forces are left to the integrator's evaluation.
    void distribute(const std::vector<State>& all, const std::map<std::pair<Index, Index>, History>& springs, bool first) {
        std::vector<ParticleRecord> owned;
        std::vector<const State*> own_states;
        for (const State& s : all) {
            Vec<dim> x;
            for (int a = 0; a < dim; ++a) x[a] = s.r.x[a];
            if (!comm_.split().owns(x)) continue;
            owned.push_back(s.r);
            own_states.push_back(&s);
        }
        halo_.emplace(comm_, owned, width_);
        local_.emplace(law_, comm_.split().local_domain());
        global_.clear();
        for (const auto* set : std::array<const std::vector<ParticleRecord>*, 2>{&owned, &halo_->ghosts()})
            for (const ParticleRecord& r : *set) {
                Vec<dim> x;
                for (int a = 0; a < dim; ++a) x[a] = r.x[a];
                const std::size_t i = local_->particles().add(x, r.radius, r.mass, r.inertia);
                write_motion(i, r);
                global_.push_back(r.id);
            }
        owned_ = owned.size();
        local_->set_time_step(dt_);
        local_->set_skin(skin_);
        local_->set_auto_sort(false);     // the first owned_ particles stay the owned ones
        local_->set_track_energy(false);  // the books would count the ghosts' contacts too
        local_->prepare();                // the lists (and, at the start, the first forces)
        rebuilds_ = local_->neighbor_rebuilds();
        if (first) return;
        auto& p = local_->particles();
        for (std::size_t i = 0; i < owned_; ++i) {
            for (int a = 0; a < dim; ++a) p.template get<field::Force>()[i][a] = own_states[i]->force[a];
            p.template get<field::Torque>()[i] = angular(own_states[i]->torque);
        }
        local_->visit_pair_histories([&](Index i, Index j, History& h) {
            const Index a = global_id(i), b = global_id(j);
            const auto found = springs.find(a < b ? std::pair{a, b} : std::pair{b, a});
            if (found == springs.end()) h = History{};
            else h = a < b ? found->second : seen_from_partner(found->second);
        });
    }

    CartesianComm<dim> comm_;
    Domain<dim> box_;
    Law law_;
    std::optional<Sim> local_;
    std::optional<Halo<dim>> halo_;
    std::vector<Index> global_;    // by local id (the order added): owned, then ghosts
    std::size_t owned_ = 0, rebuilds_ = 0, redistributions_ = 0;
    double skin_, dt_, width_ = 0.0;
};

}  // namespace micromacro::mpi
