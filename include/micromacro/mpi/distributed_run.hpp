#pragma once
// A scene run over MPI ranks with the serial engine: each rank runs a BasicSimulation in the
// whole box on the particles its subdomain owns followed by the ghosts of its halo, at their
// wrapped positions, so that a pair across a periodic boundary is measured by the minimum image
// and a particle wraps in the step it crosses, as in the serial run (CartesianSplit::
// search_window), and after every particle pass refreshes the ghosts from their owners before
// the forces are computed. One rank runs the serial engine on the serial box. The forces, laws, springs and
// integrator are the serial ones: the integrator policy drives this class through the same
// stages (kick_drift_kick, compute_forces, kick_force_change) it drives the engine through. A
// ghost's own force is incomplete and never used: its state is overwritten at every refresh.
//
// Once a particle has moved half the skin since the last distribution (or a rank's engine has
// rebuilt its lists on its own), every rank redistributes, in the step, between the particle
// pass and the forces: the particles go to the ranks that own their positions now, each with its
// last force and torque (the integrator's closing kick needs them) and each pair's spring with
// it, the halos are built again and each rank's engine is rebuilt on its new particles. Particles
// go to the neighbouring ranks only, axis by axis (as in LAMMPS's Comm::exchange).
//
// The places in the serial numbering follow the serial engine's sorts (mpi/serial_order.hpp), and
// a resumed run takes over the scene's neighbour-list references: the ranks search where it would.
// The slabs' boundaries follow the particles (Split::balanced, mpi/balance.hpp).
//
// Walls: every rank holds every wall, and a particle's wall contacts are its owner's (a ghost
// has none). After each force evaluation the walls' forces are summed over the ranks, on every
// rank in the serial run's order (set_serial_wall_sums), so that the walls move by the same
// numbers everywhere, and by the serial run's; a wall contact's spring travels with its
// particle. Along an axis the scene leaves unbounded (walls alone bound the biaxial test's box)
// the split is the particles' extent, taken again at every redistribution, so that the slabs
// follow a box the walls deform.
//
// Energy books (with the scene's set_track_energy, on by default): each rank's engine books its
// own particles' body forces and wall contacts, half of each pair with a ghost (the ghost's owner
// books the other half) and its share of a driven wall's work; rank 0 books the walls' own terms
// (a stress-controlled wall's pressure work and damper). A rank's books go on in its next engine
// at a redistribution; mpi::open_books (mpi/energy.hpp) adds them over the ranks.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#include <mpi.h>

#include "micromacro/core/dim_traits.hpp"
#include "micromacro/core/domain.hpp"
#include "micromacro/core/energy.hpp"
#include "micromacro/core/error.hpp"
#include "micromacro/engine/simulation.hpp"
#include "micromacro/mpi/balance.hpp"
#include "micromacro/mpi/communicator.hpp"
#include "micromacro/mpi/distributed_walls.hpp"
#include "micromacro/mpi/engine_parts.hpp"
#include "micromacro/mpi/halo.hpp"
#include "micromacro/mpi/migration.hpp"
#include "micromacro/mpi/serial_order.hpp"
#include "micromacro/mpi/springs.hpp"
#include "micromacro/neighbors/skin.hpp"

namespace micromacro::mpi {

template <class Sim>
class DistributedRun {
public:
    static constexpr int dim = Sim::dimension;
    using History = typename Sim::History;
    using Law = std::remove_cvref_t<decltype(std::declval<const Sim&>().law())>;
    using Boundary = std::remove_cvref_t<decltype(std::declval<const Sim&>().walls())>;
    static_assert(Sim::rotation && Law::has_history,
                  "DistributedRun: needs a law with rotation and springs (the records carry angular velocities)");

    /// How a run takes over `whole`: `fresh` computes the first forces, `resume` keeps the forces,
    /// torques and springs of whole's last evaluation (a scene that has run, or one loaded from a
    /// state file, such as one written from whole_scene in mpi/checkpoint.hpp), so that the run
    /// continues as whole would have. A scene whose forces are not its present ones (never
    /// prepared, or its particles, law, time step or skin changed since) is refused: call its
    /// prepare() first.
    enum class Start { fresh, resume };
    /// What each rank passes: `whole`, the whole scene (the same on every rank), of which it keeps
    /// the particles it owns; or `share`, its own share of the particles (any positions: each goes
    /// to the rank that owns it), numbered over the ranks in rank order (rank 0's share first),
    /// with the same law, walls, body forces, time step, skin and clock on every rank, so that no
    /// rank need hold the whole scene. A share starts fresh (its springs are not known across the
    /// shares).
    enum class Input { whole, share };
    /// How the box is cut: `balanced`, each slab's boundaries where it holds an equal share of the
    /// particles, at the start and at every redistribution (mpi/balance.hpp); `equal`, equal
    /// slabs (along an axis walls alone bound, of the particles' extent).
    enum class Split { balanced, equal };

    /// Splits `whole` (the same scene on every rank: particles, law, dt, skin, a box) over the
    /// ranks of `parent`. The skin is the scene's, or the engine's default (a fifth of the mean
    /// radius); the halo is the largest contact distance plus it. The clock starts at whole's.
    DistributedRun(MPI_Comm parent, const Sim& whole, Start start = Start::fresh, Input input = Input::whole,
                   Split split = Split::balanced);

    const CartesianComm<dim>& comm() const { return comm_; }
    /// The whole scene's box.
    const Domain<dim>& box() const { return box_; }
    /// This rank's ghosts, for sending values of its particles to the ranks that see them.
    const Halo<dim>& halo() const { return *halo_; }
    /// The engine of this rank: its particles [0, owned()) are this rank's, the rest ghosts.
    const Sim& local() const { return *local_; }
    std::size_t owned() const { return owned_; }
    /// The neighbour skin every rank's engine runs with (the scene's, or default_skin).
    double skin() const { return skin_; }
    /// The global id of local particle i (the whole scene's particle id).
    Index global_id(std::size_t i) const { return global_[local_->particles().id(i)]; }
    /// The place of local particle i in the serial numbering (the whole scene's index, or the
    /// shares' in rank order).
    Index place(std::size_t i) const { return place_[local_->particles().id(i)]; }
    /// The scene's clock (a rank's engine starts anew at every redistribution).
    double time() const { return time_; }
    std::size_t steps_done() const { return steps_; }
    double time_step() const { return dt_; }
    /// An engine without particles with the scene's law, body forces and walls (as they stand
    /// now), in the whole scene's box: what mpi::whole_scene fills.
    Sim empty_scene() const { return engine(box_, local_->walls()); }
    /// Threads for each rank's engine (BasicSimulation::set_threads): ranks x threads the cores.
    /// With one, each rank sums a particle's forces in the serial run's order (see
    /// serial_pair_order); with more, in the thread shares' order.
    void set_threads(int threads) {
        local_->set_threads(threads), threads_ = threads;
        serial_pair_order();
    }
    /// The contact law from now on, as a serial scene's law() changed between steps (friction
    /// switched on after a preparation): the next step() or run() first evaluates the present
    /// forces again with it (and with the body forces as they are then), as the serial scene's
    /// next step does. The same law on every rank.
    void set_law(const Law& law) {
        law_ = law;
        local_->law() = law;
        law_changed_ = true;
    }
    /// A body force from its next evaluation on, as a serial scene's body_force<F>() = force.
    template <class F>
    void set_body_force(const F& force) {
        std::get<F>(forces_) = force;
        local_->template body_force<F>() = force;
    }
    /// On (the default), the walls' forces are summed in the serial run's order: each wall
    /// contact's part goes to every rank, which adds them in the order of their particles' places
    /// in the serial numbering, so any rank count moves the walls by the serial run's numbers.
    /// Off, each rank's sum is added in rank order: round-off differences, but no message that
    /// grows with the walls' contacts (for large walled scenes on many ranks; docs/mpi.md).
    /// Every rank must make the same call.
    void set_serial_wall_sums(bool on) {
        serial_wall_sums_ = on;
        if constexpr (Sim::has_walls) {
            local_->keep_wall_terms(on);
            wall_sum_.rearrange();  // from the next evaluation's parts
        }
    }
    /// How often the particles were handed to new ranks.
    std::size_t redistributions() const { return redistributions_; }
    /// The serial scene's set_auto_sort, and how often its particles were sorted (the places in
    /// the serial numbering renumbered, counted on from the scene's spatial_sorts()).
    bool auto_sort() const { return order_.on(); }
    std::size_t spatial_sorts() const { return order_.sorts(); }
    /// What this rank's next neighbour search waits on, by owned index, with the serial order's
    /// measure: the particles' part of the serial scene's search_state() (mpi::whole_scene).
    SearchState<dim, typename Sim::Scalar> search_state() const;
    /// This rank's halo traffic per step: bytes and messages it sends to refresh the ghosts.
    std::size_t halo_bytes_per_step() const { return halo_->bytes_per_refresh(); }
    std::size_t halo_messages_per_step() const { return halo_->messages_per_refresh(comm_); }

    void step() {
        evaluate_changed_law();
        typename Sim::IntegratorPolicy{}.step(*this, dt_);
    }
    /// `steps` steps, each closing kick merged into the next step's pass as the engine's run()
    /// does: the same bits as calling step() that often, a pass over the particles less per step.
    void run(std::size_t steps) {
        if (steps == 0) return;
        evaluate_changed_law();
        typename Sim::IntegratorPolicy{}.run(*this, dt_, steps);
    }

    // ---- the stages the integrator policy calls ------------------------------------------------
    void kick_drift_kick(double h_before, double dt, double h_after, double h_closing = 0.0) {
        local_->kick_drift_kick(h_before, dt, h_after, h_closing);
        time_ += dt;
        ++steps_;
        refresh_or_redistribute();
    }
    void compute_forces() {
        local_->compute_forces();
        sum_walls();
    }
    void kick_force_change(double h) {
        local_->kick_force_change(h);
        ghosts_current_ = false;
    }

    /// The ghosts from their owners' present state. After a step the ghosts' velocities miss the
    /// step's closing kick (the next step's particle pass refreshes them before any force is
    /// computed); what reads the ghosts between steps, such as the averages, calls this first.
    /// A collective call: every rank must make it.
    void refresh_ghosts() {
        if (ghosts_current_) return;
        refresh_halo();
    }

private:
    /// A particle with what its new rank needs mid-step: its state and its last force and torque.
    struct State {
        ParticleRecord r;
        std::array<double, 3> force, torque;
    };
    /// A spring on its way with one of its particles, `carrier`: a pair's (by global ids), or a
    /// wall contact's (a: the particle's global id, b: the wall).
    struct CarriedSpring {
        Index carrier;
        bool wall;
        PairSpring<History> pair;
    };
    /// How distribute() starts a rank's engine: at the run's start (fresh or resumed) or within
    /// a step.
    enum class Stage { fresh, resume, within_step };

    /// An engine without particles with the scene's law and body forces, in `domain`, with `walls`.
    Sim engine(const Domain<dim>& domain, const Boundary& walls) const {
        return std::apply([&](const auto&... forces) {
            return Sim(law_, domain, walls, typename Sim::IntegratorPolicy{}, typename detail::EngineParts<Sim>::NeighborSearch{},
                       forces...);
        }, forces_);
    }

    void write_motion(std::size_t i, const Motion<dim>& m) {
        auto& p = local_->particles();
        for (int a = 0; a < dim; ++a) {
            p.position()[i][a] = m.x[a];
            p.velocity()[i][a] = m.v[a];
        }
        p.template get<field::AngularVelocity>()[i] = m.angular();
    }

    /// After set_law: the serial scene's next step prepares again, a neighbour search (which may
    /// sort) and the present forces evaluated anew. So the ranks hand out their particles as at a
    /// search, then every rank's engine evaluates again (its prepare(), at the same positions).
    void evaluate_changed_law() {
        if (!law_changed_) return;
        law_changed_ = false;
        redistribute();
        local_->prepare();
        rebuilds_ = local_->neighbor_rebuilds();
        rearrange_walls();
        sum_walls();
    }

    /// After a particle pass: the ghosts from their owners' present state, or, once a particle
    /// has moved half the skin or an engine has rebuilt its lists from ghosts it integrated
    /// itself, a redistribution. Decided over every rank at once.
    void refresh_or_redistribute() {
        // The engine's own largest move since the distribution (its last rebuild): its ghosts'
        // are one step's integration off, but each ghost's owner counts it exactly.
        const double here[2] = {local_->largest_move(), local_->neighbor_rebuilds() != rebuilds_ ? 1.0 : 0.0};
        double everywhere[2] = {0.0, 0.0};
        check(MPI_Allreduce(here, everywhere, 2, MPI_DOUBLE, MPI_MAX, comm_.comm()), "MPI_Allreduce (largest move)");
        if (2.0 * everywhere[0] >= skin_ || everywhere[1] > 0.0) {
            redistribute();
            return;
        }
        refresh_halo();
    }

    /// Straight from the owners' engine arrays into the ghosts' (the halo's own records stay
    /// as at its build).
    void refresh_halo() {
        auto& p = local_->particles();
        halo_->refresh(comm_, [&](std::size_t k) { return motion_of(p, k); },
                       [&](std::size_t g, const Motion<dim>& m) { write_motion(owned_ + g, m); });
        ghosts_current_ = true;
    }

    /// The particles that left this rank's subdomain go to the ranks that own their positions
    /// now (position wrapped into the box, last force and torque), each with the springs of its
    /// pairs, axis by axis to the neighbouring ranks (a particle moves less than a slab between
    /// two distributions, at most one slab along each axis); the others stay, with their springs.
    /// Then halos and the engine are built afresh.
    void redistribute();

    /// This rank's engine on the particles of `all` it owns and the ghosts of its new halo, with
    /// the walls of walls_, each pair's spring from `springs` and each wall contact's from
    /// `wall_springs` by (global id, wall) (the others start anew). At a fresh start the forces
    /// are computed; else the last forces and torques are restored (for the integrator's closing
    /// kick within a step) and so are the walls' forces.
    void distribute(const std::vector<State>& all, const SpringsByPair<History>& springs, const SpringsByPair<History>& wall_springs,
                    Stage stage);
    /// This rank's halo and engine on `own_states`, its particles, at `places` in the serial
    /// numbering (by own_states, which it puts in their order), their lists built.
    void build(std::vector<const State*>& own_states, const std::vector<Index>& places);
    /// At a resumed start: the scene's neighbour-list references for this rank's engine.
    void take_start_search();
    /// The start's boundaries (Split::balanced) from the particles of `all` (a share's: added
    /// over the ranks).
    void balance_start(const std::vector<State>& all, bool share);

    /// After the engine's prepare(), which builds its lists: the walls' serial sums are arranged
    /// anew at the next sum.
    void rearrange_walls() {
        if constexpr (Sim::has_walls) wall_sum_.rearrange();
    }
    /// The walls' forces summed over the ranks as set_serial_wall_sums says. A collective call.
    void sum_walls() {
        if constexpr (Sim::has_walls) {
            if (serial_wall_sums_)
                wall_sum_.sum(local_->walls(), local_->wall_terms(), place_, comm_);
            else
                sum_wall_forces(local_->walls(), comm_);
        }
    }

    /// On one thread, the engine's pairs in the order of their particles' places in the serial
    /// numbering (the whole scene's, or the shares' in rank order): each particle's forces are
    /// then summed as in the serial run, whatever the split (BasicSimulation::set_pair_order).
    void serial_pair_order() {
        local_->set_pair_order(threads_ == 1 ? std::vector<std::uint64_t>(place_.begin(), place_.end()) : std::vector<std::uint64_t>{});
    }

    CartesianComm<dim> comm_;
    Domain<dim> box_;
    Law law_;
    Boundary walls_;  // every wall as of the last distribution (force: the sum over the ranks)
    typename detail::EngineParts<Sim>::Forces forces_;
    std::array<bool, dim> follows_;  // the axes whose split follows the particles' extent
    std::optional<Sim> local_;
    std::optional<Halo<dim>> halo_;
    std::vector<Index> global_;    // by local id (the order added): owned, then ghosts
    std::vector<Index> place_;     // by local id: the place in the serial numbering
    std::size_t owned_ = 0, rebuilds_ = 0, redistributions_ = 0;
    int threads_ = 1;
    bool ghosts_current_ = true;  // false from a closing kick to the next refresh
    bool law_changed_ = false;    // set_law since the last step
    bool serial_wall_sums_ = true;
    [[no_unique_address]] std::conditional_t<Sim::has_walls, SerialWallSum<dim>, std::tuple<>> wall_sum_;
    SerialOrder order_;
    std::optional<SearchState<dim, typename Sim::Scalar>> start_search_;  // a resumed scene's, by global id, until used
    double skin_, dt_, width_ = 0.0, time_;
    std::size_t steps_;
    bool track_;                               // energy books, as the scene's
    bool balance_;                             // Split::balanced
    std::optional<OpenBooks> books_at_start_;  // a scene's that has run (rank 0's; the others' zero)
};

}  // namespace micromacro::mpi

// The members defined apart: the hand-over of particles between ranks.
#include "micromacro/mpi/distribution.hpp"
