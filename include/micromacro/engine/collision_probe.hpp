#pragma once
// Measures what a collision really does in the simulation. Head-on, for comparison with the
// closed form of Eq. 22: how long the overlap stays positive and the ratio of the relative normal
// speeds after and before. Oblique, with friction: the spin and the tangential velocity it leaves,
// for the convergence of the tangential spring (no closed form: compare with a much smaller step).
#include <cmath>
#include <type_traits>

#include "micromacro/contact/contact_law.hpp"
#include "micromacro/engine/simulation.hpp"
#include "micromacro/neighbors/brute_force.hpp"

namespace micromacro {

struct CollisionMeasurement {
    double contact_duration;  ///< s, overlap > 0, zero crossings interpolated linearly
    double restitution;       ///< -(relative normal velocity after) / (before)
    std::size_t steps;        ///< steps simulated
};

/// Head-on collision of particles (m1, a1) and (m2, a2) approaching at relative speed v with time
/// step dt, in dimension dim, integrated by `Integrator`. No friction, no background damping.
/// The contact begins `entry_phase` (0..1) of a step before the fourth step ends: at coarse steps
/// the result depends on it (tests/physics/extremes.cpp derives by how much). `Real` is the
/// storage precision (see BasicSimulation; float is accepted however coarse). `law` is a contact
/// law (ContactLawModel) or a normal model alone (NormalModel, e.g. LinearSpringDashpot).
template <int dim, class Integrator = VelocityVerlet, class Real = double, class GivenLaw>
CollisionMeasurement measure_normal_collision(const GivenLaw& law, double m1, double a1, double m2, double a2, double v,
                                              double dt, double entry_phase = 0.5) {
    detail::require_positive(v, "approach speed", "the particles must approach");
    if (!(entry_phase > 0.0 && entry_phase <= 1.0))
        detail::throw_input_error("entry phase ", entry_phase, " is outside (0, 1]; it is the fraction of a step in contact");
    const auto contact_law = [&] {
        if constexpr (NormalModel<GivenLaw>) return ContactLaw<GivenLaw>{law};
        else return law;
    }();
    using Law = std::remove_const_t<decltype(contact_law)>;
    BasicSimulation<dim, Real, Law, NoWalls, Integrator, BruteForce> sim(contact_law);
    sim.allow_coarse_positions(true);
    sim.set_time_step(dt);
    Vec<dim> gap = Vec<dim>::Zero();
    gap[0] = a1 + a2 + (4.0 - entry_phase) * v * dt;  // contact begins between steps 3 and 4
    auto& p = sim.particles();
    p.add(Vec<dim>::Zero(), a1, m1);
    p.add(gap, a2, m2);
    p.velocity()[0][0] = v * m2 / (m1 + m2);
    p.velocity()[1][0] = -v * m1 / (m1 + m2);
    sim.set_skin(0.5 * std::min(a1, a2));
    auto overlap = [&] { return a1 + a2 - (convert<double>(p.position()[1]) - convert<double>(p.position()[0])).norm(); };

    // The contact duration at the law's stiffest (exact for a constant stiffness).
    const StiffnessBound stiffest = contact_law.stiffness_bound(a1 * a2 / (a1 + a2), reduced_mass(m1, m2));
    const double tc_guess = contact_duration(stiffest.normal_stiffness, stiffest.normal_damping, reduced_mass(m1, m2));
    const auto max_steps = static_cast<std::size_t>(20.0 * tc_guess / dt) + 100;
    double start = -1.0, end = -1.0, previous = overlap();
    sim.prepare();
    while (end < 0.0 && sim.steps_done() < max_steps) {
        sim.step();
        const double now = overlap();
        const double t_cross = sim.time() - dt * now / (now - previous);  // linear interpolation
        if (start < 0.0 && previous <= 0.0 && now > 0.0) start = t_cross;
        else if (start >= 0.0 && previous > 0.0 && now <= 0.0) end = t_cross;
        previous = now;
    }
    if (end < 0.0)
        throw SimulationError("measure_normal_collision: the particles did not separate within 20 contact durations");
    sim.step();  // leave the contact completely
    const double v_after = convert<double>(p.velocity()[1])[0] - convert<double>(p.velocity()[0])[0];
    return {end - start, v_after / v, sim.steps_done()};
}

/// What an oblique frictional impact leaves behind (3D vectors; in 2D the spin is along z and
/// the velocity's third component is zero).
struct ObliqueImpact {
    Vec<3> target_spin;     ///< angular velocity of the particle that was at rest, rad/s
    Vec<3> across;          ///< relative velocity v_1 - v_0 across the direction of flight (x), m/s
    std::size_t steps;      ///< steps simulated
};

/// Two equal particles (mass m, radius a, `law` with its friction): particle 0 at rest, particle 1
/// arriving along x at `speed` with impact parameter b, offset along y in 2D and along
/// (0, cos 30, sin 30) in 3D, where it also spins at `spin` rad/s about its direction of flight
/// (so the spring turns in its tangent plane). The surfaces meet `entry_phase` (0..1] of a step
/// before the fourth step ends; the run stops two contact durations after that (of the law's
/// stiffest contact, see ContactLawIn::stiffness_bound), or later once the particles have parted.
template <int dim, class Law, class Integrator = VelocityVerlet>
ObliqueImpact measure_oblique_impact(const Law& law, double m, double a, double speed, double b, double dt,
                                     double entry_phase = 0.5, double spin = 0.0) {
    detail::require_positive(speed, "approach speed", "the particles must approach");
    if (!(b >= 0.0 && b < 2.0 * a))
        detail::throw_input_error("impact parameter ", b, " is outside [0, 2a) = [0, ", 2.0 * a, "); the particles would miss");
    if (!(entry_phase > 0.0 && entry_phase <= 1.0))
        detail::throw_input_error("entry phase ", entry_phase, " is outside (0, 1]; it is the fraction of a step in contact");
    using V = Vec<dim>;
    BasicSimulation<dim, double, Law, NoWalls, Integrator, BruteForce> sim(law);
    sim.set_time_step(dt);
    V offset = V::Zero();
    if constexpr (dim == 2) offset[1] = b;
    else offset = b * V(0.0, std::sqrt(3.0) / 2, 0.5);
    const double touch_x = -std::sqrt(4.0 * a * a - b * b);  // where the surfaces meet
    const double meet = (4.0 - entry_phase) * dt;
    V start = offset;
    start[0] = touch_x - speed * meet;
    auto& p = sim.particles();
    p.add(V::Zero(), a, m);
    p.add(start, a, m);
    p.velocity()[1][0] = speed;
    if constexpr (dim == 3 && Law::needs_rotation) p.template get<field::AngularVelocity>()[1] = V(spin, 0.0, 0.0);
    sim.set_skin(0.5 * a);
    // The contact duration at the law's stiffest (exact for a constant stiffness); a softer
    // contact lasts longer, and the run goes on until the particles have parted.
    const StiffnessBound stiffest = law.stiffness_bound(a / 2, m / 2);
    const double tc = contact_duration(stiffest.normal_stiffness, stiffest.normal_damping, m / 2);
    const auto steps = static_cast<std::size_t>((meet + 2.0 * tc) / dt) + 2;
    sim.run(steps);
    for (std::size_t more = 0; sim.contact_count() != 0; ++more) {
        if (more > 100 * steps)
            throw SimulationError("measure_oblique_impact: the particles are still in contact 200 contact durations after they met");
        sim.step();
    }
    ObliqueImpact out{Vec<3>::Zero(), Vec<3>::Zero(), sim.steps_done()};
    if constexpr (Law::needs_rotation) {
        const auto w = p.template get<field::AngularVelocity>()[0];
        if constexpr (dim == 2) out.target_spin.z() = w;
        else out.target_spin = w;
    }
    const V dv = p.velocity()[1] - p.velocity()[0];
    out.across.template head<dim - 1>() = dv.template tail<dim - 1>();
    return out;
}

}  // namespace micromacro
