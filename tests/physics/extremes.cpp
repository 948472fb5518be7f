// Stability at the extremes: stiffness over eight decades, restitution from 0.999 to 0.01, and
// degenerate scenes (no particle, one particle, exactly touching, a particle in a wall corner).
#define BOOST_TEST_MODULE physics_extremes
#include <boost/test/unit_test.hpp>

#include <cmath>

#include "support/scenes.hpp"

using namespace mmtest;

// k from 1e1 to 1e9 N/m with dt = t_c/50 from the helper: the measured restitution and contact
// duration stay within 1e-3 of Eq. 22 (the relative error does not depend on k: time scales as
// sqrt(m/k), which the step follows).
BOOST_AUTO_TEST_CASE_TEMPLATE(stiffness_over_eight_decades, D, Dims) {
    const double m = mm::sphere_mass(rho, a_mean), m12 = m / 2;
    for (double stiffness = 1e1; stiffness <= 1e9 * 1.001; stiffness *= 10) {
        const double gamma = mm::damping_for_restitution(stiffness, m12, 0.78);
        const double tc = mm::contact_duration(stiffness, gamma, m12);
        const double v = 0.1 * std::sqrt(stiffness / 1e5);  // the same overlap (relative to a) at every k
        const auto c = mm::measure_normal_collision<D::value>(mm::LinearSpringDashpot(stiffness, gamma), m, a_mean, m, a_mean,
                                                              v, tc / 50);
        BOOST_TEST(std::abs(c.restitution / 0.78 - 1.0) < 1e-3, "k = " << stiffness);
        BOOST_TEST(std::abs(c.contact_duration / tc - 1.0) < 1e-3, "k = " << stiffness);
    }
}

// Damping from zero to just below critical: restitution 1 (elastic), 0.999 ... 0.01 at t_c/200.
BOOST_AUTO_TEST_CASE_TEMPLATE(damping_from_elastic_to_nearly_critical, D, Dims) {
    const double m = mm::sphere_mass(rho, a_mean), m12 = m / 2;
    for (double e : {1.0, 0.999, 0.9, 0.5, 0.1, 0.01}) {
        const double gamma = e < 1.0 ? mm::damping_for_restitution(k, m12, e) : 0.0;
        const double tc = mm::contact_duration(k, gamma, m12);
        const auto c = mm::measure_normal_collision<D::value>(mm::LinearSpringDashpot(k, gamma), m, a_mean, m, a_mean, 0.1, tc / 200);
        BOOST_TEST_MESSAGE(D::value << "D e = " << e << ": measured " << c.restitution);
        BOOST_TEST(std::abs(c.restitution - e) < 1e-3 * std::max(e, 0.1), "e = " << e);
    }
}

BOOST_AUTO_TEST_CASE_TEMPLATE(degenerate_scenes, D, Dims) {
    constexpr int dim = D::value;
    using V = mm::Vec<dim>;
    const mm::FrictionalLinear law{mm::LinearSpringDashpot(k, gamma0), mm::CundallStrack(0.2 * k, 0.2 * gamma0, 0.5)};
    {  // no particles: steps run, nothing happens
        mm::Simulation<dim, mm::FrictionalLinear> sim(law);
        sim.set_time_step(1e-7);
        sim.run(10);
        BOOST_TEST(sim.time() == 10 * 1e-7);
        BOOST_TEST(sim.contact_count() == 0u);
        BOOST_TEST(sim.energy().total() == 0.0);
    }
    {  // one particle moves freely and uniformly
        mm::Simulation<dim, mm::FrictionalLinear> sim(law);
        sim.particles().add(V::Zero(), a_mean, 1e-5);
        sim.particles().velocity()[0] = V::Constant(0.5);
        sim.set_time_step(1e-6);
        sim.run(1000);
        BOOST_TEST((sim.particles().position()[0] - V::Constant(0.5 * sim.time())).norm() < 1e-15);
    }
    {  // exactly touching: in contact with zero overlap counts as no force
        mm::Simulation<dim, mm::FrictionalLinear> sim(law);
        V x = V::Zero();
        x[0] = 2 * a_mean;
        sim.particles().add(V::Zero(), a_mean, 1e-5);
        sim.particles().add(x, a_mean, 1e-5);
        sim.set_time_step(1e-7);
        sim.run(5);
        BOOST_TEST(sim.particles().force()[0].norm() == 0.0);
        BOOST_TEST(sim.particles().position()[0].norm() == 0.0);
    }
    {  // a particle pressed into a wall corner: both walls push, along their normals
        mm::Walls<dim> walls;
        walls.add_axis_aligned(0, true, 0.0);
        walls.add_axis_aligned(1, true, 0.0);
        mm::Simulation<dim, mm::FrictionalLinear, mm::Walls<dim>> sim(law, {}, walls);
        V x = V::Constant(0.5);
        x[0] = x[1] = a_mean - 1e-6;  // 1 um into both walls
        sim.particles().add(x, a_mean, mm::sphere_mass(rho, a_mean));
        sim.set_time_step(1e-7);
        sim.prepare();
        const V f = sim.particles().force()[0];
        BOOST_TEST(std::abs(f[0] - k * 1e-6) < 1e-9 * k * 1e-6);
        BOOST_TEST(std::abs(f[1] - k * 1e-6) < 1e-9 * k * 1e-6);
        BOOST_TEST(sim.contact_count() == 2u);
        BOOST_TEST(std::abs(sim.walls()[0].force[0] + k * 1e-6) < 1e-9 * k * 1e-6);
    }
}
