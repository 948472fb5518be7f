#pragma once
// The simulation: particles, walls and body forces advanced by an integrator, with contacts
// found by a neighbour-search policy and resolved by a contact law.
//
// All pair physics runs through one place, `respond()`, called from the one pair loop and the
// one wall loop of `compute_forces()`. What a scene does not use is not compiled in: without a
// tangential law there is no history and no rotation; with `NoWalls` there is no wall code.
#include <algorithm>
#include <array>
#include <cstdint>
#include <cmath>
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
#include "micromacro/engine/spring_adjustments.hpp"
#include "micromacro/engine/stability.hpp"
#include "micromacro/engine/thread_shares.hpp"
#include "micromacro/engine/wall_contacts.hpp"
#include "micromacro/engine/wall_work.hpp"
#include "micromacro/integrators/integrators.hpp"
#include "micromacro/neighbors/linked_cells.hpp"
#include "micromacro/neighbors/spatial_order.hpp"
#include "micromacro/particles/particles.hpp"
#include "micromacro/walls/walls.hpp"

namespace micromacro {

/// The engine. `Real` is the storage precision of the particle state (positions, velocities,
/// forces, radii, masses): every force and update is computed in double, and with float each
/// stored value is rounded to float, which halves the particles' memory and its traffic but
/// resolves positions only to ~6e-8 of their magnitude (prepare() checks that against the
/// radii). Contact springs, walls and energies stay double. `Simulation` is the double engine.
template <int dim, class Real, class Law, class Boundary = NoWalls, class Integrator = VelocityVerlet,
          class Neighbors = LinkedCells, class... BodyForces>
    requires SupportedDimension<dim> && (std::is_same_v<Real, double> || std::is_same_v<Real, float>)
class BasicSimulation {
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
    const Law& law() const { return law_; }
    /// The contact law may be changed between steps (e.g. friction switched on after a
    /// frictionless preparation); the stability limit is checked again at the next prepare().
    Law& law() {
        prepared_ = false;
        return law_;
    }
    template <class F>
    F& body_force() { return std::get<F>(body_forces_); }
    template <class F>
    const F& body_force() const { return std::get<F>(body_forces_); }

    void set_time_step(double dt) {
        detail::require_positive(dt, "time step dt", "choose dt = t_c / 50 (see contact_duration)");
        dt_ = dt;
        prepared_ = false;
    }
    double time_step() const { return dt_; }
    /// Skin of the neighbour list: pairs closer than this (surface to surface) are candidates.
    void set_skin(double skin) {
        detail::require_positive(skin, "neighbour skin", "the default is a fifth of the mean radius");
        skin_ = skin;
        prepared_ = false;
    }
    double skin() const { return skin_; }
    /// Lets prepare() accept a time step above the stability limit (a blow-up is then detected
    /// and reported instead of refused up front).
    void allow_unstable_time_step(bool allow) { allow_unstable_ = allow; }
    /// Energy tracking costs a few flops per contact; on by default.
    void set_track_energy(bool on) { track_energy_ = on; }
    /// Lets prepare() accept positions stored more coarsely than 1e-6 of the smallest radius
    /// (see position_resolution(); float storage usually needs this).
    void allow_coarse_positions(bool allow) {
        allow_coarse_positions_ = allow;
        prepared_ = false;
    }

    /// Threads for the pair loop and the particle passes (OpenMP; compile with -fopenmp). The
    /// candidates are split into equal contiguous shares, each thread adds its forces into its
    /// own array and the arrays are summed in thread order: a fixed thread count gives the same
    /// bits every run, another count differs by round-off only.
    void set_threads(int threads) {
#ifdef _OPENMP
        if (threads < 1 || threads > omp_get_max_threads() * 4)
            detail::throw_input_error("threads = ", threads, " is outside 1..", omp_get_max_threads() * 4,
                                      "; use up to the number of cores (", omp_get_num_procs(), " here)");
#else
        if (threads != 1)
            detail::throw_input_error("threads = ", threads, " needs OpenMP, but this program was compiled without "
                                      "it; compile with -fopenmp (CMake: link OpenMP::OpenMP_CXX) or use 1 thread");
#endif
        threads_ = threads;
    }
    int threads() const { return threads_; }
    /// Threads actually used: starting a team costs microseconds, so a scene with fewer than
    /// 2000 particles per thread runs serially (the choice depends only on N and the count, so
    /// a fixed count still gives the same bits).
    int active_threads() const {
        return particles_.size() >= 2000 * static_cast<std::size_t>(threads_) ? threads_ : 1;
    }

    /// The largest stable time step of the scene's stiffest two-body oscillation: the normal
    /// spring between the two lightest particles, with friction the tangential spring (its
    /// contact point moved by translation and, where particles turn, rotation), and a
    /// stress-controlled wall on one particle (Eq. 22's oscillator, limits from the integrators).
    /// Many contacts on one particle stiffen it further: this bound is necessary, not sufficient.
    /// Below it an undamped tangential spring (gamma_t = 0) still grows, by about (omega_t dt)^3
    /// per period (1e-4 at the paper's omega_t dt = 0.05, 1e-3 at 0.1): a little damping absorbs it.
    double stable_time_step() const {
        if (particles_.empty()) return std::numeric_limits<double>::infinity();
        const double inv_max = particles_.largest_inverse_mass();
        bool any_wall = false;
        if constexpr (has_walls) any_wall = walls_.size() > 0;
        if (particles_.size() < 2 && !any_wall) return std::numeric_limits<double>::infinity();  // nothing to touch
        const double partners = particles_.size() > 1 ? 2.0 : 1.0;  // another particle, or a wall
        double limit = normal_time_step_limit<Integrator>(law_.normal, partners * inv_max);
        if constexpr (has_tangential)
            limit = std::min(limit, tangential_time_step_limit<Integrator>(law_.tangential,
                                                                           partners * particles_.largest_contact_point_mobility()));
        if constexpr (has_walls)  // a stress-controlled wall on one contact
            for (const auto& w : walls_)
                if (const auto* s = std::get_if<StressControlled>(&w.motion))
                    limit = std::min(limit, stress_wall_time_step_limit(law_.normal, s->mass, s->damping, inv_max));
        return limit;
    }

    /// Checks the scene, builds the neighbour lists and computes the forces. Called by the first
    /// step() and again after set_time_step(), set_skin() or adding particles; call it yourself to
    /// see errors before running. The energy books open at the first call and are kept after.
    void prepare() {
        if (!(dt_ > 0.0))
            detail::throw_input_error("no time step set; call set_time_step(dt), e.g. dt = t_c / 50");
        const std::size_t n = particles_.size();
        if (n > std::numeric_limits<Index>::max() - 1)
            detail::throw_input_error("too many particles: ", n);
        const auto& r = particles_.radius();
        if (!(skin_ > 0.0)) {
            double mean = 0.0;
            for (double a : r) mean += a;  // in double whatever the storage
            skin_ = n ? 0.2 * mean / n : 1.0;
        }
        if (n) domain_.check_interaction_range(2.0 * double(*std::max_element(r.begin(), r.end())) + skin_);
        check_position_resolution();
        const double limit = stable_time_step();
        if (dt_ > limit && !allow_unstable_)
            detail::throw_input_error("time step dt = ", dt_, " s exceeds the stability limit ", limit,
                                      " s of the stiffest contact (lightest particles); use dt <= ", limit,
                                      " (the paper uses t_c/50), or allow_unstable_time_step(true) to run anyway");
        for (auto& x : particles_.position()) {
            V wrapped = convert<double>(x);
            domain_.wrap(wrapped);
            x = convert<Real>(wrapped);
        }
        if constexpr (has_walls) {
            for (std::size_t w = 0; w < walls_.size(); ++w) {
                for (int k = 0; k < dim; ++k)
                    if (domain_.periodic(k) && walls_[w].normal[k] != 0.0)
                        detail::throw_input_error("wall ", w, " is not parallel to periodic axis ", k,
                                                  "; walls may only bound non-periodic axes");
                for (std::size_t i = 0; i < n; ++i)
                    if (!(walls_[w].distance(convert<double>(particles_.position()[i])) > 0.0))
                        detail::throw_input_error("particle ", i, " starts outside wall ", w, " (its centre is ",
                                                  -walls_[w].distance(convert<double>(particles_.position()[i])),
                                                  " m behind the plane); move it inside or move the wall");
            }
        }
        rebuild_neighbors();
        if (steps_ == 0) {
            step_back_springs();  // prepare() called again before the first step
            compute_forces();
            initial_energy_ = track_energy_ ? energy().total() : 0.0;
            books_ = {};  // the first evaluation only opens the books
        } else {
            compute_forces_without_books();
        }
        prepared_ = true;
    }

    /// Renumbers the particles in row order (see spatial_order) so that particles
    /// close in space are close in memory and the pair loop reuses the cache lines it loads:
    /// worth doing once after placing particles at random, and now and then in long flows.
    /// Every per-particle array, the contact lists with their histories and the neighbour-list
    /// references follow, so the physics is unchanged; later steps differ by round-off only
    /// (forces are summed in another order). Returns the permutation: the particle now at
    /// index k was particle order[k].
    std::vector<Index> sort_spatially(double cell = 0.0) {
        const std::size_t n = particles_.size();
        const std::vector<Index> order = spatial_order(particles_.position(), particles_.radius(), domain_, cell);
        std::vector<Index> new_index(n);
        for (std::size_t k = 0; k < n; ++k) new_index[order[k]] = static_cast<Index>(k);
        const detail::Permutation permute{order};  // an archive that reorders every array it visits
        particles_.serialize(permute);
        permute.array(reference_);
        if constexpr (Integrator::keeps_previous_forces) {
            permute.array(previous_force_);
            if constexpr (rotation) permute.array(previous_torque_);
        }
        pairs_.renumber(new_index, true);
        if constexpr (has_walls) wall_contacts_.renumber(new_index, false);
        return order;
    }

    /// The spacing of representable coordinates at the farthest particle or wall from the origin
    /// (one unit in the last place): overlaps are differences of coordinates, so this is the
    /// absolute error of every overlap. Relative to an overlap delta the force error is about
    /// position_resolution() / delta (2e-6 for overlaps of 1e-7 m at 1e3 m from the origin in
    /// double precision, 2e-2 at 0.02 m in float; tests/physics/extremes.cpp and precision.cpp
    /// measure it).
    double position_resolution() const {
        double far = 0.0;
        for (const auto& x : particles_.position()) far = std::max(far, double(x.cwiseAbs().maxCoeff()));
        if constexpr (has_walls)
            for (const auto& w : walls_) far = std::max(far, std::abs(w.offset));
        return far * std::numeric_limits<Real>::epsilon();
    }

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
    std::size_t neighbor_rebuilds() const { return rebuilds_; }

    // ---- integrator stages -------------------------------------------------------------------
    /// Kick by h_before, drift by dt, kick by h_after (either kick may be zero), in one pass over
    /// the particles: the same arithmetic as three passes, with a third of the memory traffic,
    /// which is what limits large packings. With h_closing != 0 the pass first completes the
    /// previous step by kick_force_change(h_closing) (run() merges the two stages this way).
    /// The pass also clears the array the next compute_forces() accumulates into, once its
    /// values are dead. Walls move, time advances, lists refresh as needed.
    void kick_drift_kick(double h_before, double dt, double h_after, double h_closing = 0.0) {
        if constexpr (Integrator::keeps_previous_forces && !std::is_same_v<Real, double>) {
            // The closing kick must round v to float before the next kick, and GCC 12 at -O2
            // folds a double -> float -> double round trip of SSE vectors to nothing (measured:
            // tests/unit/run_stages.cpp): with float storage it keeps its own pass.
            if (h_closing != 0.0) kick_force_change(h_closing);
            h_closing = 0.0;
        }
        // Without periodic axes (a box of walls, like the biaxial test) the pass skips wrapping and
        // minimum images: the same numbers, a quarter fewer instructions in the pass (2D biaxial).
        constexpr bool keep = Integrator::keeps_previous_forces;
        const auto [max_move_sq, sum_move_sq] =
            domain_.any_periodic()
                ? detail::kick_drift_pass<true, rotation, keep>(particle_arrays(), domain_, h_before, dt, h_after, h_closing, active_threads())
                : detail::kick_drift_pass<false, rotation, keep>(particle_arrays(), domain_, h_before, dt, h_after, h_closing, active_threads());
        accumulators_cleared_ = true;
        if (!std::isfinite(sum_move_sq)) report_blow_up();
        double wall_move = 0.0;
        if constexpr (has_walls) {
            walls_.move(time_, dt, domain_);
            for (std::size_t k = 0; k < walls_.size(); ++k)
                wall_move = std::max(wall_move, std::abs(walls_[k].offset - wall_reference_[k]));
        }
        time_ += dt;
        ++steps_;
        const double move = std::sqrt(max_move_sq);
        if (2.0 * move >= skin_ || move + wall_move >= skin_) rebuild_neighbors();
    }

    void kick_force_change(double h) {
        static_assert(Integrator::keeps_previous_forces);
        detail::kick_force_change_pass<rotation>(particle_arrays(), h, active_threads());
    }

    void compute_forces() {
        if constexpr (Integrator::keeps_previous_forces) {
            // swap, not copy: compute_forces_impl zeroes the arrays it accumulates into anyway
            previous_force_.swap(particles_.template get<field::Force>());
            if constexpr (rotation) previous_torque_.swap(particles_.template get<field::Torque>());
        }
        if (track_energy_) compute_forces_impl<true>();
        else compute_forces_impl<false>();
        evaluated_dt_ = dt_;
    }

    // ---- state and analysis ------------------------------------------------------------------
    const EnergyBooks& books() const { return books_; }
    double initial_energy() const { return initial_energy_; }

    EnergyState energy() const {
        EnergyState e;
        e.kinetic_translational = particles_.translational_kinetic_energy();
        e.kinetic_rotational = particles_.rotational_kinetic_energy();
        if constexpr (has_walls) e.kinetic_walls = walls_.kinetic_energy();
        for_each_contact([&](const ContactView<dim>& c) {
            e.elastic_normal += law_.normal.elastic_energy(c.geometry.overlap);
            e.elastic_tangential += c.elastic_energy - law_.normal.elastic_energy(c.geometry.overlap);
        });
        std::apply([&](const auto&... f) { ((e.gravitational += gravitational_energy(f)), ...); }, body_forces_);
        return e;
    }

    /// kinetic + potential + dissipated - work_in - initial, relative to the initial energy
    /// (or to the work put in, if that is larger). Needs energy tracking.
    double energy_residual() const {
        const double now = energy().total() + books_.dissipated() - books_.work_in();
        const double scale = std::max({std::abs(initial_energy_), std::abs(books_.work_in()),
                                       std::numeric_limits<double>::min()});
        return (now - initial_energy_) / scale;
    }

    /// Elastic energy per particle: each spring's energy split half and half between the two
    /// partners; a wall gives its share to the particle.
    std::vector<double> potential_energy_per_particle() const {
        std::vector<double> u(particles_.size(), 0.0);
        for_each_contact([&](const ContactView<dim>& c) {
            if (c.wall) u[c.i] += c.elastic_energy;
            else {
                u[c.i] += 0.5 * c.elastic_energy;
                u[c.j] += 0.5 * c.elastic_energy;
            }
        });
        return u;
    }

    /// Calls f(ContactView) for every contact with positive overlap, particle pairs first, then
    /// wall contacts. Forces are those of the present state (see CundallStrack::current_force).
    template <class F>
    void for_each_contact(F&& f) const {
        const auto [walls, wall_contacts] = wall_parts();
        detail::visit_contacts<rotation>(particle_input(), domain_, law_, pairs_, walls, wall_contacts, f);
    }

    /// Deforms the scene affinely, x -> F x: particle positions, walls (planes map to planes),
    /// a periodic box (diagonal F only), and every tangential spring, which takes up the
    /// tangential part of its contact's branch change as if the partners had moved there.
    /// Velocities are kept. Used by quasi-static strain steps and the relaxed affine probe.
    void deform_affinely(const Eigen::Matrix<double, dim, dim>& F) {
        if (!prepared_) prepare();
        const double energy_before = track_energy_ ? energy().total() : 0.0;
        const Domain<dim> deformed = domain_.deformed(F);
        auto& x = particles_.template get<field::Position>();
        if constexpr (has_tangential) {
            const auto [walls, wall_contacts] = wall_parts();
            detail::load_springs_affinely(F, particle_input(), domain_, law_, pairs_, walls, wall_contacts);
        }
        if constexpr (has_walls) walls_.deform(F);
        for (auto& p : x) {
            V moved = F * convert<double>(p);
            deformed.wrap(moved);
            p = convert<Real>(moved);
        }
        domain_ = deformed;
        rebuild_neighbors();
        compute_forces_without_books();
        if (track_energy_) books_.work_by_deformation += energy().total() - energy_before;  // done instantly, no loss
    }

    /// Visits the complete state (particles, contacts with their springs, walls, box, law, body
    /// forces, neighbour-list references, the previous forces, energy books, clocks), so that a
    /// restored simulation continues bit for bit. See io/state.hpp for files.
    template <class Archive>
    void serialize(Archive& ar) {
        ar.raw(law_);  // plain parameter structs
        domain_.serialize(ar);
        if constexpr (has_walls) walls_.serialize(ar);
        std::apply([&](auto&... f) { (ar.raw(f), ...); }, body_forces_);
        particles_.serialize(ar);
        pairs_.serialize(ar);
        if constexpr (has_walls) {
            wall_contacts_.serialize(ar);
            ar.array(wall_reference_);
            ar.array(wall_books_);
        }
        ar.array(reference_);
        if constexpr (Integrator::keeps_previous_forces) {
            ar.array(previous_force_);
            if constexpr (rotation) ar.array(previous_torque_);
        }
        ar.value(books_);
        ar.value(step_books_);
        ar.value(previous_step_books_);
        ar.value(initial_energy_);
        ar.value(dt_);
        ar.value(evaluated_dt_);
        ar.value(skin_);
        ar.value(time_);
        ar.value(steps_);
        ar.value(rebuilds_);
        ar.value(prepared_);
        ar.value(allow_unstable_);
        ar.value(track_energy_);
    }

    /// Refuses a restored state (from `source`, a file name for the message) whose parts do not hold
    /// together: arrays of other lengths than the particle count, pairs naming particles or walls
    /// that do not exist, positions, velocities, radii, masses or clocks that are not finite or not
    /// positive where they must be. io::load_state calls it; a damaged file must never run.
    void check_restored(const std::string& source) const {
        auto refuse = [&](auto&&... what) {
            detail::throw_input_error(source, ": the restored state does not hold together (", what..., ")");
        };
        const std::size_t n = particles_.size();
        particles_.check_restored(refuse);
        if (reference_.size() != n) refuse(reference_.size(), " neighbour-list references for ", n, " particles");
        if constexpr (Integrator::keeps_previous_forces) {
            if (previous_force_.size() != n) refuse(previous_force_.size(), " previous forces for ", n, " particles");
            if constexpr (rotation)
                if (previous_torque_.size() != n) refuse(previous_torque_.size(), " previous torques for ", n, " particles");
        }
        if (!pairs_.consistent()) refuse("contact histories and pairs of different lengths");
        for (std::size_t c = 0; c < pairs_.size(); ++c) {
            const auto [i, j] = pairs_.pairs()[c];
            if (!(i < j && j < n)) refuse("pair ", c, " names particles ", i, " and ", j, " of ", n);
        }
        if constexpr (has_walls) {
            walls_.check_restored(refuse);
            if (!wall_contacts_.consistent()) refuse("wall histories and wall contacts of different lengths");
            for (std::size_t c = 0; c < wall_contacts_.size(); ++c) {
                const auto [i, w] = wall_contacts_.pairs()[c];
                if (!(i < n && w < walls_.size())) refuse("wall contact ", c, " names particle ", i, " and wall ", w);
            }
        }
        if (!(dt_ > 0.0 && std::isfinite(dt_)) || !std::isfinite(time_) || !(evaluated_dt_ >= 0.0 && std::isfinite(evaluated_dt_)))
            refuse("time step ", dt_, ", time ", time_);
    }

    /// Bytes the simulation holds in its arrays (particles, contacts with history, neighbour-list
    /// references, previous forces), capacities counted: the engine's own memory footprint.
    std::size_t storage_bytes() const {
        std::size_t b = particles_.size() * particles_.bytes_per_particle() + pairs_.bytes() +
                        reference_.capacity() * sizeof(SV);
        if constexpr (has_walls) b += wall_contacts_.bytes();
        b += pair_loop_.bytes();
        if constexpr (Integrator::keeps_previous_forces) {
            b += previous_force_.capacity() * sizeof(SV);
            if constexpr (rotation) b += previous_torque_.capacity() * sizeof(SA);
        }
        return b;
    }

    std::size_t contact_count() const {
        std::size_t count = 0;
        for_each_contact([&](const ContactView<dim>&) { ++count; });
        return count;
    }

private:
    // All pair forces, on threads_ threads (see engine/thread_shares.hpp).
    template <bool track>
    void pair_forces() {
        SA* torque = nullptr;
        if constexpr (rotation) torque = particles_.template get<field::Torque>().data();
        pair_loop_.template run<track>(contact_input(pairs_), pairs_.size(), static_cast<Index>(particles_.size()), active_threads(),
                                       domain_, law_, dt_, particles_.template get<field::Force>().data(), torque, step_books_);
    }

    template <bool track>
    void compute_forces_impl() {
        auto& f = particles_.template get<field::Force>();
        if (!accumulators_cleared_) {  // else kick_drift_kick() cleared them in its pass
            f.assign(particles_.size(), SV::Zero());
            if constexpr (rotation) particles_.template get<field::Torque>().assign(particles_.size(), zero_angular<dim, Real>());
        }
        accumulators_cleared_ = false;
        pair_forces<track>();
        if constexpr (has_walls) {
            SA* torque = nullptr;
            if constexpr (rotation) torque = particles_.template get<field::Torque>().data();
            detail::wall_forces<track, rotation>(contact_input(wall_contacts_), wall_contacts_.size(), walls_, law_, dt_, f.data(),
                                                 torque, step_books_);
        }
        std::apply([&](const auto&... bf) { (apply_body_force<track>(bf), ...); }, body_forces_);
        if constexpr (track) close_step_books();
    }

    // A body force that measures motion against the walls' mean flow receives it (the lab frame,
    // zero, in a scene without walls).
    template <bool track, class F>
    void apply_body_force(const F& force) {
        if constexpr (requires(AffineField<dim> field) { force.template apply<track>(particles_, step_books_, dt_, field); }) {
            AffineField<dim> field;
            if constexpr (has_walls) field = walls_.affine_field();
            force.template apply<track>(particles_, step_books_, dt_, field);
        } else {
            force.template apply<track>(particles_, step_books_, dt_);
        }
    }

    // Re-evaluates the forces of a state the books have not seen move (a re-prepare, an imposed
    // deformation): it adds nothing to the books, it only restarts the trapezoid.
    void compute_forces_without_books() {
        const EnergyBooks kept = books_;
        step_back_springs();
        compute_forces();
        books_ = kept;
    }

    // Before the same instant is evaluated again: every spring back to where the last evaluation
    // found it (see CundallStrack::step_back), so the new evaluation does not advance it twice.
    void step_back_springs() {
        if constexpr (has_tangential) {
            if (!(evaluated_dt_ > 0.0)) return;  // nothing evaluated yet
            const auto [walls, wall_contacts] = wall_parts();
            detail::step_back_springs<rotation>(particle_input(), domain_, law_, pairs_, walls, wall_contacts, evaluated_dt_, dt_);
        }
    }

    // What an evaluation's forces dissipate, rate x dt, is booked half now and half at the next
    // evaluation: with velocity Verlet a force acts from half a step before its evaluation to
    // half a step after, so the trapezoid keeps the books second order and level with the state.
    void close_step_books() {
        if constexpr (has_walls) detail::book_wall_work(walls_, domain_, wall_books_, books_);
        books_.add_mean(step_books_, previous_step_books_);
        previous_step_books_ = step_books_;
        step_books_ = {};
    }

    // The walls and their contact list, both null in a scene without walls.
    std::pair<const Walls<dim>*, const ContactList<History>*> wall_parts() const {
        if constexpr (has_walls) return {&walls_, &wall_contacts_};
        else return {nullptr, nullptr};
    }
    std::pair<const Walls<dim>*, ContactList<History>*> wall_parts() {
        if constexpr (has_walls) return {&walls_, &wall_contacts_};
        else return {nullptr, nullptr};
    }

    // The arrays the pair and wall loops read: the particles' (particle_input) and a contact list's.
    detail::ContactLoopInput<dim, Real, History> particle_input() const {
        detail::ContactLoopInput<dim, Real, History> in{particles_.position().data(), particles_.velocity().data(),
                                                        particles_.radius().data(), nullptr, nullptr, nullptr};
        if constexpr (rotation) in.w = particles_.template get<field::AngularVelocity>().data();
        return in;
    }
    detail::ContactLoopInput<dim, Real, History> contact_input(ContactList<History>& list) {
        auto in = particle_input();
        in.pair = list.pairs().data();
        if constexpr (has_tangential) in.history = list.history_data();
        return in;
    }

    template <class F>
    double gravitational_energy(const F& force) const {
        if constexpr (requires { force.potential_energy(particles_); }) return force.potential_energy(particles_);
        else return 0.0;
    }

    // The particle arrays the passes of engine/particle_pass.hpp work on.
    detail::ParticleArrays<dim, Real> particle_arrays() {
        detail::ParticleArrays<dim, Real> a{particles_.template get<field::Position>().data(),
                                            particles_.template get<field::Velocity>().data(),
                                            particles_.template get<field::Force>().data(),
                                            particles_.template get<field::InverseMass>().data(),
                                            nullptr, nullptr, nullptr, nullptr, nullptr, reference_.data(), particles_.size()};
        if constexpr (rotation) {
            a.w = particles_.template get<field::AngularVelocity>().data();
            a.torque = particles_.template get<field::Torque>().data();
            a.inv_I = particles_.template get<field::InverseInertia>().data();
        }
        if constexpr (Integrator::keeps_previous_forces) {
            a.f_old = previous_force_.data();
            if constexpr (rotation) a.torque_old = previous_torque_.data();
        }
        return a;
    }

    void rebuild_neighbors() {
        const auto& x = particles_.position();
        const auto& r = particles_.radius();
        auto& next = pairs_.scratch();
        next.clear();
        neighbors_.find_pairs(x, r, domain_, skin_, next);
        pairs_.commit_scratch();
        reference_ = x;
        if constexpr (has_walls) {
            auto& wn = wall_contacts_.scratch();
            wn.clear();
            detail::find_wall_candidates(x, r, walls_, skin_, wn);
            wall_contacts_.commit_scratch();
            wall_reference_.resize(walls_.size());
            for (std::size_t w = 0; w < walls_.size(); ++w) wall_reference_[w] = walls_[w].offset;
        }
        ++rebuilds_;
    }

    [[noreturn]] void report_blow_up() const {
        const auto& x = particles_.position();
        std::size_t bad = 0;  // the first particle whose displacement overflowed or is NaN
        while (bad + 1 < x.size() &&
               std::isfinite(domain_.separation(convert<double>(x[bad]), convert<double>(reference_[bad])).squaredNorm()))
            ++bad;
        throw SimulationError(detail::concat(
            "the simulation blew up at step ", steps_ + 1, " (t = ", time_, " s): particle ", bad,
            " reached position component ", x[bad][0], ". The time step dt = ", dt_,
            " s against the stability limit ", stable_time_step(), " s is the usual cause; reduce dt"));
    }

    // See micromacro::check_position_resolution (engine/stability.hpp).
    void check_position_resolution() const {
        if (particles_.empty() || allow_coarse_positions_) return;
        const auto& r = particles_.radius();
        micromacro::check_position_resolution(position_resolution(), *std::min_element(r.begin(), r.end()),
                                              std::numeric_limits<Real>::epsilon(), std::is_same_v<Real, float>);
    }

    Law law_;
    Domain<dim> domain_;
    Boundary walls_;
    Integrator integrator_;
    Neighbors neighbors_;
    std::tuple<BodyForces...> body_forces_;
    ParticleSet particles_;
    ContactList<History> pairs_;
    [[no_unique_address]] std::conditional_t<has_walls, ContactList<History>, NoHistory> wall_contacts_;
    std::vector<SV> reference_;
    int threads_ = 1;
    detail::ThreadedPairLoop<dim, Real, rotation> pair_loop_;
    // Forces of the previous evaluation, for integrators that correct with the force change.
    [[no_unique_address]] std::conditional_t<Integrator::keeps_previous_forces, std::vector<SV>, NoHistory> previous_force_;
    [[no_unique_address]] std::conditional_t<Integrator::keeps_previous_forces && rotation, std::vector<SA>, NoHistory>
        previous_torque_;
    std::vector<double> wall_reference_;
    EnergyBooks books_, step_books_, previous_step_books_;
    std::vector<detail::WallBook> wall_books_;  // the walls as the books saw them at the last evaluation
    double initial_energy_ = 0.0;
    double dt_ = 0.0, skin_ = 0.0, time_ = 0.0;
    double evaluated_dt_ = 0.0;  // the step of the last force evaluation, which advanced the springs
    std::size_t steps_ = 0, rebuilds_ = 0;
    bool prepared_ = false, allow_unstable_ = false, track_energy_ = true, allow_coarse_positions_ = false;
    bool accumulators_cleared_ = false;  // the force (and torque) arrays are zero and sized: see kick_drift_kick
};

/// The engine in double precision (the usual choice; see BasicSimulation for float storage).
template <int dim, class Law, class Boundary = NoWalls, class Integrator = VelocityVerlet, class Neighbors = LinkedCells,
          class... BodyForces>
using Simulation = BasicSimulation<dim, double, Law, Boundary, Integrator, Neighbors, BodyForces...>;

}  // namespace micromacro
