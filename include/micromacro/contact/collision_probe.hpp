#pragma once
// Measures what a normal collision really does in the simulation, for comparison with the
// closed form of Eq. 22: two particles meet head-on, and the probe records how long the overlap
// stays positive and the ratio of the relative normal speeds after and before.
#include <cmath>

#include "micromacro/contact/contact_law.hpp"
#include "micromacro/core/simulation.hpp"
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
/// storage precision (see BasicSimulation; float is accepted however coarse).
template <int dim, class Integrator = VelocityVerlet, class Real = double>
CollisionMeasurement measure_normal_collision(const LinearSpringDashpot& law, double m1, double a1, double m2,
                                              double a2, double v, double dt, double entry_phase = 0.5) {
    detail::require_positive(v, "approach speed", "the particles must approach");
    if (!(entry_phase > 0.0 && entry_phase <= 1.0))
        detail::throw_input_error("entry phase ", entry_phase, " is outside (0, 1]; it is the fraction of a step in contact");
    using Law = ContactLaw<LinearSpringDashpot>;
    BasicSimulation<dim, Real, Law, NoWalls, Integrator, BruteForce> sim(Law{law});
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

    const double tc_guess = contact_duration(law.stiffness(), law.damping(), reduced_mass(m1, m2));
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

}  // namespace micromacro
