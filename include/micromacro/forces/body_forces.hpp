#pragma once
// Forces that act on each particle alone. Each policy adds to the force (and torque) arrays and,
// when energy is tracked, books what it dissipates (the BodyForce concept below: one apply() with
// what the engine hands every evaluation, a BodyForceStep); a policy with a potential reports it
// (potential_energy), and a drag names its decay rates (drag_rate, spin_drag_rate) for the
// time-step check. The engine applies them after the contact and wall forces, in the order the
// scene lists them. apply() and potential_energy() act on the first `count` particles: the
// engine passes the particles it computes, without the ghosts of a distributed run, whose forces
// and energies are their owners'.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "micromacro/core/affine_field.hpp"
#include "micromacro/core/dim_traits.hpp"
#include "micromacro/core/energy.hpp"
#include "micromacro/core/error.hpp"
#include "micromacro/particles/particles.hpp"

namespace micromacro {

/// A policy's default count: every particle.
inline constexpr std::size_t all_particles = std::numeric_limits<std::size_t>::max();

/// What the engine hands a body force at every evaluation.
template <int dim>
struct BodyForceStep {
    double dt = 0.0;                     ///< the time step, for the energy books
    AffineField<dim> flow{};             ///< the scene's mean flow: its walls' affine field, or the periodic cell's (zero at rest)
    std::size_t count = all_particles;   ///< act on the first `count` particles only (a distributed run's ghosts are their owners')
};

/// A body force: `apply<track_energy>(particles, books, step)` adds its forces (and torques) to
/// the first step.count particles and, with track_energy, books what it takes. Checked by the
/// engine for its dimension, rotation and storage precision.
template <class F, int dim, bool rot, class Real>
concept BodyForce = requires(const F& f, Particles<dim, rot, Real>& p, EnergyBooks& books, const BodyForceStep<dim>& step) {
    f.template apply<true>(p, books, step);
    f.template apply<false>(p, books, step);
};

/// Background damping, Eq. 30: f_i -= gamma_b v_i, and t_i -= gamma_r omega_i when particles rotate.
struct BackgroundDamping {
    double translational = 0.0;  ///< gamma_b (kg/s)
    double rotational = 0.0;     ///< gamma_r (kg m^2/s)

    BackgroundDamping() = default;
    BackgroundDamping(double gamma_b, double gamma_r) : translational(gamma_b), rotational(gamma_r) {
        detail::require_non_negative(gamma_b, "background damping gamma_b", "use 0 to switch it off");
        detail::require_non_negative(gamma_r, "rotational background damping gamma_r", "use 0 to switch it off");
    }

    /// The drag's decay rates of a particle's velocity and spin, gamma_b / m and gamma_r / I
    /// (1/s): the engine's time-step check (BasicSimulation::stable_time_step) adds them to the
    /// damping of the particle's contacts, and an explicit drag overshoots beyond dt = 1 / rate.
    double drag_rate(double inverse_mass) const { return translational * inverse_mass; }
    double spin_drag_rate(double inverse_inertia) const { return rotational * inverse_inertia; }

    template <bool track_energy, int dim, bool rot, class Real>
    void apply(Particles<dim, rot, Real>& p, EnergyBooks& books, const BodyForceStep<dim>& step) const {
        // One pass, raw pointers and local constants (through the members the compiler reloaded
        // them after every store). The power gamma |v|^2 is summed as |v|^2 and |omega|^2 apart,
        // two independent chains of additions instead of one running through both loops (perf had
        // the two loops at ~7% of the paper biaxial's loading, most of it on that chain).
        Vec<dim>* f = p.template get<field::Force>().data();
        const Vec<dim, Real>* v = p.template get<field::Velocity>().data();
        [[maybe_unused]] Angular<dim>* t = nullptr;
        [[maybe_unused]] const Angular<dim, Real>* w = nullptr;
        if constexpr (rot) {
            t = p.template get<field::Torque>().data();
            w = p.template get<field::AngularVelocity>().data();
        }
        if (translational == 0.0 && rotational == 0.0) return;  // listed but off: no pass
        const double gamma_b = translational, gamma_r = rotational;
        const std::size_t n = std::min(step.count, p.size());
        double v_sq = 0.0, w_sq = 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            f[i] -= gamma_b * convert<double>(v[i]);
            if constexpr (track_energy) v_sq += convert<double>(v[i]).squaredNorm();
            if constexpr (rot) {
                t[i] -= gamma_r * convert<double>(w[i]);
                if constexpr (track_energy) w_sq += DimTraits<dim>::squared_norm(convert<double>(w[i]));
            }
        }
        if constexpr (track_energy) books.dissipated_background += (translational * v_sq + rotational * w_sq) * step.dt;
    }
};

/// Eq. 30 measured against the box's mean flow instead of the lab: f_i -= gamma_b (v_i - u(x_i)),
/// t_i -= gamma_r (omega_i - the flow's spin), u the scene's mean flow (BodyForceStep::flow: the
/// walls' affine field, or a periodic cell's flow; in a still scene the lab frame, so Eq. 30 itself). A packing
/// that follows its walls affinely feels no drag, so a strong damping calms the oscillations a
/// moving wall drives without resisting the deformation itself; it does resist non-affine flow
/// such as a shear band.
struct AffineDamping {
    double translational = 0.0;  ///< gamma_b (kg/s)
    double rotational = 0.0;     ///< gamma_r (kg m^2/s)

    AffineDamping() = default;
    AffineDamping(double gamma_b, double gamma_r) : translational(gamma_b), rotational(gamma_r) {
        detail::require_non_negative(gamma_b, "affine damping gamma_b", "use 0 to switch it off");
        detail::require_non_negative(gamma_r, "rotational affine damping gamma_r", "use 0 to switch it off");
    }

    /// The drag's decay rates of a particle's velocity and spin, gamma_b / m and gamma_r / I
    /// (1/s): the engine's time-step check (BasicSimulation::stable_time_step) adds them to the
    /// damping of the particle's contacts, and an explicit drag overshoots beyond dt = 1 / rate.
    double drag_rate(double inverse_mass) const { return translational * inverse_mass; }
    double spin_drag_rate(double inverse_inertia) const { return rotational * inverse_inertia; }

    template <bool track_energy, int dim, bool rot, class Real>
    void apply(Particles<dim, rot, Real>& p, EnergyBooks& books, const BodyForceStep<dim>& step) const {
        if (translational == 0.0 && rotational == 0.0) return;  // listed but off: no pass
        const AffineField<dim>& field = step.flow;
        auto& f = p.template get<field::Force>();
        const auto& x = p.template get<field::Position>();
        const auto& v = p.template get<field::Velocity>();
        [[maybe_unused]] const Angular<dim> spin = field.spin();
        double power = 0.0;
        const std::size_t n = std::min(step.count, p.size());
        for (std::size_t i = 0; i < n; ++i) {
            const Vec<dim> velocity = convert<double>(v[i]), relative = velocity - field.velocity(convert<double>(x[i]));
            f[i] -= Vec<dim>(translational * relative);
            if constexpr (track_energy) power += translational * relative.dot(velocity);
            if constexpr (rot) {
                auto& t = p.template get<field::Torque>()[i];
                const Angular<dim> omega = convert<double>(p.template get<field::AngularVelocity>()[i]), turning = omega - spin;
                t -= Angular<dim>(rotational * turning);
                if constexpr (track_energy) power += rotational * DimTraits<dim>::dot(turning, omega);
            }
        }
        // What the drag takes from the particles, gamma (v - u) . v: gamma |v - u|^2 against the
        // relative motion, plus gamma (v - u) . u against the mean flow, which the walls' work
        // supplies (it is not zero where the motion is not affine); booked as dissipated, so the
        // energy books close.
        if constexpr (track_energy) books.dissipated_background += power * step.dt;
    }
};

/// Cundall's local non-viscous damping, as in PFC and YADE's NewtonIntegrator: each component of
/// the force and of the torque on a particle is reduced by alpha |F_k| against the particle's
/// velocity along it, F_k -= alpha |F_k| sign(v_k). It slows accelerating motion, not steady motion
/// under zero net force, and needs no mass or time scale. It acts on what the particle feels
/// from its contacts, walls and the body forces listed before it: list it last. The energy it
/// takes, alpha |F_k| |v_k| per component and unit time, is booked as background dissipation.
struct LocalDamping {
    double alpha = 0.0;  ///< 0 <= alpha < 1 (PFC's default 0.7 is a quasi-static relaxation)

    LocalDamping() = default;
    explicit LocalDamping(double alpha_) : alpha(alpha_) {
        if (!(alpha_ >= 0.0 && alpha_ < 1.0))
            detail::throw_input_error("local damping alpha = ", alpha_, " is outside [0, 1); it is the fraction of each force "
                                      "component taken against the motion (0.7 in PFC, 0.2 in YADE's examples)");
    }

    template <bool track_energy, int dim, bool rot, class Real>
    void apply(Particles<dim, rot, Real>& p, EnergyBooks& books, const BodyForceStep<dim>& step) const {
        if (alpha == 0.0) return;  // listed but off: no pass
        auto& f = p.template get<field::Force>();
        const auto& v = p.template get<field::Velocity>();
        double power = 0.0;
        // One component: reduced against the velocity along it; returns the power taken.
        auto damp = [&](double& force, Real velocity) {
            const double fk = force, vk = double(velocity);
            const double taken = alpha * std::abs(fk) * ((vk > 0.0) - (vk < 0.0));
            force = fk - taken;
            return taken * vk;
        };
        const std::size_t n = std::min(step.count, p.size());
        for (std::size_t i = 0; i < n; ++i) {
            for (int k = 0; k < dim; ++k) power += damp(f[i][k], v[i][k]);
            if constexpr (rot) {
                auto& t = p.template get<field::Torque>()[i];
                const auto& w = p.template get<field::AngularVelocity>()[i];
                if constexpr (dim == 2) power += damp(t, w);
                else
                    for (int k = 0; k < 3; ++k) power += damp(t[k], w[k]);
            }
        }
        if constexpr (track_energy) books.dissipated_background += power * step.dt;
    }
};

/// Uniform gravity: f_i += m_i g, potential energy -sum m_i g . x_i.
template <int dim>
struct Gravity {
    Vec<dim> g = Vec<dim>::Zero();

    template <bool track_energy, bool rot, class Real>
    void apply(Particles<dim, rot, Real>& p, EnergyBooks&, const BodyForceStep<dim>& step) const {
        auto& f = p.template get<field::Force>();
        const auto& m = p.template get<field::Mass>();
        const std::size_t n = std::min(step.count, p.size());
        for (std::size_t i = 0; i < n; ++i) f[i] += double(m[i]) * g;
    }
    template <bool rot, class Real>
    double potential_energy(const Particles<dim, rot, Real>& p, std::size_t count = all_particles) const {
        double u = 0.0;
        const std::size_t n = std::min(count, p.size());
        for (std::size_t i = 0; i < n; ++i) u -= double(p.mass()[i]) * g.dot(convert<double>(p.position()[i]));
        return u;
    }
};

}  // namespace micromacro
