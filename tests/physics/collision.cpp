// Binary normal collisions against Eq. 22: contact duration t_c = pi/omega and restitution
// e = exp(-eta_0 t_c), in 2D and 3D, and the convergence order of both integrators.
#define BOOST_TEST_MODULE physics_collision
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <limits>
#include <utility>

#include "support/scenes.hpp"

using namespace mmtest;

namespace {
template <int dim, class Integrator = mm::VelocityVerlet>
mm::CollisionMeasurement collide(double m1, double a1, double m2, double a2, double gamma, double steps_per_tc) {
    const double tc = mm::contact_duration(k, gamma, mm::reduced_mass(m1, m2));
    return mm::measure_normal_collision<dim, Integrator>(mm::LinearSpringDashpot(k, gamma), m1, a1, m2, a2, 0.1,
                                                         tc / steps_per_tc);
}
double rel(double measured, double exact) { return std::abs(measured / exact - 1.0); }
}  // namespace

BOOST_AUTO_TEST_CASE_TEMPLATE(matches_eq22_at_tc_over_200, D, Dims) {
    // Equal mean particles, and an unequal pair (0.5 mm with 1.5 mm) from the paper's range.
    for (auto [a1, a2] : {std::pair{1e-3, 1e-3}, std::pair{0.5e-3, 1.5e-3}}) {
        const double m1 = mm::sphere_mass(rho, a1), m2 = mm::sphere_mass(rho, a2), m12 = mm::reduced_mass(m1, m2);
        const auto c = collide<D::value>(m1, a1, m2, a2, gamma0, 200);
        BOOST_TEST(rel(c.contact_duration, mm::contact_duration(k, gamma0, m12)) < 1e-3);
        BOOST_TEST(rel(c.restitution, mm::restitution(k, gamma0, m12)) < 1e-3);
    }
}

BOOST_AUTO_TEST_CASE_TEMPLATE(elastic_collision_restores_speed, D, Dims) {
    const double m = mm::sphere_mass(rho, a_mean);
    const auto c = collide<D::value>(m, a_mean, m, a_mean, 0.0, 200);
    BOOST_TEST(std::abs(c.restitution - 1.0) < 1e-9);  // symplectic + linear spring: exact up to round-off...
}

// The error must shrink by 2^order when dt is halved (ratio within 15% of the ideal).
BOOST_AUTO_TEST_CASE_TEMPLATE(velocity_verlet_is_second_order, D, Dims) {
    const double m = mm::sphere_mass(rho, a_mean), m12 = m / 2;
    const double tc = mm::contact_duration(k, gamma0, m12), e = mm::restitution(k, gamma0, m12);
    const auto coarse = collide<D::value>(m, a_mean, m, a_mean, gamma0, 100);
    const auto fine = collide<D::value>(m, a_mean, m, a_mean, gamma0, 200);
    const double ratio_e = std::abs(coarse.restitution - e) / std::abs(fine.restitution - e);
    const double ratio_t = std::abs(coarse.contact_duration - tc) / std::abs(fine.contact_duration - tc);
    BOOST_TEST_MESSAGE("Verlet error ratios: e " << ratio_e << ", t_c " << ratio_t);
    BOOST_TEST(std::abs(ratio_e - 4.0) < 0.6);
    BOOST_TEST(std::abs(ratio_t - 4.0) < 0.6);
}

BOOST_AUTO_TEST_CASE_TEMPLATE(symplectic_euler_is_first_order, D, Dims) {
    const double m = mm::sphere_mass(rho, a_mean), m12 = m / 2;
    const double e = mm::restitution(k, gamma0, m12);
    const auto coarse = collide<D::value, mm::SymplecticEuler>(m, a_mean, m, a_mean, gamma0, 200);
    const auto fine = collide<D::value, mm::SymplecticEuler>(m, a_mean, m, a_mean, gamma0, 400);
    const double ratio_e = std::abs(coarse.restitution - e) / std::abs(fine.restitution - e);
    BOOST_TEST_MESSAGE("symplectic Euler error ratio: e " << ratio_e);
    BOOST_TEST(std::abs(ratio_e - 2.0) < 0.3);
    BOOST_TEST(std::abs(fine.restitution - e) < 1e-2 * e);
}

BOOST_AUTO_TEST_CASE(helpers_invert_each_other) {
    const double m12 = mm::sphere_mass(rho, a_mean) / 2;
    for (double e : {0.999, 0.78, 0.5, 0.01}) {
        const double gamma = mm::damping_for_restitution(k, m12, e);
        BOOST_TEST(std::abs(mm::restitution(k, gamma, m12) - e) < 1e-12);
    }
    // The paper's parameters (Sec. 4): two 1 mm particles, t_c = 2.04e-5 s, e = 0.78 by Eq. 22.
    BOOST_TEST(std::abs(mm::contact_duration(k, gamma0, m12) - 2.04e-5) < 0.01e-5);
    BOOST_TEST(std::abs(mm::restitution(k, gamma0, m12) - 0.78) < 0.005);
    BOOST_TEST(mm::reduced_mass(2.0, std::numeric_limits<double>::infinity()) == 2.0);
}

// The stability limits of the integrators are those of their one-step maps: just below the
// limit a particle squeezed between two walls (so it never leaves its contacts) stays bounded,
// just above it the oscillation grows without bound.
BOOST_AUTO_TEST_CASE(stability_limits_are_sharp) {
    auto grows = [](auto integrator, double dt, double omega, double eta) {
        using I = decltype(integrator);
        using Law = mm::ContactLaw<mm::LinearSpringDashpot>;
        const double m = 1.0;
        mm::Walls<2> walls;
        walls.add_axis_aligned(1, true, 0.0);
        walls.add_axis_aligned(1, false, 1.0);
        // Two springs in parallel: m x'' = -2 k x - 2 gamma x', so k = m omega^2 / 2, gamma = eta m.
        mm::Simulation<2, Law, mm::Walls<2>, I, mm::BruteForce> sim(
            Law{mm::LinearSpringDashpot(0.5 * omega * omega * m, eta * m)}, {}, walls);
        const double offset = 1e-6;  // tiny, so the orbit stays in the linear range (|y - 0.5| < 0.5)
        sim.particles().add(mm::Vec<2>(0.0, 0.5 - offset), 1.0, m);
        sim.allow_unstable_time_step(true);
        sim.set_time_step(dt);
        // Stable near the limit the discrete orbit is an ellipse stretched by up to
        // 1/sqrt(1 - (omega dt/2)^2) ~ 5 times at 0.98; unstable, it grows like 1.5^steps.
        double amplitude = 0.0;
        sim.run(300, [&](const auto& s) { amplitude = std::max(amplitude, std::abs(s.particles().position()[0].y() - 0.5)); });
        return amplitude > 20 * offset;
    };
    for (double eta : {0.0, 0.05, 0.5}) {
        const double omega = 1.0;
        const double vv = mm::VelocityVerlet::stability_limit(omega, eta);
        const double se = mm::SymplecticEuler::stability_limit(omega, eta);
        BOOST_TEST(!grows(mm::VelocityVerlet{}, 0.98 * vv, omega, eta));
        BOOST_TEST(grows(mm::VelocityVerlet{}, 1.02 * vv, omega, eta));
        BOOST_TEST(!grows(mm::SymplecticEuler{}, 0.98 * se, omega, eta));
        BOOST_TEST(grows(mm::SymplecticEuler{}, 1.02 * se, omega, eta));
    }
    BOOST_TEST(std::abs(mm::VelocityVerlet::stability_limit(1.0, 0.0) - 2.0) < 1e-15);
    BOOST_TEST(std::abs(mm::VelocityVerlet::stability_limit(1.0, 0.5) - 2.0 * (std::sqrt(2.0) - 1.0)) < 1e-15);
    // Strong damping, where the textbook form 2 (sqrt(4 eta^2 + omega^2) - 2 eta) / omega^2 cancels:
    // the limit tends to 1 / (2 eta) for Verlet and 1 / eta for symplectic Euler.
    BOOST_TEST(mm::VelocityVerlet::stability_limit(1.0, 1e9) == 0.5e-9, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(mm::SymplecticEuler::stability_limit(1.0, 1e9) == 1e-9, boost::test_tools::tolerance(1e-12));
    // An overflowing stiffness or damping leaves nothing stable: 0, not NaN (which every dt <= limit
    // test would pass).
    const double inf = std::numeric_limits<double>::infinity();
    for (auto [omega, eta] : {std::pair{inf, 0.0}, std::pair{1.0, inf}}) {
        BOOST_TEST(mm::VelocityVerlet::stability_limit(omega, eta) == 0.0);
        BOOST_TEST(mm::SymplecticEuler::stability_limit(omega, eta) == 0.0);
    }
    // A frequency whose square overflows still has its limit 2 / omega.
    BOOST_TEST(mm::VelocityVerlet::stability_limit(1e160, 0.0) == 2e-160, boost::test_tools::tolerance(1e-12));
}
