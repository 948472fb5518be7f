#pragma once
// Time integrators. An integrator orders the stages every scene offers:
//   kick_drift_kick(h1, dt, h2[, h0])
//                         [kick_force_change(h0), then] v += h1 F/m, x += dt v, v += h2 F/m
//                         (omega += (h1 + h2) T/I when particles rotate); walls move, time and
//                         the step count advance, neighbour lists refresh,
//   compute_forces()      all forces and torques at the current positions and velocities,
//   kick_force_change(h)  v += h (F - F_previous)/m, for integrators that keep F_previous.
// On entry to step() the forces belong to the current state; so they do on exit.
#include <cmath>
#include <concepts>
#include <cstddef>

namespace micromacro {

namespace detail {
/// The stages every scene offers its integrator (see above), as declarations only: what the
/// TimeIntegrator concept checks an integrator's step() and run() against.
struct StagesArchetype {
    void kick_drift_kick(double h1, double dt, double h2, double h0 = 0.0);
    void compute_forces();
    void kick_force_change(double h);
};
}  // namespace detail

/// An integrator: a name and order (for reports), whether it keeps the previous forces (the
/// engine then stores them), step() and run() over the stages, and the largest stable dt of a
/// damped oscillator x'' = -omega0^2 x - 2 eta x' under it (the engine's time-step check).
template <class I>
concept TimeIntegrator = requires(const I& i, detail::StagesArchetype& stages, double dt, std::size_t steps) {
    { I::name } -> std::convertible_to<const char*>;
    { I::order } -> std::convertible_to<int>;
    { I::keeps_previous_forces } -> std::convertible_to<bool>;
    { I::stability_limit(1.0, 0.0) } -> std::convertible_to<double>;
    i.step(stages, dt);
    i.run(stages, dt, steps);
};

/// Velocity Verlet (kick-drift-kick), second order, symplectic; the default.
///
/// Velocity-dependent forces (dashpots, background damping) need v at the new time, which Verlet
/// only knows after the forces. Evaluating them with the half-step velocity, as many DEM codes
/// do, makes damped collisions first order. Here they see the predicted v* = v_{n+1/2} +
/// (dt/2) a_n, and the second half kick is corrected by the force change: second order in the
/// restitution too (tests/physics/collision.cpp checks the order).
struct VelocityVerlet {
    static constexpr const char* name = "velocity-verlet";
    static constexpr int order = 2;
    static constexpr bool keeps_previous_forces = true;
    template <class Stages>
    void step(Stages& s, double dt) const {
        // v_{n+1/2}, x_{n+1}, predicted v_{n+1} = v_{n+1/2} + dt/2 a_n
        s.kick_drift_kick(0.5 * dt, dt, 0.5 * dt);
        s.compute_forces();             // a_{n+1}
        s.kick_force_change(0.5 * dt);  // v_{n+1} = v_{n+1/2} + dt/2 a_{n+1}
    }
    /// `steps` steps with each closing kick merged into the next step's pass (which also clears
    /// the force array): two passes over the particles per step instead of four, the same
    /// arithmetic.
    template <class Stages>
    void run(Stages& s, double dt, std::size_t steps) const {
        for (std::size_t k = 0; k < steps; ++k) {
            s.kick_drift_kick(0.5 * dt, dt, 0.5 * dt, k == 0 ? 0.0 : 0.5 * dt);
            s.compute_forces();
        }
        s.kick_force_change(0.5 * dt);
    }
    /// Largest stable dt for x'' = -omega0^2 x - 2 eta x' (derived from det(M + 1) = 0 of the
    /// one-step map; with the predicted velocity the damping acts like 2 eta of the plain scheme).
    /// Written as 2 / (sqrt(4 eta^2 + omega0^2) + 2 eta), the same number without the cancellation
    /// of 2 (sqrt(...) - 2 eta) / omega0^2: it holds for omega0 = 0 and is 0, never NaN, when a
    /// stiffness or damping overflows.
    static double stability_limit(double omega0, double eta) {
        return 2.0 / (std::hypot(2.0 * eta, omega0) + 2.0 * eta);
    }
};

/// Symplectic (semi-implicit) Euler: v_{n+1} = v_n + dt F(x_n, v_n)/m, x_{n+1} = x_n + dt v_{n+1}.
/// First order, symplectic (energy stays bounded without damping), one force array less.
struct SymplecticEuler {
    static constexpr const char* name = "symplectic-euler";
    static constexpr int order = 1;
    static constexpr bool keeps_previous_forces = false;
    template <class Stages>
    void step(Stages& s, double dt) const {
        s.kick_drift_kick(dt, dt, 0.0);
        s.compute_forces();
    }
    template <class Stages>
    void run(Stages& s, double dt, std::size_t steps) const {
        for (std::size_t k = 0; k < steps; ++k) step(s, dt);
    }
    /// Largest stable dt for x'' = -omega0^2 x - 2 eta x'.
    static double stability_limit(double omega0, double eta) {
        return 2.0 / (std::hypot(eta, omega0) + eta);  // = 2 (sqrt(eta^2 + omega0^2) - eta) / omega0^2, as above
    }
};

}  // namespace micromacro
