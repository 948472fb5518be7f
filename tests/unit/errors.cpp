// Every rejected input raises InputError with a message that names the offending value and the
// limit; a blow-up that the user allowed is stopped with a SimulationError naming step and particle.
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <limits>
#include <string>

#include "support/expect_error.hpp"
#include "support/scenes.hpp"

BOOST_AUTO_TEST_SUITE(unit_errors)  // the file's cases, run as the CTest test of this file's name

using namespace mmtest;

namespace {
const double not_a_number = std::numeric_limits<double>::quiet_NaN();
const double infinite = std::numeric_limits<double>::infinity();

const mm::FrictionlessLinear law{mm::LinearSpringDashpot(k, gamma0)};
}  // namespace

BOOST_AUTO_TEST_CASE_TEMPLATE(bad_particles, D, Dims) {
    constexpr int dim = D::value;
    using V = mm::Vec<dim>;
    mm::Particles<dim, true> p;
    expect_error([&] { p.add(V::Zero(), 0.0, 1.0); }, {"radius = 0", "> 0"});
    expect_error([&] { p.add(V::Zero(), -1e-3, 1.0); }, {"radius = -0.001"});
    expect_error([&] { p.add(V::Zero(), not_a_number, 1.0); }, {"radius = nan"});
    expect_error([&] { p.add(V::Zero(), 1e-3, 0.0); }, {"mass = 0", "> 0"});
    expect_error([&] { p.add(V::Zero(), 1e-3, -2.0); }, {"mass = -2"});
    V bad = V::Zero();
    bad[dim - 1] = not_a_number;
    expect_error([&] { p.add(bad, 1e-3, 1.0); }, {"position component " + std::to_string(dim - 1), "not finite"});
    bad[dim - 1] = infinite;
    expect_error([&] { p.add(bad, 1e-3, 1.0); }, {"inf"});
    BOOST_TEST(p.size() == 0u);  // nothing half-added
}

BOOST_AUTO_TEST_CASE_TEMPLATE(coincident_centres, D, Dims) {
    constexpr int dim = D::value;
    mm::Simulation<dim, mm::FrictionlessLinear> sim(law);
    sim.particles().add(mm::Vec<dim>::Constant(1e-3), 1e-3, 1e-5);
    sim.particles().add(mm::Vec<dim>::Constant(5e-3), 1e-3, 1e-5);
    sim.particles().add(mm::Vec<dim>::Constant(1e-3), 1e-3, 1e-5);
    sim.set_time_step(1e-7);
    expect_error([&] { sim.prepare(); }, {"particles 0 and 2", "coincident centres"});
}

BOOST_AUTO_TEST_CASE_TEMPLATE(time_step_above_stability_limit, D, Dims) {
    constexpr int dim = D::value;
    mm::Simulation<dim, mm::FrictionalLinear> sim(
        mm::FrictionalLinear{mm::LinearSpringDashpot(k, gamma0), mm::CundallStrack(0.2 * k, 0.2 * gamma0, 0.5)});
    const double m = mm::sphere_mass(rho, 0.5e-3);
    sim.particles().add(mm::Vec<dim>::Zero(), 0.5e-3, m);
    sim.particles().add(mm::Vec<dim>::Constant(3e-3), 0.5e-3, m);
    const double limit = sim.stable_time_step();
    // The bound is that of the lightest pair: below 2/omega, omega = sqrt(k / (m/2)).
    BOOST_TEST(limit < 2.0 / std::sqrt(k / (m / 2)));
    BOOST_TEST(limit > 0.2 * mm::contact_duration(k, gamma0, m / 2));
    sim.set_time_step(1.01 * limit);
    expect_error([&] { sim.prepare(); }, {"time step dt = ", "exceeds the stability limit", "use dt <="});
    sim.set_time_step(0.99 * limit);
    sim.prepare();  // fine
    expect_error([&] { sim.set_time_step(-1.0); }, {"time step dt = -1"});
    expect_error([&] { sim.set_time_step(not_a_number); }, {"time step dt = nan"});
    // A tangential stiffness whose oscillation overflows: no dt is stable (its limit is 0, not NaN).
    sim.law().tangential = mm::CundallStrack(1e308, 0.2 * gamma0, 0.5);
    BOOST_TEST(sim.stable_time_step() == 0.0);
    expect_error([&] { sim.prepare(); }, {"exceeds the stability limit 0 s"});
}

// A time step beyond the limit is refused with the oscillation that sets it and the fix for it:
// the normal spring, the tangential spring, the drag, or a stress-controlled wall whose damper
// (as the biaxial preparation's, p A / v, in a big box) is too strong for its mass.
BOOST_AUTO_TEST_CASE_TEMPLATE(the_refusal_names_what_sets_the_limit, D, Dims) {
    constexpr int dim = D::value;
    using V = mm::Vec<dim>;
    const double a = 0.5e-3, m = mm::sphere_mass(rho, a);
    auto refused = [](auto& sim, std::initializer_list<std::string> parts) {
        const mm::StabilityLimit limit = sim.stability_limit();
        BOOST_TEST(limit.seconds == sim.stable_time_step());
        sim.set_time_step(1.01 * limit.seconds);
        expect_error([&] { sim.prepare(); }, parts);
        sim.set_time_step(0.99 * limit.seconds);
        sim.prepare();
        return limit;
    };
    mm::Simulation<dim, mm::FrictionalLinear> pair(
        mm::FrictionalLinear{mm::LinearSpringDashpot(k, gamma0), mm::CundallStrack(0.2 * k, 0.2 * gamma0, 0.5)});
    pair.particles().add(V::Zero(), a, m);
    pair.particles().add(V::Constant(3e-3), a, m);
    BOOST_TEST((refused(pair, {"of the normal spring and dashpot of the lightest particles' contact; use dt <="}).cause ==
                mm::StabilityLimit::Cause::normal_spring));
    pair.law().tangential = mm::CundallStrack(5.0 * k, 0.2 * gamma0, 0.5);
    BOOST_TEST((refused(pair, {"of the tangential spring of the lightest particles' contact; use dt <="}).cause ==
                mm::StabilityLimit::Cause::tangential_spring));

    // A lone particle: no contact to limit it, only its drag (with partners, the drag damps their
    // springs too and the spring's limit is the tighter).
    mm::Simulation<dim, mm::FrictionlessLinear, mm::NoWalls, mm::VelocityVerlet, mm::LinkedCells, mm::BackgroundDamping> damped(
        law, {}, {}, {}, {}, mm::BackgroundDamping(1.0, 0.0));
    damped.particles().add(V::Zero(), a, m);
    BOOST_TEST((refused(damped, {"of the body forces' drag on the lightest particle; use dt <=", ", less drag"}).cause ==
                mm::StabilityLimit::Cause::drag));

    mm::Walls<dim> walls;
    for (int axis = 0; axis < dim - 1; ++axis) {
        walls.add_axis_aligned(axis, true, -0.05);
        walls.add_axis_aligned(axis, false, 0.05);
    }
    walls.add_axis_aligned(dim - 1, false, 2e-3, mm::StressControlled{20.0, 1e-6, 1e4});
    mm::Simulation<dim, mm::FrictionlessLinear, mm::Walls<dim>> box(law, {}, walls);
    box.particles().add(V::Zero(), a, m);
    const auto wall = refused(box, {"of stress-controlled wall " + std::to_string(2 * (dim - 1)) + " on one particle; use dt <=",
                                    "a heavier wall or a weaker damper"});
    BOOST_TEST((wall.cause == mm::StabilityLimit::Cause::stress_wall));
    BOOST_TEST(wall.wall == std::size_t(2 * (dim - 1)));
}

BOOST_AUTO_TEST_CASE(missing_time_step) {
    mm::Simulation<2, mm::FrictionlessLinear> sim(law);
    sim.particles().add(mm::Vec<2>::Zero(), 1e-3, 1e-5);
    expect_error([&] { sim.step(); }, {"no time step set"});
}

BOOST_AUTO_TEST_CASE(overdamped_contact_has_no_duration) {
    const double m12 = 1e-5;
    const double critical = 2.0 * std::sqrt(k * m12);
    expect_error([&] { mm::contact_duration(k, 1.01 * critical, m12); }, {"overdamped", "lower gamma_0 below"});
    expect_error([&] { mm::restitution(k, 1.01 * critical, m12); }, {"overdamped"});
    BOOST_TEST(mm::contact_duration(k, 0.99 * critical, m12) > 0.0);
    expect_error([&] { mm::damping_for_restitution(k, m12, 0.0); }, {"restitution e = 0"});
    expect_error([&] { mm::damping_for_restitution(k, m12, 1.5); }, {"restitution e = 1.5"});
    expect_error([&] { mm::LinearSpringDashpot(-1.0, 0.1); }, {"normal stiffness k = -1"});
    expect_error([&] { mm::LinearSpringDashpot(k, -0.1); }, {"gamma_0 = -0.1"});
}

BOOST_AUTO_TEST_CASE(friction_coefficients) {
    expect_error([&] { mm::CundallStrack(2e4, 0.02, 0.3, 0.5); }, {"mu_d = 0.5", "mu_s = 0.3", "mu_d <= mu_s"});
    expect_error([&] { mm::CundallStrack(0.0, 0.02, 0.5); }, {"k_t = 0", "Frictionless"});
    expect_error([&] { mm::CundallStrack(2e4, 0.02, -0.1); }, {"mu_s = -0.1"});
}

BOOST_AUTO_TEST_CASE_TEMPLATE(particle_outside_walls, D, Dims) {
    constexpr int dim = D::value;
    mm::Walls<dim> walls;
    walls.add_box(mm::Vec<dim>::Zero(), mm::Vec<dim>::Constant(0.01));
    mm::Simulation<dim, mm::FrictionlessLinear, mm::Walls<dim>> sim(law, {}, walls);
    sim.particles().add(mm::Vec<dim>::Constant(0.005), 1e-3, 1e-5);
    mm::Vec<dim> outside = mm::Vec<dim>::Constant(0.005);
    outside[0] = 0.012;
    sim.particles().add(outside, 1e-3, 1e-5);
    sim.set_time_step(1e-7);
    expect_error([&] { sim.prepare(); }, {"particle 1 starts outside wall 1", "0.002"});
}

BOOST_AUTO_TEST_CASE_TEMPLATE(periodic_box_too_short, D, Dims) {
    constexpr int dim = D::value;
    std::array<bool, dim> periodic{};
    periodic[0] = true;
    mm::Vec<dim> hi = mm::Vec<dim>::Constant(0.1);
    hi[0] = 3e-3;  // shorter than two interaction ranges (2 x (2 mm + skin))
    mm::Simulation<dim, mm::FrictionlessLinear> sim(law, mm::Domain<dim>(mm::Vec<dim>::Zero(), hi, periodic));
    sim.particles().add(mm::Vec<dim>::Constant(1e-3), 1e-3, 1e-5);
    sim.set_time_step(1e-7);
    expect_error([&] { sim.prepare(); }, {"periodic axis 0 is 0.003", "shorter than two interaction ranges"});
    expect_error([&] { mm::Domain<dim>(mm::Vec<dim>::Zero(), mm::Vec<dim>::Zero(), periodic); }, {"hi > lo"});
}

// An affine compression may not take a periodic box below two interaction ranges either (a
// packing compressed to a pressure, as examples/random_packing does, with too few particles for
// its radii): refused before anything moves, the scene as it was.
BOOST_AUTO_TEST_CASE_TEMPLATE(compressing_a_periodic_box_too_far_is_refused, D, Dims) {
    constexpr int dim = D::value;
    const double a = 1e-3, L = 8e-3;
    mm::Simulation<dim, mm::FrictionlessLinear> sim(law, mm::Domain<dim>::fully_periodic(mm::Vec<dim>::Zero(), mm::Vec<dim>::Constant(L)));
    sim.particles().add(mm::Vec<dim>::Constant(1e-3), a, mm::sphere_mass(rho, a));
    sim.particles().add(mm::Vec<dim>::Constant(4e-3), a, mm::sphere_mass(rho, a));
    sim.set_time_step(1e-7);
    sim.prepare();
    const double range = mm::interaction_range(a, sim.skin());  // 2 a + skin = 2.2 mm: the box may shrink to 4.4 mm
    const auto before = sim.particles().position();
    const auto F = [](double s) { return Eigen::Matrix<double, dim, dim>(Eigen::Matrix<double, dim, dim>::Identity() * s); };
    expect_error([&] { sim.deform_affinely(F(0.99 * 2.0 * range / L)); },
                 {"the deformation leaves periodic axis 0", "shorter than two interaction ranges", "deform less"});
    BOOST_TEST(sim.domain().length(0) == L);
    for (std::size_t i = 0; i < before.size(); ++i) BOOST_TEST(sim.particles().position()[i] == before[i]);
    sim.deform_affinely(F(1.01 * 2.0 * range / L));  // just enough room: fine
    BOOST_TEST(sim.domain().length(0) == 1.01 * 2.0 * range, boost::test_tools::tolerance(1e-12));
}

// The same limit while the cell deforms by its velocity gradient: the step that takes an axis
// below two interaction ranges stops with a SimulationError naming the time and the fix.
BOOST_AUTO_TEST_CASE_TEMPLATE(a_cell_compressed_by_its_flow_below_two_ranges_stops, D, Dims) {
    constexpr int dim = D::value;
    const double a = 1e-3, L = 8e-3;
    mm::Simulation<dim, mm::FrictionlessLinear> sim(law, mm::Domain<dim>::fully_periodic(mm::Vec<dim>::Zero(), mm::Vec<dim>::Constant(L)));
    sim.particles().add(mm::Vec<dim>::Constant(1e-3), a, mm::sphere_mass(rho, a));
    sim.set_time_step(1e-5);
    Eigen::Matrix<double, dim, dim> gradient = Eigen::Matrix<double, dim, dim>::Zero();
    gradient(0, 0) = -100.0;  // axis 0 shrinks by 0.1% per step: below 2 x 2.2 mm after about 600 steps
    sim.set_velocity_gradient(gradient);
    expect_error<mm::SimulationError>([&] { sim.run(2000); }, {"the cell's axis 0 has shrunk to", "shorter than two interaction ranges",
                                                              "stop the compression earlier"});
    BOOST_TEST(sim.domain().length(0) >= 0.99 * 2.0 * mm::interaction_range(a, sim.skin()));
}

BOOST_AUTO_TEST_CASE(bad_walls) {
    mm::Walls<2> walls;
    expect_error([&] { walls.add(mm::Vec<2>::Zero(), mm::Vec<2>::Zero()); }, {"normal has length 0"});
    expect_error([&] { walls.add_axis_aligned(0, true, 0.0, mm::StrainControlled{0.01, 0.0}); }, {"period = 0"});
    expect_error([&] { walls.add_axis_aligned(0, true, 0.0, mm::StressControlled{-1.0, 1.0, 1.0}); }, {"pressure = -1"});
    expect_error([&] { walls.add_axis_aligned(0, true, 0.0, mm::StressControlled{20.0, 0.0, 1.0}); }, {"mass = 0"});
    expect_error([&] { walls.add(mm::Vec<2>(1, 1), mm::Vec<2>::Zero(), mm::StressControlled{20.0, 1.0, 1.0}); },
                 {"not axis-aligned needs an explicit area"});
    BOOST_TEST(walls.size() == 0u);
    // A stress-controlled wall without opposite walls on the other axis has no area.
    walls.add_axis_aligned(0, false, 0.01, mm::StressControlled{20.0, 1.0, 1.0});
    mm::Simulation<2, mm::FrictionlessLinear, mm::Walls<2>> sim(law, {}, walls);
    sim.particles().add(mm::Vec<2>(0.005, 0.0), 1e-3, 1e-5);
    sim.set_time_step(1e-7);
    expect_error([&] { sim.run(2); }, {"area is undefined", "StressControlled::area"});
}

// A particle squeezed between two walls with dt = 1.5x the limit: the oscillation grows by a
// constant factor each step until the numbers overflow.
BOOST_AUTO_TEST_CASE_TEMPLATE(blow_up_is_reported, D, Dims) {
    constexpr int dim = D::value;
    mm::Walls<dim> walls;
    walls.add_axis_aligned(0, true, 0.0);
    walls.add_axis_aligned(0, false, 1.9e-3);
    mm::Simulation<dim, mm::FrictionlessLinear, mm::Walls<dim>> sim(law, {}, walls);
    mm::Vec<dim> x = mm::Vec<dim>::Zero();
    x[0] = 0.949e-3;
    sim.particles().add(x, 1e-3, mm::sphere_mass(rho, 1e-3));
    sim.allow_unstable_time_step(true);
    sim.set_time_step(1.5 * sim.stable_time_step());
    expect_error<mm::SimulationError>([&] { sim.run(100000); }, {"blew up at step", "particle 0", "reduce dt"});
    BOOST_TEST(sim.steps_done() < 100000u);
}

// A NaN that appears mid-run (here put into a velocity, as a user's own force or a bad restart
// could) stops the run at the next step with the particle named, in a scene with contacts:
// the pair loop counts a NaN pair as not touching, so the displacement check must catch it.
BOOST_AUTO_TEST_CASE_TEMPLATE(nan_mid_run_is_reported, D, Dims) {
    constexpr int dim = D::value;
    using Law = mm::FrictionalLinear;
    mm::Simulation<dim, Law> sim(Law{mm::LinearSpringDashpot(k, gamma0), mm::CundallStrack(0.2 * k, 0.02, 0.5)});
    for (int p = 0; p < 3; ++p) {
        mm::Vec<dim> x = mm::Vec<dim>::Zero();
        x[0] = p * 1.99e-3;
        sim.particles().add(x, 1e-3, mm::sphere_mass(rho, 1e-3));
    }
    sim.set_time_step(1e-7);
    sim.run(10);
    BOOST_TEST_REQUIRE(sim.contact_count() == 2u);
    sim.particles().velocity()[1][0] = std::numeric_limits<double>::quiet_NaN();
    expect_error<mm::SimulationError>([&] { sim.run(10); }, {"blew up at step 11", "particle 1", "reduce dt"});
}

BOOST_AUTO_TEST_SUITE_END()
