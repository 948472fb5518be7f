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
#include "micromacro/engine/contact_view.hpp"
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
        const auto& inv_m = particles_.template get<field::InverseMass>();
        const double inv_max = *std::max_element(inv_m.begin(), inv_m.end());
        bool any_wall = false;
        if constexpr (has_walls) any_wall = walls_.size() > 0;
        if (particles_.size() < 2 && !any_wall) return std::numeric_limits<double>::infinity();  // nothing to touch
        const double partners = particles_.size() > 1 ? 2.0 : 1.0;  // another particle, or a wall
        const double inv_mu_n = partners * inv_max;
        double limit = Integrator::stability_limit(std::sqrt(law_.normal.stiffness() * inv_mu_n),
                                                  0.5 * law_.normal.damping() * inv_mu_n);
        if constexpr (has_tangential) {
            // The contact point's tangential mobility: 1/m + a^2/I with rotation, 1/m without.
            double inv_t = 0.0;
            for (std::size_t i = 0; i < particles_.size(); ++i) {
                double mobility = inv_m[i];
                if constexpr (rotation) {
                    const double a = particles_.radius()[i];
                    mobility += a * a * double(particles_.template get<field::InverseInertia>()[i]);
                }
                inv_t = std::max(inv_t, mobility);
            }
            const double inv_mu_t = partners * inv_t;
            limit = std::min(limit, Integrator::stability_limit(std::sqrt(law_.tangential.stiffness() * inv_mu_t),
                                                               0.5 * law_.tangential.damping() * inv_mu_t));
        }
        if constexpr (has_walls)  // a stress-controlled wall on one contact: semi-implicit Euler
            for (const auto& w : walls_)
                if (const auto* s = std::get_if<StressControlled>(&w.motion)) {
                    const double inv_mu = 1.0 / s->mass + inv_max;
                    limit = std::min(limit, SymplecticEuler::stability_limit(std::sqrt(law_.normal.stiffness() * inv_mu),
                                                                            0.5 * s->damping / s->mass));
                }
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
        const auto [max_move_sq, sum_move_sq] = domain_.any_periodic() ? kick_drift_pass<true>(h_before, dt, h_after, h_closing)
                                                                       : kick_drift_pass<false>(h_before, dt, h_after, h_closing);
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
        SV* v = particles_.template get<field::Velocity>().data();
        const SV* f = particles_.template get<field::Force>().data();
        const SV* f_old = previous_force_.data();
        const Real* inv_m = particles_.template get<field::InverseMass>().data();
        [[maybe_unused]] SA* w = nullptr;
        [[maybe_unused]] const SA* torque = nullptr;
        [[maybe_unused]] const SA* torque_old = nullptr;
        [[maybe_unused]] const Real* inv_I = nullptr;
        if constexpr (rotation) {
            w = particles_.template get<field::AngularVelocity>().data();
            torque = particles_.template get<field::Torque>().data();
            torque_old = previous_torque_.data();
            inv_I = particles_.template get<field::InverseInertia>().data();
        }
        const std::size_t n = particles_.size();
        MICROMACRO_OMP(omp parallel for num_threads(active_threads()) schedule(static) if (active_threads() > 1))
        for (std::size_t i = 0; i < n; ++i) {
            v[i] = convert<Real>(force_change_kick(convert<double>(v[i]), h * double(inv_m[i]), convert<double>(f[i]),
                                                   convert<double>(f_old[i])));
            if constexpr (rotation)
                w[i] = convert<Real>(force_change_kick(convert<double>(w[i]), h * double(inv_I[i]), convert<double>(torque[i]),
                                                       convert<double>(torque_old[i])));
        }
    }

    // v + h/m (F - F_old), or its rotational twin: the one formula of kick_force_change and of
    // the closing kick merged into kick_drift_kick, so the two give the same bits.
    template <class U>
    MICROMACRO_INLINE static U force_change_kick(const U& v, double h_over_mass, const U& now, const U& before) {
        return U(v + h_over_mass * (now - before));
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
        const auto& v = particles_.velocity();
        for (std::size_t i = 0; i < particles_.size(); ++i)
            e.kinetic_translational += 0.5 * double(particles_.mass()[i]) * convert<double>(v[i]).squaredNorm();
        if constexpr (rotation) {
            const auto& w = particles_.template get<field::AngularVelocity>();
            const auto& I = particles_.template get<field::Inertia>();
            for (std::size_t i = 0; i < particles_.size(); ++i)
                e.kinetic_rotational += 0.5 * double(I[i]) * T::squared_norm(convert<double>(w[i]));
        }
        if constexpr (has_walls)
            for (const auto& w : walls_)
                if (const auto* s = std::get_if<StressControlled>(&w.motion)) e.kinetic_walls += 0.5 * s->mass * w.speed * w.speed;
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
        const auto& x = particles_.position();
        const auto& r = particles_.radius();
        for (std::size_t c = 0; c < pairs_.size(); ++c) {
            const auto [i, j] = pairs_.pairs()[c];
            const V d = domain_.separation(convert<double>(x[i]), convert<double>(x[j]));
            const double dist = d.norm(), reach = double(r[i]) + double(r[j]);
            if (!(dist < reach) || dist == 0.0) continue;
            const V n = d * (1.0 / dist);  // as the force loop computes it
            f(view(i, j, false, n, reach - dist, d, relative_velocity(i, j, n), history_of(pairs_, c)));
        }
        if constexpr (has_walls)
            for (std::size_t c = 0; c < wall_contacts_.size(); ++c) {
                const auto [i, w] = wall_contacts_.pairs()[c];
                const auto& wall = walls_[w];
                const double s = wall.distance(convert<double>(x[i])), a = r[i];
                if (!(s < a)) continue;
                f(view(i, w, true, wall.normal, a - s, V(s * wall.normal), wall_relative_velocity(i, wall),
                       history_of(wall_contacts_, c), wall.frictionless));
            }
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
            auto load = [&](History& h, const V& l) {
                const V n = l.normalized(), moved = F * l - l;
                law_.tangential.displace(V(moved - n * n.dot(moved)), h);
            };
            for (std::size_t c = 0; c < pairs_.size(); ++c) {
                const auto [i, j] = pairs_.pairs()[c];
                load(pairs_.history(c), domain_.separation(convert<double>(x[i]), convert<double>(x[j])));
            }
            if constexpr (has_walls)
                for (std::size_t c = 0; c < wall_contacts_.size(); ++c) {
                    const auto [i, w] = wall_contacts_.pairs()[c];
                    if (!walls_[w].frictionless)
                        load(wall_contacts_.history(c), V(walls_[w].distance(convert<double>(x[i])) * walls_[w].normal));
                }
        }
        if constexpr (has_walls) {
            const Eigen::Matrix<double, dim, dim> normal_map = F.inverse().transpose();
            for (auto& w : walls_) {
                const V point = F * (w.offset * w.normal);
                w.normal = (normal_map * w.normal).normalized();
                w.offset = w.normal.dot(point);
                w.initial_offset = w.offset;
            }
        }
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
        if (!particles_.consistent()) refuse("particle fields of different lengths");
        if (reference_.size() != n) refuse(reference_.size(), " neighbour-list references for ", n, " particles");
        if constexpr (Integrator::keeps_previous_forces) {
            if (previous_force_.size() != n) refuse(previous_force_.size(), " previous forces for ", n, " particles");
            if constexpr (rotation)
                if (previous_torque_.size() != n) refuse(previous_torque_.size(), " previous torques for ", n, " particles");
        }
        for (std::size_t i = 0; i < n; ++i) {
            if (!convert<double>(particles_.position()[i]).allFinite() || !convert<double>(particles_.velocity()[i]).allFinite())
                refuse("particle ", i, " has a position or velocity that is not finite");
            if (!(double(particles_.radius()[i]) > 0.0) || !(double(particles_.mass()[i]) > 0.0) ||
                !std::isfinite(double(particles_.radius()[i])) || !std::isfinite(double(particles_.mass()[i])))
                refuse("particle ", i, " has radius ", particles_.radius()[i], " and mass ", particles_.mass()[i]);
        }
        if (!pairs_.consistent()) refuse("contact histories and pairs of different lengths");
        for (std::size_t c = 0; c < pairs_.size(); ++c) {
            const auto [i, j] = pairs_.pairs()[c];
            if (!(i < j && j < n)) refuse("pair ", c, " names particles ", i, " and ", j, " of ", n);
        }
        if constexpr (has_walls) {
            for (std::size_t w = 0; w < walls_.size(); ++w)
                if (!walls_[w].normal.allFinite() || !std::isfinite(walls_[w].offset) || !std::isfinite(walls_[w].speed))
                    refuse("wall ", w, " has a position or speed that is not finite");
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
        for (const auto& list : spills_) b += list.capacity() * sizeof(Spill);
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
    // What a thread's share of the pair loop owes a particle of a later thread (see pair_forces):
    // subtracted from its force and torque, as the partner of a pair.
    struct Spill {
        Index particle;
        SV force;
        [[no_unique_address]] std::conditional_t<rotation, SA, NoHistory> torque;
    };

    struct Response {
        V force;       // on i
        V tangential;  // tangential part of force, for the torques
        double normal_force;
    };

    // The physics of one contact, shared by particle pairs and wall contacts. What it dissipates
    // goes to `books` (a local copy in the pair loop, so the sums stay in registers).
    template <bool track>
    MICROMACRO_INLINE static Response respond(const Law& law, double dt, const V& n, double overlap, double normal_velocity,
                                              const V& relative_velocity, History* h, EnergyBooks& books, bool smooth = false) {
        const NormalForce fn = law.normal.force(overlap, normal_velocity);
        if constexpr (track) books.dissipated_normal -= fn.viscous * normal_velocity * dt;
        Response out{fn.total() * n, V::Zero(), fn.total()};
        if constexpr (has_tangential) {
            if (smooth) return out;  // a frictionless wall: normal part only
            const auto ft = law.tangential.template force<dim, track>(n, relative_velocity, normal_velocity, fn.total(), overlap,
                                                                               dt, *h);
            if constexpr (track) {
                books.dissipated_tangential += ft.dissipated_viscous;
                books.dissipated_sliding += ft.dissipated_sliding;
            }
            out.force += ft.force;
            out.tangential = ft.force;
        }
        return out;
    }

    // The one pair loop, over candidates [begin, end), adding into the particles' force and
    // torque arrays f and torque; a partner at or past owned_end belongs to another thread and
    // goes to `spill` instead (see pair_forces() below). Raw pointers and local copies of the
    // law, the box and the energy account: through the members the compiler would reload them
    // after every store to the forces. (Keeping i's values in registers over its run of
    // partners was tried: more instructions and no faster, the loop runs out of registers.)
    // A coincident pair cannot be thrown from a thread; it is recorded and reported after.
    // `periodic`: whether the box has a periodic axis (else separations are plain differences).
    template <bool track, bool periodic>
    void pair_forces(std::size_t begin, std::size_t end, SV* f, [[maybe_unused]] SA* torque, EnergyBooks& books,
                     IndexPair& coincident, Index owned_end, std::vector<Spill>& spill) {
        const SV* x = particles_.position().data();
        const SV* v = particles_.velocity().data();
        const Real* r = particles_.radius().data();
        [[maybe_unused]] const SA* w = nullptr;
        if constexpr (rotation) w = particles_.template get<field::AngularVelocity>().data();
        const IndexPair* pair = pairs_.pairs().data();
        [[maybe_unused]] History* history = nullptr;
        if constexpr (has_tangential) history = pairs_.history_data();
        const Domain<dim> domain = domain_;
        const Law law = law_;
        const double dt = dt_;
        EnergyBooks account = books;
        // Three passes per block of candidates: find the touching pairs (branch-free, the 20-30%
        // of candidates that do not touch would otherwise be a badly predicted jump), take their
        // square roots and reciprocals as Eigen packets, then compute their forces. The square
        // root and division of each contact sat in one chain with its force and stalled the
        // single loop (perf: a fifth of its samples); in packets they pipeline two (SSE2) or
        // four (AVX) at a time. The arithmetic and the order of the sums are unchanged.
        constexpr std::size_t block = 128;
        std::array<std::uint32_t, block> touching;
        [[maybe_unused]] std::array<std::uint32_t, block> opened;
        std::array<V, block> separation;
        std::array<double, block> separation_sq, distance, inverse_distance;
        for (std::size_t b0 = begin; b0 < end; b0 += block) {
            const std::size_t b1 = std::min(end, b0 + block);
            std::size_t count = 0, open = 0;
            for (std::size_t c = b0; c < b1; ++c) {
                const auto [i, j] = pair[c];
                const V d = domain.template separation_for<periodic>(convert<double>(x[i]), convert<double>(x[j]));
                const double dist_sq = d.squaredNorm(), reach = double(r[i]) + double(r[j]);
                const bool touches = dist_sq < reach * reach;
                touching[count] = static_cast<std::uint32_t>(c - b0);
                if constexpr (has_tangential) opened[open] = static_cast<std::uint32_t>(c - b0);
                separation[count] = d;
                separation_sq[count] = dist_sq;
                count += touches;
                open += !touches;
            }
            if constexpr (has_tangential)
                for (std::size_t k = 0; k < open; ++k) {  // the contact opened, if it was one
                    History& h = history[b0 + opened[k]];
                    if (h.touching) [[unlikely]]
                        opened_pair<periodic>(pair[b0 + opened[k]], h, f, torque, owned_end, spill);
                    h = History{};
                }
            {  // square roots and reciprocals two or four at a time (Eigen's packets)
                using Column = Eigen::Array<double, Eigen::Dynamic, 1>;
                Eigen::Map<Column> dist(distance.data(), count), inverse(inverse_distance.data(), count);
                dist = Eigen::Map<const Column>(separation_sq.data(), count).sqrt();
                inverse = dist.inverse();
            }
            for (std::size_t k = 0; k < count; ++k) {
                const std::size_t c = b0 + touching[k];
                const auto [i, j] = pair[c];
                if (separation_sq[k] == 0.0) [[unlikely]] {
                    coincident = pair[c];
                    continue;
                }
                const double ri = r[i], rj = r[j], reach = ri + rj;
                const double dist = distance[k];
                const V n = separation[k] * inverse_distance[k];
                const V dv = convert<double>(v[i]) - convert<double>(v[j]);
                const V vr = relative_velocity(n, dv, w, i, j, ri, rj);
                History* h = nullptr;
                if constexpr (has_tangential) h = history + c;
                const Response resp = respond<track>(law, dt, n, reach - dist, n.dot(dv), vr, h, account);
                const SV& stored = convert<Real>(resp.force);  // resp.force itself in double
                f[i] += stored;
                [[maybe_unused]] A arm{};
                if constexpr (rotation) {
                    arm = T::cross(n, resp.tangential);  // torque on i is (-a_i n) x f_t
                    torque[i] -= convert<Real>(A(ri * arm));
                }
                if (j < owned_end) [[likely]] {
                    f[j] -= stored;
                    if constexpr (rotation) torque[j] -= convert<Real>(A(rj * arm));
                } else {  // another thread's particle: added by its owner after the loop
                    Spill& s = spill.emplace_back();
                    s.particle = j;
                    s.force = stored;
                    if constexpr (rotation) s.torque = convert<Real>(A(rj * arm));
                }
            }
        }
        books = account;
    }

    // The rest of the last evaluation's tangential impulse for a pair found open whose history
    // says it touched then (see opening_correction), added to both particles like a contact's
    // force. Out of the pair loop's way: one pair in thousands per step comes here.
    template <bool periodic>
    MICROMACRO_COLD void opened_pair(IndexPair p, const History& h, SV* f, [[maybe_unused]] SA* torque, Index owned_end,
                                     std::vector<Spill>& spill) const {
        const auto [i, j] = p;
        const auto& x = particles_.position();
        const auto& v = particles_.velocity();
        const auto& r = particles_.radius();
        const V d = domain_.template separation_for<periodic>(convert<double>(x[i]), convert<double>(x[j]));
        const double dist = d.norm();
        if (!(dist > 0.0)) return;
        const V n = d / dist;
        const V force = opening_correction(h, n, double(r[i]) + double(r[j]) - dist, n.dot(convert<double>(v[i]) - convert<double>(v[j])));
        const SV stored = convert<Real>(force);
        f[i] += stored;
        [[maybe_unused]] A arm{};
        if constexpr (rotation) {
            arm = T::cross(n, force);
            torque[i] -= convert<Real>(A(double(r[i]) * arm));
        }
        if (j < owned_end) {
            f[j] -= stored;
            if constexpr (rotation) torque[j] -= convert<Real>(A(double(r[j]) * arm));
        } else {
            Spill& s = spill.emplace_back();
            s.particle = j;
            s.force = stored;
            if constexpr (rotation) s.torque = convert<Real>(A(double(r[j]) * arm));
        }
    }

    // The tangential force that completes a just-opened contact's last evaluation, from the
    // overlap and separation speed of now: the overlap then was overlap + speed dt, the normal
    // force then the law's at that overlap, and the contact opened overlap-then / speed after it.
    V opening_correction(const History& h, const V& n, double overlap_now, double normal_velocity) const {
        if constexpr (requires { law_.tangential.opening_correction(n, h, 0.0, 0.0, 0.0); }) {
            if (!(normal_velocity > 0.0)) return V::Zero();
            const double overlap_then = overlap_now + normal_velocity * dt_;
            if (!(overlap_then > 0.0)) return V::Zero();
            const double fn = law_.normal.force(overlap_then, normal_velocity).total();
            return law_.tangential.opening_correction(n, h, fn, overlap_then / normal_velocity, dt_);
        } else {
            return V::Zero();
        }
    }

    // All pair forces, on threads_ threads. The candidates are sorted by their first particle i;
    // each thread takes a nearly equal contiguous share, cut where i changes, and so owns the
    // particles from its first i to the next share's first i: it writes their forces directly.
    // Only a partner j past its own particles (j > i, so it belongs to a later thread) goes into
    // the thread's spill list, which the owner adds after the loop, threads in order. With
    // particles in spatial order (sort_spatially) a share's partners lie close to it and the
    // spill lists stay short. Bitwise the same for a fixed thread count.
    template <bool track>
    void pair_forces() {
        SV* f = particles_.template get<field::Force>().data();
        SA* torque = nullptr;
        if constexpr (rotation) torque = particles_.template get<field::Torque>().data();
        const std::size_t count = pairs_.size();
        const auto n = static_cast<Index>(particles_.size());
        const int shares = active_threads();
        thread_books_.assign(shares, EnergyBooks{});
        coincident_.assign(shares, IndexPair{0, 0});
        spills_.resize(shares);
        for (auto& list : spills_) list.clear();
        // Share t: candidates [begin, end), particles below owned_end its own. Without periodic
        // axes the separations need no minimum-image test (see kick_drift_kick).
        const bool periodic = domain_.any_periodic();
        auto share = [&](std::size_t begin, std::size_t end, int t, Index owned_end) {
            if (periodic) pair_forces<track, true>(begin, end, f, torque, thread_books_[t], coincident_[t], owned_end, spills_[t]);
            else pair_forces<track, false>(begin, end, f, torque, thread_books_[t], coincident_[t], owned_end, spills_[t]);
        };
        if (shares == 1) {
            share(0, count, 0, n);
        } else {
            const IndexPair* pair = pairs_.pairs().data();
            share_start_.assign(shares + 1, count);
            share_start_[0] = 0;
            for (int t = 1; t < shares; ++t) {
                std::size_t c = std::max(share_start_[t - 1], detail::share_begin(count, t, shares));
                while (c > 0 && c < count && pair[c].i == pair[c - 1].i) ++c;  // do not split a particle's run
                share_start_[t] = c;
            }
            auto first_particle = [&](int t) { return share_start_[t] < count ? pair[share_start_[t]].i : n; };
            MICROMACRO_OMP(omp parallel num_threads(shares)) {
                const int t = detail::thread_number();
                const Index owned_begin = t == 0 ? 0 : first_particle(t), owned_end = t + 1 == shares ? n : first_particle(t + 1);
                share(share_start_[t], share_start_[t + 1], t, owned_end);
                MICROMACRO_OMP(omp barrier)
                for (int u = 0; u < t; ++u)
                    for (const Spill& s : spills_[u]) {
                        if (s.particle < owned_begin || s.particle >= owned_end) continue;
                        f[s.particle] -= s.force;
                        if constexpr (rotation) torque[s.particle] -= s.torque;
                    }
            }
        }
        for (const IndexPair& c : coincident_)
            if (c.i != c.j) report_coincident(c.i, c.j);
        if constexpr (track)
            for (const EnergyBooks& b : thread_books_) step_books_.add(b);  // in thread order
    }

    template <bool track>
    void compute_forces_impl() {
        auto& f = particles_.template get<field::Force>();
        const auto& x = particles_.position();
        const auto& r = particles_.radius();
        if (!accumulators_cleared_) {  // else kick_drift_kick() cleared them in its pass
            f.assign(particles_.size(), SV::Zero());
            if constexpr (rotation) particles_.template get<field::Torque>().assign(particles_.size(), zero_angular<dim, Real>());
        }
        accumulators_cleared_ = false;
        pair_forces<track>();
        if constexpr (has_walls) {
            for (auto& wall : walls_) wall.force = V::Zero();
            for (std::size_t c = 0; c < wall_contacts_.size(); ++c) {
                const auto [i, w] = wall_contacts_.pairs()[c];
                auto& wall = walls_[w];
                const double s = wall.distance(convert<double>(x[i])), a = r[i];
                if (s >= a) {
                    if constexpr (has_tangential) {
                        History& h = wall_contacts_.history(c);
                        if (h.touching) [[unlikely]] {  // opened in the last step: see opening_correction
                            const V force = opening_correction(h, wall.normal, a - s, wall.normal.dot(wall_relative_velocity(i, wall)));
                            f[i] += convert<Real>(force);
                            wall.force -= force;
                            if constexpr (rotation)
                                particles_.template get<field::Torque>()[i] -= convert<Real>(A(a * T::cross(wall.normal, force)));
                        }
                        h = History{};
                    }
                    continue;
                }
                const V& n = wall.normal;
                const V vr = wall_relative_velocity(i, wall);
                const Response resp = respond<track>(law_, dt_, n, a - s, n.dot(vr), vr, history_of(wall_contacts_, c),
                                                     step_books_, wall.frictionless);
                f[i] += convert<Real>(resp.force);
                wall.force -= resp.force;
                if constexpr (rotation)
                    particles_.template get<field::Torque>()[i] -= convert<Real>(A(a * T::cross(n, resp.tangential)));
            }
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
            const auto& x = particles_.position();
            for (std::size_t c = 0; c < pairs_.size(); ++c) {
                const auto [i, j] = pairs_.pairs()[c];
                const V d = domain_.separation(convert<double>(x[i]), convert<double>(x[j]));
                const double dist = d.norm();
                if (dist == 0.0) continue;
                const V n = d * (1.0 / dist);
                law_.tangential.step_back(n, relative_velocity(i, j, n), evaluated_dt_, dt_, pairs_.history(c));
            }
            if constexpr (has_walls)
                for (std::size_t c = 0; c < wall_contacts_.size(); ++c) {
                    const auto [i, w] = wall_contacts_.pairs()[c];
                    const auto& wall = walls_[w];
                    law_.tangential.step_back(wall.normal, wall_relative_velocity(i, wall), evaluated_dt_, dt_,
                                              wall_contacts_.history(c));
                }
        }
    }

    // What an evaluation's forces dissipate, rate x dt, is booked half now and half at the next
    // evaluation: with velocity Verlet a force acts from half a step before its evaluation to
    // half a step after, so the trapezoid keeps the books second order and level with the state.
    void close_step_books() {
        if constexpr (has_walls) book_wall_work();
        books_.add_mean(step_books_, previous_step_books_);
        previous_step_books_ = step_books_;
        step_books_ = {};
    }

    // Work of the walls between the last two evaluations (trapezoid in the wall force).
    void book_wall_work() {
        wall_books_.resize(walls_.size());
        for (std::size_t w = 0; w < walls_.size(); ++w) {
            const auto& wall = walls_[w];
            auto& last = wall_books_[w];
            const double push = wall.force.dot(wall.normal);  // < 0: the particles push it outward
            const double moved = wall.offset - last.offset;
            if (const auto* s = std::get_if<StressControlled>(&wall.motion)) {
                // The wall is part of the system: the pressure does work, its damper dissipates.
                const double area = walls_.area(wall, domain_);
                books_.work_by_walls += s->pressure * 0.5 * (area + last.area) * moved;
                books_.dissipated_walls += s->damping * s->damped_speed(wall.speed) * moved;
                last.area = area;
            } else {
                // A driven wall does work -F_wall . displacement on the particles.
                books_.work_by_walls -= 0.5 * (push + last.push) * moved;
            }
            last.offset = wall.offset;
            last.push = push;
        }
    }

    // v_ij of Eq. 25: relative velocity of the contact points, v_i - v_j + a_i n x w_i + a_j n x w_j,
    // from dv = v_i - v_j and the angular velocities w (unused without rotation). Static on raw
    // arrays for the pair loop (see pair_forces); analysis calls the member below.
    MICROMACRO_INLINE static V relative_velocity(const V& n, const V& dv, [[maybe_unused]] const SA* w, [[maybe_unused]] Index i,
                                                 [[maybe_unused]] Index j, [[maybe_unused]] double ri, [[maybe_unused]] double rj) {
        if constexpr (rotation) return dv + T::cross(n, A(ri * convert<double>(w[i]) + rj * convert<double>(w[j])));
        else return dv;
    }
    V relative_velocity(Index i, Index j, const V& n) const {
        const SA* w = nullptr;
        if constexpr (rotation) w = particles_.template get<field::AngularVelocity>().data();
        const auto& v = particles_.velocity();
        const auto& r = particles_.radius();
        return relative_velocity(n, V(convert<double>(v[i]) - convert<double>(v[j])), w, i, j, r[i], r[j]);
    }
    template <class W>
    V wall_relative_velocity(Index i, const W& wall) const {
        V vr = convert<double>(particles_.velocity()[i]) - wall.speed * wall.normal;
        if constexpr (rotation)
            vr += T::cross(wall.normal, A(double(particles_.radius()[i]) *
                                          convert<double>(particles_.template get<field::AngularVelocity>()[i])));
        return vr;
    }

    template <class List>
    static auto* history_of(List& list, std::size_t c) {
        if constexpr (has_tangential) return &list.history(c);
        else return static_cast<History*>(nullptr);
    }

    ContactView<dim> view(Index i, Index j, bool wall, const V& n, double overlap, const V& branch, const V& vr,
                          const History* h, bool smooth = false) const {
        ContactView<dim> c{i, j, wall, {n, overlap, n.dot(vr), vr}, branch, 0, 0, V::Zero(), 0, false};
        const NormalForce fn = law_.normal.force(overlap, c.geometry.normal_velocity);
        c.normal_force = fn.total();
        c.normal_elastic_force = fn.elastic;
        c.elastic_energy = law_.normal.elastic_energy(overlap);
        if constexpr (has_tangential) {
            if (smooth) return c;
            c.tangential_force = law_.tangential.current_force(n, vr, fn.total(), *h);
            c.elastic_energy += law_.tangential.elastic_energy(law_.tangential.present_spring(n, *h));
            c.sliding = h->sliding;
        }
        return c;
    }

    template <class F>
    double gravitational_energy(const F& force) const {
        if constexpr (requires { force.potential_energy(particles_); }) return force.potential_energy(particles_);
        else return 0.0;
    }

    // The particle pass of kick_drift_kick (see there): the largest squared displacement from
    // the references and the sum of them all (finite unless a particle blew up).
    template <bool periodic>
    std::pair<double, double> kick_drift_pass(double h_before, double dt, double h_after, double h_closing) {
        SV* x = particles_.template get<field::Position>().data();
        SV* v = particles_.template get<field::Velocity>().data();
        SV* f = particles_.template get<field::Force>().data();
        const Real* inv_m = particles_.template get<field::InverseMass>().data();
        [[maybe_unused]] SA* w = nullptr;
        [[maybe_unused]] SA* torque = nullptr;
        [[maybe_unused]] const Real* inv_I = nullptr;
        if constexpr (rotation) {
            w = particles_.template get<field::AngularVelocity>().data();
            torque = particles_.template get<field::Torque>().data();
            inv_I = particles_.template get<field::InverseInertia>().data();
        }
        // The forces of the step before (Verlet): read by a closing kick, then cleared.
        [[maybe_unused]] SV* f_old = nullptr;
        [[maybe_unused]] SA* torque_old = nullptr;
        if constexpr (Integrator::keeps_previous_forces) {
            f_old = previous_force_.data();
            if constexpr (rotation) torque_old = previous_torque_.data();
        }
        const SV* reference = reference_.data();
        const std::size_t n = particles_.size();
        // A local copy: the stores to x and v could alias the members, which the compiler would
        // then reload for every particle.
        const Domain<dim> domain = domain_;
        double max_move_sq = 0.0, sum_move_sq = 0.0;
        // firstprivate: shared, the scalars and pointers would be read through the outlined
        // function's argument block for every particle (the stores to x, v, w may alias it).
        MICROMACRO_OMP(omp parallel for num_threads(active_threads()) schedule(static) reduction(max : max_move_sq) reduction(+ : sum_move_sq)
                           firstprivate(x, v, f, inv_m, w, torque, inv_I, f_old, torque_old, reference, domain, h_before, dt,
                                        h_after, h_closing) if (active_threads() > 1))
        for (std::size_t i = 0; i < n; ++i) {
            const V fi = convert<double>(f[i]);
            V vi = convert<double>(v[i]);
            [[maybe_unused]] A wi = zero_angular<dim, double>();
            if constexpr (rotation) wi = convert<double>(w[i]);
            if constexpr (Integrator::keeps_previous_forces) {
                if (h_closing != 0.0) {  // kick_force_change(h_closing) (double only, see above)
                    vi = force_change_kick(vi, h_closing * double(inv_m[i]), fi, convert<double>(f_old[i]));
                    if constexpr (rotation)
                        wi = force_change_kick(wi, h_closing * double(inv_I[i]), convert<double>(torque[i]),
                                               convert<double>(torque_old[i]));
                }
                f_old[i] = SV::Zero();  // becomes the force array at the next compute_forces()
                if constexpr (rotation) torque_old[i] = zero_angular<dim, Real>();
            }
            const V a = double(inv_m[i]) * fi;
            vi += h_before * a;
            V xi = convert<double>(x[i]) + dt * vi;
            vi += h_after * a;
            if constexpr (periodic) domain.wrap(xi);
            // The displacement from the stored value, not reloaded from x[i]: wrap() stores
            // coordinates one by one, and a vector load right after them stalls.
            const SV stored = convert<Real>(xi);
            x[i] = stored;
            v[i] = convert<Real>(vi);
            const double move_sq =
                domain.template separation_for<periodic>(convert<double>(stored), convert<double>(reference[i])).squaredNorm();
            // The maximum drops a NaN, and the pair loop treats a NaN pair as not touching, so
            // nothing else would stop the run: the sum catches NaN and infinity. (It replaced a
            // NaN-to-infinity select per particle: 5% fewer instructions in this pass, 2D 1950
            // 1.03-1.06x side by side. By value, not std::max: its reference result made GCC carry
            // the maximum from particle to particle through memory.)
            max_move_sq = move_sq > max_move_sq ? move_sq : max_move_sq;
            sum_move_sq += move_sq;
            if constexpr (rotation) {
                w[i] = convert<Real>(A(wi + (h_before + h_after) * double(inv_I[i]) * convert<double>(torque[i])));
                if constexpr (!Integrator::keeps_previous_forces) torque[i] = zero_angular<dim, Real>();
            }
            if constexpr (!Integrator::keeps_previous_forces) f[i] = SV::Zero();  // read for the last time
        }
        return {max_move_sq, sum_move_sq};
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
            for (Index i = 0; i < x.size(); ++i)
                for (Index w = 0; w < walls_.size(); ++w)
                    if (walls_[w].distance(convert<double>(x[i])) < double(r[i]) + skin_) wn.push_back({i, w});
            wall_contacts_.commit_scratch();
            wall_reference_.resize(walls_.size());
            for (std::size_t w = 0; w < walls_.size(); ++w) wall_reference_[w] = walls_[w].offset;
        }
        ++rebuilds_;
    }

    [[noreturn]] void report_coincident(Index i, Index j) const {
        detail::throw_input_error("particles ", i, " and ", j, " have coincident centres (at distance 0), so their "
                                  "contact normal is undefined; move one of them");
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

    /// Refuses a scene whose stored coordinates cannot resolve overlaps of 1e-4 of the smallest
    /// radius (the paper's are 2e-4 of the mean) to 1%: too far from the origin, or float storage
    /// for most packings, unless allow_coarse_positions(true).
    void check_position_resolution() const {
        if (particles_.empty() || allow_coarse_positions_) return;
        const auto& r = particles_.radius();
        const double smallest = *std::min_element(r.begin(), r.end());
        const double resolution = position_resolution();
        if (resolution > 1e-6 * smallest)
            detail::throw_input_error("coordinates up to ", resolution / std::numeric_limits<Real>::epsilon(),
                                      " m from the origin are resolved to ", resolution, " m in ",
                                      std::is_same_v<Real, float> ? "float" : "double",
                                      ", more than 1e-6 of the smallest radius ", smallest,
                                      " m: overlaps would lose their digits; move the origin into the packing",
                                      std::is_same_v<Real, float> ? ", store in double" : "",
                                      ", or call allow_coarse_positions(true) to accept it");
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
    // Per-thread scratch of pair_forces(): where each share starts, and what it adds to later
    // threads' particles (see Spill).
    int threads_ = 1;
    std::vector<std::size_t> share_start_;
    std::vector<std::vector<Spill>> spills_;
    std::vector<EnergyBooks> thread_books_;
    std::vector<IndexPair> coincident_;
    // Forces of the previous evaluation, for integrators that correct with the force change.
    [[no_unique_address]] std::conditional_t<Integrator::keeps_previous_forces, std::vector<SV>, NoHistory> previous_force_;
    [[no_unique_address]] std::conditional_t<Integrator::keeps_previous_forces && rotation, std::vector<SA>, NoHistory>
        previous_torque_;
    std::vector<double> wall_reference_;
    EnergyBooks books_, step_books_, previous_step_books_;
    struct WallBooks {
        double offset = 0, push = 0, area = 0;
    };
    std::vector<WallBooks> wall_books_;
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
