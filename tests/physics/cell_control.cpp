// An element test's drive (engine/cell_control.hpp): a strain path is followed to the integrator's
// round-off whatever the other components do, the cell's lattice is the deformation gradient
// times the starting one, and a stress servo brings a gas to a jammed packing at the target
// pressure and holds it there; 2D and 3D.
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <random>

#include <micromacro/engine/cell_control.hpp>

#include "support/expect_error.hpp"
#include "support/scenes.hpp"

BOOST_AUTO_TEST_SUITE(physics_cell_control)  // the file's cases, run as the CTest test of this file's name

using namespace mmtest;

namespace {
template <int dim>
using Matrix = Eigen::Matrix<double, dim, dim>;
template <int dim>
using Cell = mm::Simulation<dim, mm::FrictionalLinear, mm::NoWalls, mm::VelocityVerlet, mm::LinkedCells, mm::AffineDamping>;

// A periodic gas of radii 0.5-1 mm at a volume fraction near 0.5 (2D) or 0.3 (3D), at rest.
template <int dim>
Cell<dim> gas(std::size_t n, unsigned seed) {
    const double L = dim == 2 ? 0.03 : 0.0085;
    const auto p = random_packing<dim>(n, 0.5e-3, 1.0e-3, L, seed, false, true);
    const double tc = mm::contact_duration(k, gamma0, mm::sphere_mass(rho, 0.5e-3) / 2);
    Cell<dim> sim(mm::FrictionalLinear{mm::LinearSpringDashpot(k, gamma0), mm::CundallStrack(0.2 * k, 0.2 * gamma0, 0.5)},
                  periodic_box<dim>(L), {}, {}, {}, mm::AffineDamping(mm::sphere_mass(rho, 0.75e-3) / (20 * tc), 0.0));
    for (std::size_t i = 0; i < p.x.size(); ++i) sim.particles().add(p.x[i], p.r[i], mm::sphere_mass(rho, p.r[i]));
    sim.set_time_step(tc / 50);
    return sim;
}
}  // namespace


// Prescribed paths on every component at once (a compression with shears of every axis pair):
// F_ik reaches each path's value at the end to round-off, and the lattice is F times the start.
BOOST_AUTO_TEST_CASE_TEMPLATE(strain_paths_are_followed, D, Dims) {
    constexpr int dim = D::value;
    auto sim = gas<dim>(100, 3);
    const double T = 2000 * sim.time_step();
    mm::CellControl<dim> control(0.0, 1.0);
    const auto path = [T](double amplitude) { return [=](double t) { return amplitude * std::sin(0.5 * M_PI * t / T); }; };
    for (int a = 0; a < dim; ++a) control.strain_path(a, a, path(-0.02 * (a + 1)));
    control.strain_path(0, dim - 1, path(0.4));
    if constexpr (dim == 3) control.strain_path(0, 1, path(-0.2)).strain_path(1, 2, path(0.3));
    const Matrix<dim> start = sim.domain().lattice();
    control.run(sim, 2000);
    const Matrix<dim> F = control.deformation();
    BOOST_TEST(control.time() == T, boost::test_tools::tolerance(1e-12));
    for (int a = 0; a < dim; ++a) BOOST_TEST(F(a, a) == 1.0 - 0.02 * (a + 1), boost::test_tools::tolerance(1e-9));
    BOOST_TEST(F(0, dim - 1) == 0.4, boost::test_tools::tolerance(1e-9));
    if constexpr (dim == 3) {
        BOOST_TEST(F(0, 1) == -0.2, boost::test_tools::tolerance(1e-9));
        BOOST_TEST(F(1, 2) == 0.3, boost::test_tools::tolerance(1e-9));
    }
    const Matrix<dim> expected = F * start;  // no tilt passed half a period: nothing re-based
    BOOST_TEST((sim.domain().lattice() - expected).norm() <= 1e-12 * expected.norm());
}

// What a servo reads (read: straight from the contacts) is the full average's (measure: through a
// snapshot): the same stress to the bit, contact and kinetic parts, in a cell compressed and
// sheared while it moves; each stiffness entry C^n_ikik + C^t_ikik to round-off.
BOOST_AUTO_TEST_CASE_TEMPLATE(a_servo_reads_the_averaged_stress_and_stiffness, D, Dims) {
    constexpr int dim = D::value;
    auto sim = gas<dim>(200, 7);
    auto control = mm::CellControl<dim>::following_stiffness(50 * sim.time_step(), 20.0);
    control.pressure(dim == 2 ? 1000.0 : 1e6);
    control.run(sim, 20000);
    control.rate(0, dim - 1, 5.0);
    control.run(sim, 3000);  // the cell moves: the kinetic stress is measured against its flow
    const auto m = control.measure(sim);
    const auto r = control.read(sim);
    BOOST_TEST_REQUIRE(m.contacts > 30u);
    BOOST_TEST(m.stress_kinetic.norm() > 0.0);
    BOOST_TEST(std::abs(m.stress(0, dim - 1)) > 0.0);
    for (int i = 0; i < dim; ++i)
        for (int k = 0; k < dim; ++k) {
            BOOST_TEST(r.stress(i, k) == m.stress(i, k), i << k);
            const double C = m.stiffness_normal(i, k, i, k) + m.stiffness_tangential(i, k, i, k);
            BOOST_TEST(std::abs(r.stiffness(i, k) - C) <= 1e-13 * C, i << k << ": " << r.stiffness(i, k) << " against " << C);
        }
}

// A gas compressed by the pressure servo ends jammed at the target pressure, each normal stress
// at it and the shear stresses near zero, the particles nearly at rest.
BOOST_TEST_DECORATOR(*boost::unit_test::label("long"))
BOOST_AUTO_TEST_CASE_TEMPLATE(pressure_servo_jams_a_gas_at_the_target, D, Dims) {
    constexpr int dim = D::value;
    auto sim = gas<dim>(dim == 2 ? 300 : 250, 5);
    const double p = dim == 2 ? 1000.0 : 1e6;  // N/m, Pa: overlaps about 1% of a radius
    const double max_rate = dim == 2 ? 50.0 : 20.0;
    mm::CellControl<dim> control(4 * max_rate / p, max_rate);
    control.pressure(p);
    control.run(sim, dim == 2 ? 100000 : 80000);
    const auto m = control.measure(sim);
    BOOST_TEST_MESSAGE(dim << "D: pressure " << m.pressure << " for " << p << ", volume fraction " << m.volume_fraction
                           << ", coordination " << m.coordination << ", stress\n" << m.stress);
    for (int a = 0; a < dim; ++a) BOOST_TEST(m.stress(a, a) == p, boost::test_tools::tolerance(2e-3));  // measured 2e-4
    for (int a = 0; a < dim; ++a)
        for (int b = a + 1; b < dim; ++b) BOOST_TEST(std::abs(m.stress(a, b) + m.stress(b, a)) < 0.004 * p);
    BOOST_TEST(m.stress_kinetic.norm() < 1e-4 * p);
    BOOST_TEST(m.coordination > (dim == 2 ? 3.0 : 4.0));
}

// The servo whose gain follows the averaged stiffness brings the gas to rest at its target at
// pressures a hundred times apart with one setting (a constant gain fit for one is too slow or
// unstable at the other): each normal stress within 2e-3 of p, no shear stress, no motion left.
BOOST_TEST_DECORATOR(*boost::unit_test::label("long"))
BOOST_AUTO_TEST_CASE_TEMPLATE(a_servo_following_the_stiffness_jams_a_gas_at_any_pressure, D, Dims) {
    constexpr int dim = D::value;
    for (const double p_over_k : {1e-2, 1e-4}) {
        auto sim = gas<dim>(dim == 2 ? 300 : 250, 5);
        const double p = dim == 2 ? p_over_k * k : p_over_k * k / 1.5e-3;  // N/m, Pa (d = 1.5 mm)
        auto control = mm::CellControl<dim>::following_stiffness(50 * sim.time_step(), 20.0);  // t_c
        control.pressure(p);
        const auto at_rest = [&](const mm::MicroMacro<dim>& m) {
            bool rest = m.stress_kinetic.norm() < 1e-4 * p;
            for (int a = 0; a < dim; ++a) {
                rest = rest && std::abs(m.stress(a, a) / p - 1) < 2e-3;
                for (int b = a + 1; b < dim; ++b) rest = rest && std::abs(m.stress(a, b) + m.stress(b, a)) < 0.004 * p;
            }
            return rest;
        };
        std::size_t steps = 0;
        for (; steps < 400000 && !at_rest(control.measure(sim)); steps += 5000) control.run(sim, 5000);
        const auto m = control.measure(sim);
        BOOST_TEST_MESSAGE(dim << "D, p/k " << p_over_k << ": at rest after " << steps << " steps, pressure " << m.pressure << " for "
                               << p << ", volume fraction " << m.volume_fraction << ", coordination " << m.coordination);
        BOOST_TEST(at_rest(m), dim << "D, p/k " << p_over_k << ": stress\n" << m.stress << "\nkinetic " << m.stress_kinetic.norm());
    }
}

BOOST_AUTO_TEST_CASE(bad_components_are_refused) {
    mm::CellControl<3> control(1.0, 1.0);
    expect_error([&] { control.rate(2, 1, 1.0); }, {"component (2, 1)", "0 <= i <= k < 3"});
    expect_error([&] { control.stress(0, 3, 1.0); }, {"component (0, 3)"});
    expect_error([&] { control.rate(0, 1, std::nan("")); }, {"rate of component (0, 1)", "finite"});
    expect_error([&] { mm::CellControl<2>(-1.0, 1.0); }, {"gain", "-1"});
    expect_error([&] { mm::CellControl<2>(1.0, 0.0); }, {"largest strain rate"});
    expect_error([&] { mm::CellControl<2>(1.0, 1.0, 0); }, {"interval is 0 steps"});
    expect_error([&] { mm::CellControl<2>::following_stiffness(0.0, 1.0); }, {"relaxation time", "0"});
}

BOOST_AUTO_TEST_SUITE_END()
