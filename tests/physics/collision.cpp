// Binary normal collisions against Eq. 22: contact duration t_c = pi/omega and restitution
// e = exp(-eta_0 t_c), in 2D and 3D, and the convergence order of both integrators.
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <limits>
#include <utility>

#include "support/scenes.hpp"

BOOST_AUTO_TEST_SUITE(physics_collision)  // the file's cases, run as the CTest test of this file's name

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

// Newton's third law to the last bit: a pair's force, torques and tangential spring do not depend
// on which of its two particles is numbered first. Two unequal spinning particles in an oblique
// impact (damped, sticking, then sliding at mu = 0.3), numbered both ways, follow the same
// trajectory and books bit for bit, in 2D and 3D, in an open box and across a periodic boundary:
// every step of the law is sign-symmetric (separation, normal, relative velocity and spring negate
// exactly, sums of two terms commute, rounding to nearest is symmetric under negation). A build
// with fused multiply-adds (MICROMACRO_FMA) fuses a_i w_i + a_j w_j one way or the other, so there
// the 3D rotation parts differ in the last bits (measured: up to 3 ulp of an angular velocity).
BOOST_AUTO_TEST_CASE_TEMPLATE(numbering_does_not_change_a_pair, D, Dims) {
    constexpr int dim = D::value;
    using V = mm::Vec<dim>;
    const double a1 = 1e-3, a2 = 0.7e-3, m1 = mm::sphere_mass(rho, a1), m2 = mm::sphere_mass(rho, a2);
    const double tc = mm::contact_duration(k, gamma0, m1 * m2 / (m1 + m2));
    for (const bool periodic : {false, true}) {
        BOOST_TEST_CONTEXT((periodic ? "across a periodic boundary" : "in an open box")) {
            const double L = 10e-3;
            auto run = [&](bool swapped) {
                const auto box = periodic ? periodic_box<dim>(L) : mm::Domain<dim>(V::Zero(), V::Constant(L), std::array<bool, dim>{});
                mm::Simulation<dim, mm::FrictionalLinear> sim(
                    mm::FrictionalLinear{mm::LinearSpringDashpot(k, gamma0), mm::CundallStrack(0.2 * k, 0.02, 0.3)}, box);
                V n = V::Zero(), t = V::Zero();  // the line of centres, and a tangent
                n[0] = 0.8, n[dim - 1] = 0.6;
                t[0] = -0.6, t[dim - 1] = 0.8;
                V x1 = V::Constant(0.5 * L);
                if (periodic) x1[0] = L - 0.5 * a1;  // the pair straddles x = L
                V x2 = x1 + (a1 + a2 - 1e-6) * n;    // just touching
                box.wrap(x2);
                V v1 = 0.3 * n + 0.2 * t, v2 = -0.2 * n - 0.1 * t;  // approaching, and shearing past each other
                v2[1] += 0.05;
                mm::Angular<dim> w1{}, w2{};
                if constexpr (dim == 2) w1 = 40.0, w2 = -15.0;
                else w1 = V(10.0, -30.0, 25.0), w2 = V(-5.0, 12.0, 0.0);
                const std::array<std::size_t, 2> slot = swapped ? std::array<std::size_t, 2>{1, 0} : std::array<std::size_t, 2>{0, 1};
                for (std::size_t number = 0; number < 2; ++number) {
                    const bool first = (slot[0] == number);
                    sim.particles().add(first ? x1 : x2, first ? a1 : a2, first ? m1 : m2);
                    sim.particles().velocity()[number] = first ? v1 : v2;
                    sim.particles().template get<mm::field::AngularVelocity>()[number] = first ? w1 : w2;
                }
                sim.set_track_energy(true);
                sim.set_time_step(tc / 50);
                sim.run(150);  // three contact durations: through the contact
                std::vector<double> state;  // particle 1's, then particle 2's, whatever their numbers
                for (const std::size_t number : slot) {
                    const auto& p = sim.particles();
                    for (int c = 0; c < dim; ++c) state.push_back(p.position()[number][c]), state.push_back(p.velocity()[number][c]);
                    if constexpr (dim == 2) state.push_back(p.template get<mm::field::AngularVelocity>()[number]);
                    else for (int c = 0; c < 3; ++c) state.push_back(p.template get<mm::field::AngularVelocity>()[number][c]);
                }
                const auto& b = sim.books();
                for (double x : {b.dissipated_normal, b.dissipated_tangential, b.dissipated_sliding}) state.push_back(x);
                return state;
            };
            const auto one = run(false), other = run(true);
            BOOST_TEST_REQUIRE(one.size() == other.size());
            std::size_t differing = 0;
            for (std::size_t q = 0; q < one.size(); ++q) {
#ifdef MICROMACRO_FP_CONTRACT
                differing += !(std::abs(one[q] - other[q]) <= 1e-14 * std::abs(one[q]));
#else
                differing += (one[q] != other[q]);
#endif
            }
            BOOST_TEST(differing == 0u);
            BOOST_TEST(one[one.size() - 1] > 0.0);  // it slid
            BOOST_TEST(one[one.size() - 3] > 0.0);  // and the normal dashpot worked
        }
    }
}

BOOST_AUTO_TEST_SUITE_END()
