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

/// The Cundall-Strack tangential spring of Eq. 23-29, in 2D and 3D.
template <int dim>
struct TangentialSpring {
    Vec<dim> spring = Vec<dim>::Zero();  ///< xi of Eq. 23-28
    bool sliding = false;                ///< Coulomb state, for the static/dynamic hysteresis
};

/// A contact's history as its other partner sees it, for when particles are renumbered and a
/// pair's two particles swap roles: the spring is odd under the swap (the relative velocity it
/// integrates and the force it gives change sign), the sliding state is shared.
inline NoHistory seen_from_partner(NoHistory h) { return h; }
template <int dim>
TangentialSpring<dim> seen_from_partner(const TangentialSpring<dim>& h) {
    return {Vec<dim>(-h.spring), h.sliding};
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

    template <int dim>
    double elastic_energy(const History<dim>& h) const {
        return 0.5 * kt_ * h.spring.squaredNorm();
    }

    /// Eq. 23-29. `normal_force` is f_n (positive = compressive); the tangential force is
    /// active only while f_n > 0, otherwise the Coulomb limit is zero and the spring resets.
    /// The spring in `h` is updated for the next step. `normal_velocity` is n . v_ij, which the
    /// normal law has used already; Eq. 24 takes it instead of projecting v_ij again (the
    /// rotational part of v_ij is perpendicular to n, so n . v_ij = n . (v_i - v_j)): one dot
    /// product less on the contact's longest chain of dependent operations. The 2D form needs
    /// only the component along the tangent and ignores it.
    ///
    /// Eq. 26 takes the spring at the present time, xi + v_t dt/2, the midpoint of its update
    /// Eq. 27. The stored xi is the displacement summed up to the previous evaluation, half a step
    /// behind: as printed, Eq. 26 lags the motion, which acts as a negative damping k_t dt/2 and
    /// makes an undamped sticking contact ring up by 1 + (pi/2) omega_t dt per period (8% at
    /// omega_t dt = 0.05; stable only for gamma_t > k_t dt/2). Centred, the spring's work over a
    /// step equals the change of its stored energy 1/2 k_t xi^2 (exactly while it sticks in a
    /// fixed tangent plane: (xi + v dt/2) . v dt = 1/2 |xi + v dt|^2 - 1/2 |xi|^2), the lag is
    /// gone, and an undamped contact keeps its amplitude (1 + 1e-4 per period at omega_t dt =
    /// 0.05). tests/physics/tangential.cpp, undamped_sticking_contact_keeps_its_energy.
    template <int dim, bool track_energy>
    MICROMACRO_INLINE TangentialForce<dim> force(const Vec<dim>& n, const Vec<dim>& relative_velocity, double normal_velocity,
                                                 double normal_force, double dt, History<dim>& h) const {
        if constexpr (dim == 2) return force_along_line<track_energy>(n, relative_velocity, normal_force, dt, h);
        using V = Vec<dim>;
        TangentialForce<dim> out;
        const V spring = h.spring - n * n.dot(h.spring);                         // Eq. 23
        const V vt = relative_velocity - n * normal_velocity;                    // Eq. 24
        const V trial = -kt_ * V(spring + (0.5 * dt) * vt) - gamma_t_ * vt;     // Eq. 26, centred (see above)
        const double fn = std::max(normal_force, 0.0);
        // Compared squared: the square root is needed only by a sliding contact.
        const double trial_sq = trial.squaredNorm(), static_limit = mu_s_ * fn, dynamic_limit = mu_d_ * fn;
        // Static until the trial force exceeds mu_s f_n; once sliding, static again when it drops
        // below mu_d f_n (the paper's hysteresis between static and dynamic friction) or when the
        // motion reverses and unloads the spring. A reversal lowers the trial force below mu_d f_n
        // by (gamma_t + k_t dt/2) |v_t|, which is small for small steps and no damping; the
        // reversal test does not rely on it: without it the reset of Eq. 28 could keep the force
        // pointing against the old motion.
        // Whatever the state, a trial force above mu_s f_n slides.
        const bool sliding = trial_sq > static_limit * static_limit ||
                             (h.sliding && trial_sq >= dynamic_limit * dynamic_limit && vt.dot(spring) >= 0.0);
        if (!sliding) {
            out.force = trial;
            h.spring = spring + vt * dt;                                         // Eq. 27
            if constexpr (track_energy) out.dissipated_viscous = gamma_t_ * vt.squaredNorm() * dt;
        } else {
            // h still holds the step's old spring here (read only where needed: computed for every
            // contact it costs a spilled register in the pair loop).
            [[maybe_unused]] const double energy_before = track_energy ? elastic_energy<dim>(h) : 0.0;
            const double limit = dynamic_limit, trial_magnitude = std::sqrt(trial_sq);
            const V t = trial_magnitude > 0.0 ? V(trial / trial_magnitude) : V(V::Zero());
            out.force = limit * t;                                               // Eq. 29
            h.spring = -(limit / kt_) * t;                                       // Eq. 28
            // Energy the step took out of the pair that the spring did not store.
            if constexpr (track_energy)
                out.dissipated_sliding = -out.force.dot(vt) * dt - (elastic_energy<dim>(h) - energy_before);
        }
        h.sliding = sliding;
        out.sliding = sliding;
        return out;
    }

    /// Eq. 23-29 in 2D, where the tangent plane is the line along t = (-n_1, n_0): the projections
    /// become the components along t, scalars, and the pair loop saves about a third of its
    /// arithmetic. The same physics as the vector form above to round-off (tests/physics/
    /// tangential.cpp compares the two on a 2D contact embedded in 3D).
    template <bool track_energy>
    MICROMACRO_INLINE TangentialForce<2> force_along_line(const Vec<2>& n, const Vec<2>& relative_velocity, double normal_force,
                                                          double dt, History<2>& h) const {
        TangentialForce<2> out;
        const Vec<2> t(-n.y(), n.x());
        const double spring = t.dot(h.spring);                        // Eq. 23: the spring's part in the new tangent
        const double vt = t.dot(relative_velocity);                    // Eq. 24
        const double trial = -kt_ * (spring + 0.5 * dt * vt) - gamma_t_ * vt;  // Eq. 26, centred as in 3D
        const double fn = std::max(normal_force, 0.0), trial_magnitude = std::abs(trial);
        const double static_limit = mu_s_ * fn, dynamic_limit = mu_d_ * fn;
        // The hysteresis and reversal test of the vector form.
        const bool sliding = trial_magnitude > static_limit ||
                             (h.sliding && trial_magnitude >= dynamic_limit && vt * spring >= 0.0);
        if (!sliding) {
            out.force = trial * t;
            h.spring = (spring + vt * dt) * t;                 // Eq. 27
            if constexpr (track_energy) out.dissipated_viscous = gamma_t_ * vt * vt * dt;
        } else {
            [[maybe_unused]] const double energy_before = track_energy ? elastic_energy<2>(h) : 0.0;
            const double direction = trial > 0.0 ? 1.0 : (trial < 0.0 ? -1.0 : 0.0);
            out.force = (dynamic_limit * direction) * t;        // Eq. 29
            h.spring = (-(dynamic_limit / kt_) * direction) * t;  // Eq. 28
            if constexpr (track_energy)
                out.dissipated_sliding = -dynamic_limit * direction * vt * dt - (elastic_energy<2>(h) - energy_before);
        }
        h.sliding = sliding;
        out.sliding = sliding;
        return out;
    }

    /// The tangential force of the present state without advancing the spring: the trial
    /// force of Eq. 26 capped at the Coulomb limit of the contact's current friction state.
    /// Analysis uses it; it differs from the force of the last step by O(k_t v_t dt).
    template <int dim>
    Vec<dim> current_force(const Vec<dim>& n, const Vec<dim>& relative_velocity, double normal_force,
                           const History<dim>& h) const {
        const Vec<dim> spring = h.spring - n * n.dot(h.spring);
        const Vec<dim> vt = relative_velocity - n * n.dot(relative_velocity);
        const Vec<dim> trial = -kt_ * spring - gamma_t_ * vt;
        const double limit = (h.sliding ? mu_d_ : mu_s_) * std::max(normal_force, 0.0);
        const double magnitude = trial.norm();
        return magnitude > limit ? Vec<dim>(trial * (limit / magnitude)) : trial;
    }

private:
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
