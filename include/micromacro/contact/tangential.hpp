#pragma once
// Tangential contact models. A tangential model owns the per-contact state it needs (its
// History) and declares whether particles must rotate. `Frictionless` has neither, so a scene
// built with it stores no history and no rotational fields.
#include <algorithm>
#include <cmath>
#include <concepts>

#include "micromacro/core/dim_traits.hpp"
#include "micromacro/core/error.hpp"
#include "micromacro/core/inline.hpp"

namespace micromacro {

/// Tangential force on particle i and the energy it dissipated during this step.
template <int dim>
struct TangentialForce {
    Vec<dim> force = Vec<dim>::Zero();
    double dissipated_viscous = 0.0;  ///< by gamma_t while sticking
    double dissipated_sliding = 0.0;  ///< by Coulomb sliding (incl. the spring reset of Eq. 28)
    bool sliding = false;
};

struct NoHistory {};

/// No tangential force: perfectly smooth particles.
struct Frictionless {
    static constexpr bool has_history = false;
    static constexpr bool needs_rotation = false;
    template <int dim>
    using History = NoHistory;
    double stiffness() const { return 0.0; }
};

/// The Cundall-Strack tangential spring of Eq. 23-29, in 2D and 3D. The stored spring runs half
/// a step ahead of the present one (see CundallStrack::force).
template <int dim>
struct TangentialSpring {
    Vec<dim> spring = Vec<dim>::Zero();  ///< xi of Eq. 23-28 at the present time plus v_t dt/2
    bool sliding = false;                ///< Coulomb state, for the static/dynamic hysteresis
    bool touching = false;               ///< evaluated in contact before; false on a new contact
};

/// A contact's history as its other partner sees it, for when particles are renumbered and a
/// pair's two particles swap roles: the spring is odd under the swap (the relative velocity it
/// integrates and the force it gives change sign), the sliding state is shared.
inline NoHistory seen_from_partner(NoHistory h) { return h; }
template <int dim>
TangentialSpring<dim> seen_from_partner(const TangentialSpring<dim>& h) {
    return {Vec<dim>(-h.spring), h.sliding, h.touching};
}

class CundallStrack {
public:
    static constexpr bool has_history = true;
    static constexpr bool needs_rotation = true;
    template <int dim>
    using History = TangentialSpring<dim>;

    /// k_t: tangential stiffness; gamma_t: tangential damping; mu_s >= mu_d: static and sliding
    /// friction coefficients.
    CundallStrack(double kt, double gamma_t, double mu_s, double mu_d)
        : kt_(kt), gamma_t_(gamma_t), mu_s_(mu_s), mu_d_(mu_d) {
        detail::require_positive(kt, "tangential stiffness k_t", "use Frictionless for smooth particles");
        detail::require_non_negative(gamma_t, "tangential damping gamma_t", "use 0 for no tangential damping");
        detail::require_non_negative(mu_s, "static friction mu_s", "use 0 for no friction");
        detail::require_non_negative(mu_d, "sliding friction mu_d", "use 0 for no friction");
        if (mu_d > mu_s)
            detail::throw_input_error("sliding friction mu_d = ", mu_d, " exceeds static friction mu_s = ", mu_s,
                                      "; Coulomb friction needs mu_d <= mu_s (use mu_d = mu_s for one coefficient)");
    }
    /// One friction coefficient: mu_s = mu_d = mu, as in the paper's simulations.
    CundallStrack(double kt, double gamma_t, double mu) : CundallStrack(kt, gamma_t, mu, mu) {}

    double stiffness() const { return kt_; }
    double damping() const { return gamma_t_; }
    double mu_static() const { return mu_s_; }
    double mu_dynamic() const { return mu_d_; }

    /// The energy 1/2 k_t xi^2 of a spring xi (see present_spring for a contact's).
    template <int dim>
    double elastic_energy(const Vec<dim>& spring) const {
        return 0.5 * kt_ * spring.squaredNorm();
    }

    /// Eq. 23-29 for one evaluation. `normal_force` is f_n (positive = compressive); the
    /// tangential force is active only while f_n > 0, otherwise the Coulomb limit is zero and the
    /// spring resets. `normal_velocity` is n . v_ij, which the normal law has used already; Eq. 24
    /// takes it instead of projecting v_ij again (the rotational part of v_ij is perpendicular to
    /// n, so n . v_ij = n . (v_i - v_j)): one dot product less on the contact's longest chain of
    /// dependent operations.
    ///
    /// Time stepping. The engine evaluates forces at t_n with the predicted velocity v_n of
    /// velocity Verlet (the velocity-dependent forces need the velocity at the new time). The
    /// spring that gives the force is xi_n = xi_{n-1} + (v_{n-1} + v_n) dt/2: the trapezoid in the
    /// tangential velocity, which advances xi over each step by the step's mean velocity, as the
    /// positions advance: second order, and the spring's work over a step equals the change of
    /// its energy. The mean of two predicted velocities differs from the half-step velocity of
    /// velocity Verlet by dt^2/4 (a_n - a_{n-1}), so an undamped sticking contact still grows by
    /// about (omega_t dt)^3 per period (1e-4 at t_c/50; see BasicSimulation::stable_time_step).
    /// The history stores xi_n + v_n dt/2, so the next evaluation adds only its own v_{n+1} dt/2
    /// and nothing else per contact is kept. This holds for sliding too: Eq. 28 puts xi_n at the
    /// Coulomb limit and the history stores that plus v_n dt/2. (Storing the limit itself lags
    /// the spring by half a step after every sliding step: a sliding contact then sticks one step
    /// in two while the limit grows, a first-order error.)
    ///
    /// A new contact has touched for part of a step only: xi_n = v_n tau with tau = overlap /
    /// approach speed, the time since the surfaces met (at most dt). Taking half a step instead
    /// is right only on average over where in the step the contact began and leaves an error of
    /// order dt in every spring that follows from it.
    ///
    /// tests/physics/tangential.cpp checks the order on oblique impacts, the energy of an
    /// undamped sticking contact, the Coulomb limit and the hysteresis.
    template <int dim, bool track_energy>
    MICROMACRO_INLINE TangentialForce<dim> force(const Vec<dim>& n, const Vec<dim>& relative_velocity, double normal_velocity,
                                                 double normal_force, double overlap, double dt, History<dim>& h) const {
        if constexpr (dim == 2)
            return force_along_line<track_energy>(n, relative_velocity, normal_velocity, normal_force, overlap, dt, h);
        using V = Vec<dim>;
        TangentialForce<dim> out;
        const V stored = h.spring - n * n.dot(h.spring);                         // Eq. 23
        const V vt = relative_velocity - n * normal_velocity;                    // Eq. 24
        const double lead = h.touching ? 0.5 * dt : time_in_contact(overlap, normal_velocity, dt);
        const V spring = stored + lead * vt;                                     // Eq. 27: xi_n
        const V trial = -kt_ * spring - gamma_t_ * vt;                           // Eq. 26
        const double fn = std::max(normal_force, 0.0);
        // Compared squared: the square root is needed only by a sliding contact.
        const double trial_sq = trial.squaredNorm(), static_limit = mu_s_ * fn, dynamic_limit = mu_d_ * fn;
        // Static until the trial force exceeds mu_s f_n; once sliding, static again when it drops
        // below mu_d f_n (the paper's hysteresis between static and dynamic friction) or when the
        // motion reverses and unloads the spring (v_t against the stored spring, which points
        // along the last slip). Whatever the state, a trial force above mu_s f_n slides.
        const bool sliding = trial_sq > static_limit * static_limit ||
                             (h.sliding && trial_sq >= dynamic_limit * dynamic_limit && vt.dot(stored) >= 0.0);
        if (!sliding) {
            out.force = trial;
            h.spring = spring + (0.5 * dt) * vt;
            if constexpr (track_energy) out.dissipated_viscous = gamma_t_ * vt.squaredNorm() * dt;
        } else {
            // h still holds the step's old spring here (read only where needed: computed for every
            // contact it costs a spilled register in the pair loop).
            [[maybe_unused]] const double energy_before = track_energy ? elastic_energy<dim>(h.spring) : 0.0;
            const double limit = dynamic_limit, trial_magnitude = std::sqrt(trial_sq);
            const V t = trial_magnitude > 0.0 ? V(trial / trial_magnitude) : V(V::Zero());
            out.force = limit * t;                                               // Eq. 29
            h.spring = -(limit / kt_) * t + (0.5 * dt) * vt;                     // Eq. 28, stored as above
            // Energy the step took out of the pair that the spring did not store. Counted in the
            // stored springs, which run v_t dt/2 ahead: a sticking step changes their energy by
            // exactly the spring's work k_t xi_n . v_n dt (the trapezoid), so the books close
            // over any sequence of sticking and sliding steps.
            if constexpr (track_energy)
                out.dissipated_sliding = -out.force.dot(vt) * dt - (elastic_energy<dim>(h.spring) - energy_before);
        }
        h.sliding = sliding;
        h.touching = true;
        out.sliding = sliding;
        return out;
    }

    /// Eq. 23-29 in 2D, where the tangent plane is the line along t = (-n_1, n_0): the projections
    /// become the components along t, scalars, and the pair loop saves about a third of its
    /// arithmetic. The same physics as the vector form above to round-off (tests/physics/
    /// tangential.cpp compares the two on a 2D contact embedded in 3D).
    template <bool track_energy>
    MICROMACRO_INLINE TangentialForce<2> force_along_line(const Vec<2>& n, const Vec<2>& relative_velocity, double normal_velocity,
                                                          double normal_force, double overlap, double dt, History<2>& h) const {
        TangentialForce<2> out;
        const Vec<2> t(-n.y(), n.x());
        const double stored = t.dot(h.spring);                         // Eq. 23: the spring's part in the new tangent
        const double vt = t.dot(relative_velocity);                    // Eq. 24
        const double lead = h.touching ? 0.5 * dt : time_in_contact(overlap, normal_velocity, dt);
        const double spring = stored + lead * vt;                      // Eq. 27: xi_n
        const double trial = -kt_ * spring - gamma_t_ * vt;            // Eq. 26
        const double fn = std::max(normal_force, 0.0), trial_magnitude = std::abs(trial);
        const double static_limit = mu_s_ * fn, dynamic_limit = mu_d_ * fn;
        // The hysteresis and reversal test of the vector form.
        const bool sliding = trial_magnitude > static_limit ||
                             (h.sliding && trial_magnitude >= dynamic_limit && vt * stored >= 0.0);
        if (!sliding) {
            out.force = trial * t;
            h.spring = (spring + 0.5 * dt * vt) * t;
            if constexpr (track_energy) out.dissipated_viscous = gamma_t_ * vt * vt * dt;
        } else {
            [[maybe_unused]] const double energy_before = track_energy ? elastic_energy<2>(h.spring) : 0.0;
            const double direction = trial > 0.0 ? 1.0 : (trial < 0.0 ? -1.0 : 0.0);
            out.force = (dynamic_limit * direction) * t;                     // Eq. 29
            h.spring = (-(dynamic_limit / kt_) * direction + 0.5 * dt * vt) * t;  // Eq. 28, stored as above
            if constexpr (track_energy)  // as in the vector form
                out.dissipated_sliding = -dynamic_limit * direction * vt * dt - (elastic_energy<2>(h.spring) - energy_before);
        }
        h.sliding = sliding;
        h.touching = true;
        out.sliding = sliding;
        return out;
    }

    /// The time a contact first seen with this overlap has been touching: overlap / approach
    /// speed, at most one step (it did not touch at the last evaluation).
    static double time_in_contact(double overlap, double normal_velocity, double dt) {
        return overlap < -normal_velocity * dt ? overlap / -normal_velocity : dt;
    }

    /// The spring xi of the last evaluation, from the stored one, which runs v_t dt/2 ahead:
    /// exact for the predicted velocity that evaluation used, and with the velocity after the
    /// step's last kick second order (the two differ by O(dt^2)).
    template <int dim>
    Vec<dim> present_spring(const Vec<dim>& n, const Vec<dim>& relative_velocity, double dt, const History<dim>& h) const {
        if (!h.touching) return Vec<dim>::Zero();
        return in_tangent_plane(n, h.spring) - (0.5 * dt) * in_tangent_plane(n, relative_velocity);
    }

    /// The tangential force of the present state without advancing the spring: Eq. 26 with the
    /// spring of the last evaluation, capped at the Coulomb limit of the contact's current
    /// friction state. Analysis uses it; it is the force of the last evaluation to O(dt^2).
    template <int dim>
    Vec<dim> current_force(const Vec<dim>& n, const Vec<dim>& relative_velocity, double normal_force, double dt,
                           const History<dim>& h) const {
        const Vec<dim> trial =
            -kt_ * present_spring<dim>(n, relative_velocity, dt, h) - gamma_t_ * in_tangent_plane(n, relative_velocity);
        const double limit = (h.sliding ? mu_d_ : mu_s_) * std::max(normal_force, 0.0);
        const double magnitude = trial.norm();
        return magnitude > limit ? Vec<dim>(trial * (limit / magnitude)) : trial;
    }

    /// Takes back the half step the stored spring runs ahead, so that the next evaluation,
    /// at step dt_next, finds the spring of the last one (made with step dt_last): the engine
    /// calls it before evaluating the same instant again (a re-prepare, an imposed deformation),
    /// which would otherwise advance the spring a second time.
    template <int dim>
    void step_back(const Vec<dim>& n, const Vec<dim>& relative_velocity, double dt_last, double dt_next,
                   History<dim>& h) const {
        if (h.touching) h.spring -= (0.5 * (dt_last + dt_next)) * in_tangent_plane(n, relative_velocity);
    }

private:
    /// The part of `u` in the tangent plane of the contact normal n (Eq. 23, 24).
    template <int dim>
    static Vec<dim> in_tangent_plane(const Vec<dim>& n, const Vec<dim>& u) {
        return u - n * n.dot(u);
    }

    double kt_, gamma_t_, mu_s_, mu_d_;
};

/// Cundall-Strack friction between particles that do not rotate: the same spring, Coulomb limit,
/// hysteresis and energy books, driven by the relative velocity of the centres alone. For
/// studies that suppress rotation (what rolling contributes to strength and dilatancy) and for
/// blocks that slide. No torques are computed, and the scene stores no angular velocity, torque
/// or moment of inertia: a third less particle storage than with rotation.
class CundallStrackWithoutRotation : public CundallStrack {
public:
    using CundallStrack::CundallStrack;
    static constexpr bool needs_rotation = false;
};

}  // namespace micromacro
