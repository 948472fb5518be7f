#pragma once
// The simulation: particles, walls and body forces advanced by an integrator, with contacts
// found by a neighbour-search policy and resolved by a contact law. This file holds the class,
// its set-up and its run loop; its other members are defined by job in the simulation_*.hpp
// files included at the end. All pair physics runs through detail::respond(), from the one pair
// loop and the one wall loop. What a scene does not use is not compiled in: without a
// tangential law there is no history and no rotation; with `NoWalls` there is no wall code.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#include "micromacro/contact/collision.hpp"
#include "micromacro/contact/contact_law.hpp"
#include "micromacro/contact/contact_list.hpp"
#include "micromacro/contact/geometry.hpp"
#include "micromacro/core/domain.hpp"
#include "micromacro/core/energy.hpp"
#include "micromacro/core/error.hpp"
#include "micromacro/core/inline.hpp"
#include "micromacro/core/parallel.hpp"
#include "micromacro/engine/contact_analysis.hpp"
#include "micromacro/engine/contact_response.hpp"
#include "micromacro/engine/contact_view.hpp"
#include "micromacro/engine/pair_loop.hpp"
#include "micromacro/engine/particle_pass.hpp"
#include "micromacro/engine/policy_checks.hpp"
#include "micromacro/engine/spring_adjustments.hpp"
#include "micromacro/engine/stability.hpp"
#include "micromacro/engine/thread_shares.hpp"
#include "micromacro/engine/wall_contacts.hpp"
#include "micromacro/engine/wall_work.hpp"
#include "micromacro/integrators/integrators.hpp"
#include "micromacro/neighbors/linked_cells.hpp"
#include "micromacro/neighbors/search_window.hpp"
#include "micromacro/neighbors/search_state.hpp"
#include "micromacro/particles/particles.hpp"
#include "micromacro/walls/walls.hpp"

namespace micromacro {

/// The engine. `Real` is the storage precision of the particle state (positions, velocities,
/// radii, masses): every force and update is computed in double, and with float each stored value
/// is rounded to float, which halves the state's memory but resolves positions only to ~6e-8 of
/// their magnitude (prepare() checks that against the radii). Force and torque sums, contact
/// springs, walls and energies stay double. `Simulation` is the double engine.
template <int dim, class Real, class Law, class Boundary = NoWalls, class Integrator = VelocityVerlet,
          class Neighbors = LinkedCells, class... BodyForces>
class BasicSimulation {
    static_assert(detail::check_policies<dim, Real, Law, Integrator, Neighbors, BodyForces...>());

public:
    static constexpr int dimension = dim;
    static constexpr bool rotation = Law::needs_rotation;
    static constexpr bool has_tangential = Law::has_tangential;
    static constexpr bool has_walls = !std::is_same_v<Boundary, NoWalls>;
    using Scalar = Real;
    using V = Vec<dim>;             // arithmetic: double
    using A = Angular<dim>;
    using SV = Vec<dim, Real>;      // storage
    using SA = Angular<dim, Real>;
    using T = DimTraits<dim>;
    using ParticleSet = Particles<dim, rotation, Real>;
    using History = typename Law::template History<dim>;
    using IntegratorPolicy = Integrator;

    explicit BasicSimulation(Law law, Domain<dim> domain = {}, Boundary walls = {}, Integrator integrator = {},
                             Neighbors neighbors = {}, BodyForces... forces)
        : law_(law), domain_(domain), walls_(std::move(walls)), integrator_(integrator),
          neighbors_(std::move(neighbors)), body_forces_(forces...) {}

    // ---- set-up ------------------------------------------------------------------------------
    ParticleSet& particles() { return particles_; }
    const ParticleSet& particles() const { return particles_; }
    Boundary& walls() { return walls_; }
    const Boundary& walls() const { return walls_; }
    const Domain<dim>& domain() const { return domain_; }
    /// The periodic cell's velocity gradient (Domain::set_velocity_gradient): from the next step
    /// the cell deforms with it, its images moving with their shifts (an element test's drive).
    void set_velocity_gradient(const Eigen::Matrix<double, dim, dim>& L) { check_cell_motion(!L.isZero(0.0), domain_.tilted()), domain_.set_velocity_gradient(L); }
    const Law& law() const { return law_; }
    /// The contact law may be changed between steps (e.g. friction switched on after a
    /// frictionless preparation); the stability limit is checked again at the next prepare().
    Law& law() {
        prepared_ = false;
        return law_;
    }
    template <class F> F& body_force() { return std::get<F>(body_forces_); }
    template <class F> const F& body_force() const { return std::get<F>(body_forces_); }

    void set_time_step(double dt) {
        detail::require_positive(dt, "time step dt", "choose dt = t_c / 50 (see contact_duration)");
        dt_ = dt, prepared_ = false;
    }
    double time_step() const { return dt_; }
    /// Skin of the neighbour list: pairs closer than this (surface to surface) are candidates.
    void set_skin(double skin) {
        detail::require_positive(skin, "neighbour skin", "the default is a fifth of the mean radius");
        skin_ = skin, prepared_ = false;
    }
    double skin() const { return skin_; }
    /// Lets prepare() accept dt above the stability limit (a blow-up is reported, not refused).
    void allow_unstable_time_step(bool allow) { allow_unstable_ = allow; }
    void set_track_energy(bool on) { track_energy_ = on; }  // a few flops per contact; on by default
    bool track_energy() const { return track_energy_; }
    /// Lets prepare() accept positions coarser than 1e-6 of the smallest radius (float storage).
    void allow_coarse_positions(bool allow) { allow_coarse_positions_ = allow, prepared_ = false; }

    /// Threads for the pair loop and the particle passes (OpenMP): equal contiguous shares of the
    /// candidates, each thread's forces summed in thread order, so a fixed thread count gives the
    /// same bits every run and another count differs by round-off only.
    void set_threads(int threads);
    int threads() const { return threads_; }
    /// Threads actually used: a scene with fewer than 2000 particles per thread runs serially
    /// (starting a team costs microseconds; a fixed count still gives the same bits).
    int active_threads() const {
        return particles_.size() >= 2000 * static_cast<std::size_t>(threads_) ? threads_ : 1;
    }

    /// The largest stable time step of the scene's stiffest two-body oscillation: the normal
    /// spring between the two lightest particles, with friction the tangential spring (its contact
    /// point moved by translation and, where particles turn, rotation), and a stress-controlled wall
    /// on one particle (Eq. 22's oscillator, limits from the integrators), each damped also by the
    /// body forces' drag, which alone overshoots beyond dt = m / gamma_b. Many contacts on one
    /// particle stiffen it further: necessary, not sufficient. stability_limit() names the cause.
    StabilityLimit stability_limit() const;
    double stable_time_step() const { return stability_limit().seconds; }

    /// Checks the scene, builds the neighbour lists and computes the forces. Called by the first
    /// step() and again after set_time_step(), set_skin() or adding particles; call it yourself to
    /// see errors before running. The energy books open at the first call and are kept after.
    void prepare();

    /// Renumbers the particles in row order (see spatial_order) so that particles close in space
    /// are close in memory and the pair loop reuses the cache lines it loads. Every per-particle
    /// array (the ids too), the contact lists with their histories and the neighbour-list
    /// references follow, so the physics is unchanged; later steps differ by round-off only
    /// (forces are summed in another order). Returns the permutation: the particle now at index k
    /// was particle order[k]. The engine calls it on its own (see set_auto_sort).
    std::vector<Index> sort_spatially(double cell = 0.0);
    /// Renumbers the particles in the caller's order: the particle now at index k was particle
    /// order[k] (a permutation of 0..n-1); everything follows as in sort_spatially.
    void renumber(const std::vector<Index>& order);

    /// Scenes of this many particles or more are sorted by the engine; smaller ones keep the
    /// caller's numbers, which they are usually inspected by (the costs: docs/performance.md).
    static constexpr std::size_t auto_sort_min_particles = 2048;
    /// On (the default), the engine sorts the particles spatially at its first neighbour search and
    /// when the candidate pairs' mean index distance has doubled since (as LAMMPS sorts its atoms).
    /// Indices then change under the caller's feet; a particle's id (Particles::id) does not.
    void set_auto_sort(bool on) { auto_sort_ = on; }
    bool auto_sort() const { return auto_sort_; }
    /// How often the particles were sorted, by sort_spatially or on the engine's own.
    std::size_t spatial_sorts() const { return sorts_; }
    /// What the next neighbour search waits on and decides by (neighbors/search_state.hpp).
    SearchState<dim, Real> search_state() const { return {reference_, wall_reference_, sorted_gap_}; }
    void restore_search_state(SearchState<dim, Real> state);
    /// Particles from index `first` on are ghosts, copies of particles another process computes
    /// (mpi::DistributedRun): the lists leave out pairs of two ghosts and a ghost's wall contacts,
    /// the body forces act on the own particles only, and the books count half of each pair with a
    /// ghost. `counts_walls`: whether the walls' own energy and books are this process's to count.
    void set_first_ghost(std::size_t first, bool counts_walls = true) { first_ghost_ = first, counts_walls_ = counts_walls; }
    /// The neighbour search bins positions in `window` along the periodic axes it unwraps
    /// (neighbors/search_window.hpp; mpi::DistributedRun, whose ranks hold slabs of the box).
    void set_search_window(const SearchWindow<dim>& window) { window_ = window; }
    /// The candidate pairs in the order of `key` (distinct, one per particle), not of the indices:
    /// each pair's i has the smaller key, the pairs go by i's key, then j's, and each particle's
    /// forces are summed as with the particles numbered in key order (how mpi::DistributedRun's
    /// ranks sum in the serial order). On one thread then. Empty (default): index order. Not saved.
    void set_pair_order(std::vector<std::uint64_t> key);
    /// Whether each force evaluation keeps every wall candidate's part of its wall's force in
    /// wall_terms (mpi::DistributedRun adds the ranks' in the serial order). Default: off.
    void keep_wall_terms(bool on) requires has_walls { keeps_wall_terms_ = on; }
    const std::vector<detail::WallTerm<dim>>& wall_terms() const requires has_walls { return wall_terms_; }

    /// The spacing of representable coordinates at the farthest particle or wall from the origin
    /// (one unit in the last place): overlaps are differences of coordinates, so this is the
    /// absolute error of every overlap. Relative to an overlap delta the force error is about
    /// position_resolution() / delta (2e-6 for overlaps of 1e-7 m at 1e3 m from the origin in
    /// double precision, 2e-2 at 0.02 m in float; tests/physics/extremes.cpp and precision.cpp
    /// measure it).
    double position_resolution() const;

    // ---- running -----------------------------------------------------------------------------
    void step() {
        if (!prepared_ || reference_.size() != particles_.size()) prepare();
        integrator_.step(*this, dt_);
    }
    /// Runs `steps` steps: the same bits as calling step() that often, with fewer passes over
    /// the particles where the integrator can merge one step's last stage into the next's first.
    void run(std::size_t steps) {
        if (steps == 0) return;
        if (!prepared_ || reference_.size() != particles_.size()) prepare();
        integrator_.run(*this, dt_, steps);
    }
    /// Runs `steps` steps and calls observer(*this) after each.
    template <class Observer>
    void run(std::size_t steps, Observer&& observer) {
        for (std::size_t s = 0; s < steps; ++s) {
            step();
            observer(std::as_const(*this));
        }
    }
    double time() const { return time_; }
    std::size_t steps_done() const { return steps_; }
    /// Whether the forces are those of the present scene (prepare() ran since the last change).
    bool prepared() const { return prepared_ && reference_.size() == particles_.size(); }
    void set_clock(double time, std::size_t steps) { time_ = time, steps_ = steps; }  // mpi::whole_scene's
    std::size_t neighbor_rebuilds() const { return rebuilds_; }
    /// The largest displacement of a particle from where the last rebuild found it, after the last pass.
    double largest_move() const { return last_move_; }

    // ---- integrator stages -------------------------------------------------------------------
    /// Kick by h_before, drift by dt, kick by h_after (either kick may be zero), in one pass over
    /// the particles: the same arithmetic as three passes, with a third of the memory traffic,
    /// which is what limits large packings. With h_closing != 0 the pass first completes the
    /// previous step by kick_force_change(h_closing) (run() merges the two stages this way).
    /// The pass also clears the array the next compute_forces() accumulates into, once its
    /// values are dead. Walls move, time advances, lists refresh as needed.
    void kick_drift_kick(double h_before, double dt, double h_after, double h_closing = 0.0);

    void kick_force_change(double h);

    void compute_forces();

    // ---- state and analysis ------------------------------------------------------------------
    const EnergyBooks& books() const { return books_; }
    /// The books as the next evaluation continues them, and an engine taking them over (OpenBooks).
    OpenBooks open_books() const { return {books_, previous_step_books_, wall_books_, initial_energy_}; }
    void continue_books(OpenBooks b) {
        books_ = b.books, previous_step_books_ = b.last_evaluation, wall_books_ = std::move(b.walls), initial_energy_ = b.initial_energy;
    }
    double initial_energy() const { return initial_energy_; }
    /// The stored energies (with ghosts: the own particles', half of each contact with a ghost).
    EnergyState energy() const;

    /// kinetic + potential + dissipated - work_in - initial, relative to the initial energy
    /// (or to the work put in, if that is larger). Needs energy tracking.
    double energy_residual() const;

    /// Elastic energy per particle: each spring's energy split half and half between the two
    /// partners; a wall gives its share to the particle.
    std::vector<double> potential_energy_per_particle() const;

    /// Calls f(ContactView) for every contact with positive overlap, particle pairs first, then
    /// wall contacts. Forces are those of the present state (see CundallStrack::current_force).
    template <class F>
    void for_each_contact(F&& f) const {
        const auto [walls, wall_contacts] = wall_parts();
        detail::visit_contacts<rotation>(particle_input(), domain_, law_, pairs_, walls, wall_contacts, f);
    }
    /// Calls f(i, j, history) for every candidate pair (i before j: set_pair_order) and f(i, wall, history)
    /// for every candidate wall contact, the history as the last evaluation left it and open to
    /// change: how a distributed run hands springs between ranks.
    template <class F> void visit_pair_histories(F&& f) requires Law::has_history { pairs_.visit(f); }
    template <class F> void visit_pair_histories(F&& f) const requires Law::has_history { pairs_.visit(f); }
    template <class F> void visit_wall_histories(F&& f) requires(Law::has_history && has_walls) { wall_contacts_.visit(f); }
    template <class F> void visit_wall_histories(F&& f) const requires(Law::has_history && has_walls) { wall_contacts_.visit(f); }

    /// Deforms the scene affinely, x -> F x: particle positions, walls (planes map to planes), a
    /// periodic box (Domain::deformed), and every tangential spring, which takes up the tangential
    /// part of its contact's branch change as if the partners had moved there. Velocities are
    /// kept. A periodic axis left shorter than two interaction ranges is refused.
    void deform_affinely(const Eigen::Matrix<double, dim, dim>& F);

    /// Visits the complete state (particles, contacts with their springs, walls, box, law, body
    /// forces, neighbour-list references, the previous forces, energy books, clocks), so that a
    /// restored simulation continues bit for bit. See io/state.hpp for files.
    template <class Archive>
    void serialize(Archive& ar);

    /// Refuses a restored state (from `source`, a file name for the message) whose parts do not hold
    /// together: arrays of other lengths than the particle count, pairs naming particles or walls
    /// that do not exist, positions, velocities, radii, masses or clocks that are not finite or not
    /// positive where they must be. io::load_state calls it; a damaged file must never run.
    void check_restored(const std::string& source) const;

    /// Bytes the simulation holds in its arrays (particles, contacts with history, neighbour-list
    /// references, previous forces), capacities counted: the engine's own memory footprint.
    std::size_t storage_bytes() const;

    std::size_t contact_count() const;

private:
    // All pair forces, on threads_ threads (see engine/thread_shares.hpp).
    template <bool track>
    void pair_forces();

    template <bool track>
    void compute_forces_impl();

    // What every body force gets at an evaluation: dt, the scene's mean flow (the walls' affine
    // field, or the periodic cell's), the count of the engine's own particles.
    BodyForceStep<dim> body_force_step() const;

    // Re-evaluates the forces of a state the books have not seen move (a re-prepare, an imposed
    // deformation): it adds nothing to the books, it only restarts the trapezoid.
    void compute_forces_without_books();

    // Before the same instant is evaluated again: every spring back to where the last evaluation
    // found it (see CundallStrack::step_back), so the new evaluation does not advance it twice.
    void step_back_springs();

    // What an evaluation's forces dissipate, rate x dt, is booked half now and half at the next
    // evaluation: with velocity Verlet a force acts from half a step before its evaluation to
    // half a step after, so the trapezoid keeps the books second order and level with the state.
    void close_step_books();

    // The walls and their contact list, both null in a scene without walls (typed as plane walls
    // then, which the wall passes never reach).
    using WallSet = std::conditional_t<has_walls, Boundary, Walls<dim>>;
    std::pair<const WallSet*, const ContactList<History>*> wall_parts() const {
        if constexpr (has_walls) return {&walls_, &wall_contacts_};
        else return {nullptr, nullptr};
    }
    std::pair<const WallSet*, ContactList<History>*> wall_parts() {
        if constexpr (has_walls) return {&walls_, &wall_contacts_};
        else return {nullptr, nullptr};
    }

    // The arrays the pair and wall loops read: the particles' (particle_input) and a contact list's.
    detail::ContactLoopInput<dim, Real, History> particle_input() const;
    detail::ContactLoopInput<dim, Real, History> contact_input(ContactList<History>& list);
    // The order of the candidate pairs (set_pair_order).
    PairOrder pair_order() const { return {pair_key_.empty() ? nullptr : &pair_key_}; }

    template <class F>
    double gravitational_energy(const F& force) const;
    std::pair<double, double> drag_rates(std::size_t i) const;  // the body forces' on particle i: of v and of omega (1/s)
    // The particles this process computes: all but the ghosts (set_first_ghost).
    std::size_t owned_count() const { return std::min(first_ghost_, particles_.size()); }

    // The particle arrays the passes of engine/particle_pass.hpp work on.
    detail::ParticleArrays<dim, Real> particle_arrays();

    void rebuild_neighbors();
    // The moving cell over a step of dt; returns how far its images can have moved since the last search.
    double advance_cell(double dt);

    [[noreturn]] void report_blow_up() const;

    void check_position_resolution() const;  // see micromacro::check_position_resolution (engine/stability.hpp)
    void check_cell_motion(bool moving, bool tilted) const;  // a moving cell drives a scene without walls, not distributed

    Law law_;
    Domain<dim> domain_;
    Boundary walls_;
    Integrator integrator_;
    Neighbors neighbors_;
    std::tuple<BodyForces...> body_forces_;
    ParticleSet particles_;
    ContactList<History> pairs_;
    [[no_unique_address]] std::conditional_t<has_walls, ContactList<History>, NoHistory> wall_contacts_;
    [[no_unique_address]] std::conditional_t<has_walls, std::vector<detail::WallTerm<dim>>, NoHistory> wall_terms_;
    std::vector<SV> reference_;
    Eigen::Matrix<double, dim, dim> lattice_reference_ = Eigen::Matrix<double, dim, dim>::Zero();  // the cell at the last search
    int threads_ = 1;
    detail::ThreadedPairLoop<dim, Real, rotation> pair_loop_;
    // Forces of the previous evaluation, for integrators that correct with the force change.
    [[no_unique_address]] std::conditional_t<Integrator::keeps_previous_forces, std::vector<Vec<dim>>, NoHistory> previous_force_;
    [[no_unique_address]] std::conditional_t<Integrator::keeps_previous_forces && rotation, std::vector<Angular<dim>>, NoHistory>
        previous_torque_;
    std::vector<double> wall_reference_;
    EnergyBooks books_, step_books_, previous_step_books_;
    std::vector<detail::WallBook> wall_books_;  // the walls as the books saw them at the last evaluation
    double initial_energy_ = 0.0;
    double dt_ = 0.0, skin_ = 0.0, time_ = 0.0, last_move_ = 0.0, interaction_range_ = 0.0;
    double evaluated_dt_ = 0.0;  // the step of the last force evaluation, which advanced the springs
    std::size_t steps_ = 0, rebuilds_ = 0, sorts_ = 0;
    double sorted_gap_ = 0.0;  // SearchState::sorted_gap
    bool auto_sort_ = true;
    std::size_t first_ghost_ = std::numeric_limits<std::size_t>::max();
    bool counts_walls_ = true, keeps_wall_terms_ = false;
    SearchWindow<dim> window_;
    std::vector<std::uint64_t> pair_key_;  // set_pair_order's keys by particle index; empty: index order
    std::vector<SV> window_x_;  // the positions as the search sees them, where window_ unwraps an axis
    bool prepared_ = false, allow_unstable_ = false, track_energy_ = true, allow_coarse_positions_ = false;
    bool accumulators_cleared_ = false;  // the force (and torque) arrays are zero and sized: see kick_drift_kick
};

/// The engine in double precision (the usual choice; see BasicSimulation for float storage).
template <int dim, class Law, class Boundary = NoWalls, class Integrator = VelocityVerlet, class Neighbors = LinkedCells,
          class... BodyForces>
using Simulation = BasicSimulation<dim, double, Law, Boundary, Integrator, Neighbors, BodyForces...>;

}  // namespace micromacro

// The members defined apart, by job.
#include "micromacro/engine/simulation_analysis.hpp"
#include "micromacro/engine/simulation_forces.hpp"
#include "micromacro/engine/simulation_preparation.hpp"
#include "micromacro/engine/simulation_stages.hpp"
#include "micromacro/engine/simulation_state.hpp"
