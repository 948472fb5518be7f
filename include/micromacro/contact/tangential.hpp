#pragma once
// Tangential contact models. A tangential model owns the per-contact state it needs (its
// History) and declares whether particles must rotate. `Frictionless` has neither, so a scene
// built with it stores no history and no rotational fields.
#include <algorithm>
#include <cmath>
#include <concepts>

#include "micromacro/contact/tangential_history.hpp"
#include "micromacro/core/dim_traits.hpp"
#include "micromacro/core/error.hpp"
#include "micromacro/core/inline.hpp"

namespace micromacro {

/// No tangential force: perfectly smooth particles.
struct Frictionless {
    static constexpr bool has_history = false;
    static constexpr bool needs_rotation = false;
    template <int dim>
    using History = NoHistory;
    double stiffness() const { return 0.0; }
    double damping() const { return 0.0; }
};

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
    /// The same friction with another spring and dashpot, for laws whose tangential stiffness
    /// changes with the overlap (HertzMindlin); unchecked, the caller computes valid ones.
    CundallStrack with_stiffness(double kt, double gamma_t) const {
        CundallStrack c = *this;
        c.kt_ = kt;
        c.gamma_t_ = gamma_t;
        return c;
    }
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
    /// Time stepping. The spring advances as the positions do: xi_{n+1} = xi_n + dt v_{n+1/2},
    /// with the half-step velocity of velocity Verlet. The tangential spring is then a leapfrog
    /// oscillator like the normal one: second order, symplectic (an undamped sticking contact
    /// neither grows nor decays at any stable dt), and its energy is a function of the
    /// positions. The engine evaluates forces with the predicted velocity v*_{n+1} = v_{n+1/2} +
    /// (dt/2) a_n (the dashpots need the velocity at the new time), and the kicks give v_{n+1/2} =
    /// v_{n-1/2} + dt a_n, so v*_{n+1} = (3 v_{n+1/2} - v_{n-1/2}) / 2 and the half-step velocity
    /// follows from the predicted one and the last step's: v_{n+1/2} = (2 v*_{n+1} + v_{n-1/2}) / 3,
    /// exact for any forces (in the contact's frame up to its rotation within a step). The last
    /// step's dt v_{n-1/2} is the spring's last advance, so the history keeps xi_n and
    /// xi_n + dt v_{n-1/2} / 3 (`ahead`), and xi_{n+1} = P(ahead) + (2/3) dt v*_t,{n+1} with P the
    /// projection of Eq. 23: one projection per contact, as for the spring alone. The dashpot
    /// sees v* (second order, like the normal dashpot). After a sliding step the spring sits at
    /// the Coulomb limit (Eq. 28) and the step's advance is kept as it moved.
    ///
    /// Cheaper schemes fail (docs/model.md; measured in tests/physics/tangential.cpp): the spring of the last
    /// step (Eq. 26 as printed) lags half a step, first order, and an undamped contact grows by
    /// (pi/2) omega_t dt per period; advancing by the mean of two predicted velocities is second
    /// order but grows by about (omega_t dt)^3 per period, several percent near the stability limit.
    ///
    /// A new contact has touched for part of a step only: xi = v*_t tau with tau = overlap /
    /// approach speed, the time since the surfaces met (at most dt). Taking half a step instead
    /// is right only on average over where in the step the contact began and leaves an error of
    /// order dt in every spring that follows from it. A contact first seen while not approaching
    /// was placed so and starts unloaded.
    ///
    /// A contact that opened within the last step gets the rest of its last evaluation's impulse
    /// from the engine (opening_correction).
    ///
    /// tests/physics/tangential.cpp checks the order on oblique impacts, the energy of an
    /// undamped sticking contact, the Coulomb limit and the hysteresis.
    template <int dim, bool track_energy>
    MICROMACRO_INLINE TangentialForce<dim> force(const Vec<dim>& n, const Vec<dim>& relative_velocity, double normal_velocity,
                                                 double normal_force, double overlap, double dt, History<dim>& h) const {
        if constexpr (dim == 2)
            return force_along_line<track_energy>(n, relative_velocity, normal_velocity, normal_force, overlap, dt, h);
        else
            return force_in_plane<dim, track_energy>(n, relative_velocity, normal_velocity, normal_force, overlap, dt, h);
    }

    /// Eq. 23-29 on vectors in the tangent plane (3D), as described at force().
    template <int dim, bool track_energy>
    MICROMACRO_INLINE TangentialForce<dim> force_in_plane(const Vec<dim>& n, const Vec<dim>& relative_velocity, double normal_velocity,
                                                          double normal_force, double overlap, double dt, History<dim>& h) const {
        using V = Vec<dim>;
        TangentialForce<dim> out;
        const V vt = relative_velocity - n * normal_velocity;                    // Eq. 24
        V base = V::Zero(), motion;
        double span;
        if (h.touching) [[likely]] {
            // xi_{n+1} = xi_n + dt v_{n+1/2} with dt v_{n+1/2} = (2 dt v*_{n+1} + dt v_{n-1/2}) / 3.
            base = h.ahead;
            span = (2.0 / 3.0) * dt;
        } else {
            span = time_in_contact(overlap, normal_velocity, dt);
        }
        const V spring = base - n * n.dot(base) + span * vt;                    // Eq. 23, 27: xi_{n+1}
        if (h.touching) [[likely]]
            motion = spring - h.spring;  // dt v_{n+1/2} (and the projection's change, which the next one removes)
        else
            motion = dt * vt;            // as if it had moved at v_t for the whole step
        const V trial = -kt_ * spring - gamma_t_ * vt;                           // Eq. 26
        const double fn = std::max(normal_force, 0.0);
        // Compared squared: the square root is needed only by a sliding contact.
        const double trial_sq = trial.squaredNorm(), static_limit = mu_s_ * fn, dynamic_limit = mu_d_ * fn;
        // Static until the trial force exceeds mu_s f_n; once sliding, static again when it drops
        // below mu_d f_n (the paper's hysteresis between static and dynamic friction) or when the
        // motion reverses and unloads the spring (v_t against the stored spring, which points
        // along the last slip). Whatever the state, a trial force above mu_s f_n slides.
        const bool sliding = trial_sq > static_limit * static_limit ||
                             (h.sliding && trial_sq >= dynamic_limit * dynamic_limit && vt.dot(h.spring) >= 0.0);
        if (!sliding) {
            out.force = trial;
            h.spring = spring;
            if constexpr (track_energy) out.dissipated_viscous = gamma_t_ * vt.squaredNorm() * dt;
        } else {
            const double limit = dynamic_limit, trial_magnitude = std::sqrt(trial_sq);
            const V t = trial_magnitude > 0.0 ? V(trial / trial_magnitude) : V(V::Zero());
            out.force = limit * t;                                               // Eq. 29
            const V at_limit = -(limit / kt_) * t;                               // Eq. 28
            // The work of the mean of the step's two spring forces over the step's displacement,
            // less what the spring stored (zero for a sticking step, exactly).
            if constexpr (track_energy) {
                const V stored = h.spring - n * n.dot(h.spring);  // Eq. 23
                out.dissipated_sliding = 0.5 * (kt_ * stored - out.force).dot(spring - stored) -
                                         (elastic_energy<dim>(at_limit) - elastic_energy<dim>(h.spring));
            }
            h.spring = at_limit;
            h.trial = static_cast<float>(trial_magnitude);
        }
        h.ahead = h.spring + (1.0 / 3.0) * motion;
        h.sliding = sliding;
        h.fresh = !h.touching;
        h.touching = true;
        out.sliding = sliding;
        return out;
    }

    /// Eq. 23-29 in 2D, where the tangent plane is the line along t = (-n_1, n_0) and the spring
    /// its component along t (TangentialSpring<2>): the projections of the vector form become
    /// nothing, and the pair loop saves about a third of its arithmetic. The same time stepping,
    /// Coulomb limit and books as the vector form; the two agree to round-off while the contact
    /// does not turn (tests/physics/tangential.cpp).
    template <bool track_energy>
    MICROMACRO_INLINE TangentialForce<2> force_along_line(const Vec<2>& n, const Vec<2>& relative_velocity, double normal_velocity,
                                                          double normal_force, double overlap, double dt, History<2>& h) const {
        TangentialForce<2> out;
        const Vec<2> t = tangent_of(n);
        const double vt = t.dot(relative_velocity);                    // Eq. 24
        double spring, motion;  // as in the vector form
        if (h.touching) [[likely]] {
            spring = h.ahead + (2.0 / 3.0) * dt * vt;                  // Eq. 23, 27: xi_{n+1}
            motion = spring - h.spring;
        } else {
            spring = time_in_contact(overlap, normal_velocity, dt) * vt;
            motion = dt * vt;
        }
        const double trial = -kt_ * spring - gamma_t_ * vt;            // Eq. 26
        const double fn = std::max(normal_force, 0.0), trial_magnitude = std::abs(trial);
        const double static_limit = mu_s_ * fn, dynamic_limit = mu_d_ * fn;
        // The hysteresis and reversal test of the vector form.
        const bool sliding = trial_magnitude > static_limit ||
                             (h.sliding && trial_magnitude >= dynamic_limit && vt * h.spring >= 0.0);
        if (!sliding) {
            out.force = trial * t;
            if constexpr (track_energy) out.dissipated_viscous = gamma_t_ * vt * vt * dt;
            h.spring = spring;
        } else {
            const double direction = trial > 0.0 ? 1.0 : (trial < 0.0 ? -1.0 : 0.0);
            const double force = dynamic_limit * direction;
            out.force = force * t;                                                     // Eq. 29
            if constexpr (track_energy) {  // as in the vector form
                const double stored = h.spring;
                out.dissipated_sliding = 0.5 * (kt_ * stored - force) * (spring - stored) -
                                         0.5 * (force * force / kt_ - kt_ * stored * stored);
            }
            h.spring = -force / kt_;                                                   // Eq. 28
            h.trial = static_cast<float>(trial_magnitude);
        }
        h.ahead = h.spring + (1.0 / 3.0) * motion;
        h.sliding = sliding;
        h.fresh = !h.touching;
        h.touching = true;
        out.sliding = sliding;
        return out;
    }

    /// The force to add, at the evaluation that finds a contact open, so that the contact's last
    /// evaluation (h, t_n) gets the impulse of the force until the opening, `s` (<= dt) after
    /// t_n; `normal_force` is f_n at t_n (the engine's estimate from the overlap and separation
    /// speed of now). A sample stands for half a step on either side of it, but a spring that
    /// still holds when the surfaces part drops to zero at the opening: as a plain sample it
    /// misses what the spring pushed after t_n + dt/2 or adds what it did not push after the
    /// opening, an error of order dt that depends on where in a step the contact opens. Applied
    /// a step late, the impulse is the same and the trajectory differs at O(dt^2).
    ///
    /// The model over the sample's half step back to the opening: the trial force held, the
    /// normal force falling linearly to zero at the opening, and the force capped at the Coulomb
    /// limit, so that it slides for the last `ramp` before the opening (mu_s f_n, then mu_d f_n).
    /// - If the contact slid at the evaluation before too, the force has followed mu_d f_n, and
    ///   velocity Verlet integrates it as it integrates the normal force's last samples: the
    ///   sample stands, no correction (changing it moves a contact that slides throughout off
    ///   mu_d times its normal impulse).
    /// - If the spring held until after the evaluation before's half-step point, the sample
    ///   becomes the mean of the model over its half step back to the opening.
    /// - In between, the two are blended linearly.
    /// docs/oblique-impacts.md measures what it buys: where the spring is loaded when the contact
    /// opens (mu = 5) the error falls at second order, 4.6e-4 at t_c/50 over every entry phase.
    template <int dim>
    Vec<dim> opening_correction(const Vec<dim>& n, const History<dim>& h, double normal_force, double s, double dt) const {
        const Vec<dim> last = -kt_ * present_spring<dim>(n, h);  // the last evaluation's force, less its dashpot
        const double applied = last.norm();
        if (!(applied > 0.0 && s > 0.0)) return Vec<dim>::Zero();
        // A sliding contact's force was mu_d f_n exactly, and its trial force was kept.
        const bool sliding = h.sliding && mu_d_ > 0.0;
        const double fn = sliding ? applied / mu_d_ : std::max(normal_force, 0.0);
        const double trial = sliding ? double(h.trial) : applied;
        return last * ((opening_force(trial, fn, std::min(s, dt), dt) - applied) / applied);
    }

private:
    // The size of the force of the model above, averaged over the last evaluation's share.
    double opening_force(double trial_magnitude, double fn, double s, double dt) const {
        const double limit_rate = mu_s_ * fn / s;  // the static limit's rise per unit time back from the opening
        if (trial_magnitude >= limit_rate * (s + dt)) return mu_d_ * fn;  // slid at the evaluation before too
        const double ramp = trial_magnitude / limit_rate, span = s + 0.5 * dt, sliding_rate = mu_d_ * fn / s;
        const double mean = (ramp >= span ? 0.5 * sliding_rate * span * span
                                          : trial_magnitude * (span - ramp) + 0.5 * sliding_rate * ramp * ramp) / dt;
        const double weight = std::min(1.0, (s + dt - ramp) / (0.5 * dt));
        return weight * mean + (1.0 - weight) * mu_d_ * fn;
    }

    /// The time a contact first seen with this overlap has been touching: overlap / approach
    /// speed, at most one step (it did not touch at the last evaluation). A contact first seen
    /// while not approaching was placed so (a prepared packing): it starts unloaded.
    static double time_in_contact(double overlap, double normal_velocity, double dt) {
        if (!(normal_velocity < 0.0)) return 0.0;
        return overlap < -normal_velocity * dt ? overlap / -normal_velocity : dt;
    }

public:
    /// The spring xi of the last evaluation, in the tangent plane of n.
    template <int dim>
    Vec<dim> present_spring(const Vec<dim>& n, const History<dim>& h) const {
        if constexpr (dim == 2)
            return h.spring * tangent_of(n);
        else
            return in_tangent_plane(n, h.spring);
    }

    /// The tangential force of the present state without advancing the spring: Eq. 26 with the
    /// spring of the last evaluation, capped at the Coulomb limit of the contact's current
    /// friction state. Analysis uses it; it is the force of the last evaluation to O(dt).
    template <int dim>
    Vec<dim> current_force(const Vec<dim>& n, const Vec<dim>& relative_velocity, double normal_force,
                           const History<dim>& h) const {
        const Vec<dim> trial = -kt_ * present_spring<dim>(n, h) - gamma_t_ * in_tangent_plane(n, relative_velocity);
        const double limit = (h.sliding ? mu_d_ : mu_s_) * std::max(normal_force, 0.0);
        const double magnitude = trial.norm();
        return magnitude > limit ? Vec<dim>(trial * (limit / magnitude)) : trial;
    }

    /// An imposed tangential displacement of the contact points (an affine deformation of the
    /// scene) at a contact with normal n: the spring takes it up, and so does where its next step
    /// starts.
    template <int dim>
    void displace(const Vec<dim>& n, const Vec<dim>& tangential_displacement, History<dim>& h) const {
        const Spring<dim> d = coordinates(n, tangential_displacement);
        h.spring += d;
        h.ahead += d;
    }

    /// Takes back the last evaluation's advance of the spring, so that evaluating the same instant
    /// again (a re-prepare, an imposed deformation; the engine calls this first) does not advance
    /// it twice. A contact that was new then is new again. Otherwise the relative acceleration a
    /// follows from the present velocity v and the half-step velocity v - (dt_last/2) a of the
    /// last step, (spring - previous) / dt_last; the history is set so that the next evaluation,
    /// with velocity v and step dt_next, finds the present spring and the half-step velocity
    /// v - (dt_next/2) a.
    template <int dim>
    void step_back(const Vec<dim>& n, const Vec<dim>& relative_velocity, double dt_last, double dt_next,
                   History<dim>& h) const {
        if (!h.touching) return;
        if (h.fresh) {
            h = History<dim>{};
            return;
        }
        const Spring<dim> v = velocity_coordinates(n, relative_velocity), spring = in_plane<dim>(n, h.spring);
        const Spring<dim> half_kick = (v - in_plane<dim>(n, Spring<dim>(3.0 * (h.ahead - h.spring))) / dt_last) * (dt_next / dt_last);
        // The re-evaluation's (2 dt v + motion) / 3 is then dt (v - half_kick).
        const Spring<dim> motion = dt_next * (v - 3.0 * half_kick);
        h.spring = spring - dt_next * (v - half_kick);
        h.ahead = h.spring + (1.0 / 3.0) * motion;
    }

private:
    /// The part of `u` in the tangent plane of the contact normal n (Eq. 23, 24).
    template <int dim>
    static Vec<dim> in_tangent_plane(const Vec<dim>& n, const Vec<dim>& u) {
        return u - n * n.dot(u);
    }

    /// How a history holds a spring: a number along the tangent in 2D, a vector in 3D.
    template <int dim>
    using Spring = decltype(History<dim>::spring);
    /// A tangential vector as a history holds it.
    template <int dim>
    static Spring<dim> coordinates(const Vec<dim>& n, const Vec<dim>& tangential) {
        if constexpr (dim == 2)
            return tangent_of(n).dot(tangential);
        else
            return tangential;
    }
    /// The tangential part of a velocity as a history holds a spring.
    template <int dim>
    static Spring<dim> velocity_coordinates(const Vec<dim>& n, const Vec<dim>& u) {
        if constexpr (dim == 2)
            return tangent_of(n).dot(u);
        else
            return in_tangent_plane(n, u);
    }
    /// A stored spring in the tangent plane of n: a 2D spring turns with the contact already.
    template <int dim>
    static Spring<dim> in_plane(const Vec<dim>& n, const Spring<dim>& s) {
        if constexpr (dim == 2)
            return s;
        else
            return in_tangent_plane(n, s);
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
