// The Hertz-Mindlin law (contact/hertz_mindlin.hpp) run by the engine, in 2D and 3D: the Hertz
// contact duration in closed form, the restitution asked for at every impact speed, the spin a
// sliding oblique impact leaves (Coulomb's impulse, closed form), the second-order convergence of
// a sticking Mindlin spring, and the tangent stiffnesses the averages receive.
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <limits>
#include <numbers>

#include "micromacro/contact/hertz_mindlin.hpp"
#include "micromacro/engine/collision_probe.hpp"
#include "micromacro/engine/snapshot.hpp"
#include "support/scenes.hpp"

BOOST_AUTO_TEST_SUITE(physics_hertz_mindlin)  // the file's cases, run as the CTest test of this file's name

using namespace mmtest;

namespace {
constexpr double young = 1e8, poisson = 0.25;  // a soft material: overlaps of 1e-3 a at 0.1 m/s

double rel(double measured, double exact) { return std::abs(measured / exact - 1.0); }

/// The elastic Hertz collision of two particles of radius a and mass m at approach speed v:
/// delta_max = (5 m* v^2 / (4 k_n))^(2/5) and t_c = 2 (delta_max / v) int_0^1 (1 - u^(5/2))^(-1/2) du,
/// the integral sqrt(pi) Gamma(7/5) / Gamma(9/10).
double hertz_duration(double m, double a, double v) {
    const double e_star = young / (2.0 * (1.0 - poisson * poisson)), kn = 4.0 / 3.0 * e_star * std::sqrt(a / 2);
    const double delta_max = std::pow(5.0 * (m / 2) * v * v / (4.0 * kn), 0.4);
    return 2.0 * delta_max / v * std::sqrt(std::numbers::pi) * std::tgamma(1.4) / std::tgamma(0.9);
}
}  // namespace

BOOST_AUTO_TEST_CASE(restitution_map_inverts) {
    BOOST_TEST(mm::HertzMindlin::restitution_for_damping(0.0) == 1.0, boost::test_tools::tolerance(1e-8));
    for (double e : {0.2, 0.5, 0.9, 0.99}) {
        const double alpha = mm::HertzMindlin::damping_for_restitution(e);
        BOOST_TEST(alpha > 0.0);
        BOOST_TEST(std::abs(mm::HertzMindlin::restitution_for_damping(alpha) - e) < 1e-9);
    }
}

// overlap_for_force inverts the law's own elastic force, between particles (R* = a/2) and on a
// rigid wall (R* = a, E* doubled).
BOOST_AUTO_TEST_CASE(overlap_under_a_load) {
    const mm::HertzMindlin law(young, poisson, 0.5, 0.3);
    const double m = mm::sphere_mass(rho, a_mean), force = 0.04;
    for (const bool wall : {false, true}) {
        const double delta = law.overlap_for_force(force, wall ? a_mean : a_mean / 2, wall);
        const double rj = wall ? std::numeric_limits<double>::infinity() : a_mean;
        const mm::ContactKinematics<3> c{{mm::Vec<3>::UnitX(), delta, 0.0, mm::Vec<3>::Zero()}, a_mean, rj, 1 / m, wall ? 0.0 : 1 / m, 1e-7};
        BOOST_TEST(law.normal_force(c).total() == force, boost::test_tools::tolerance(1e-12));
    }
}

// t_c of the elastic Hertz contact in closed form, at two speeds (t_c ~ v^(-1/5)), and the speed
// restored; at t_c/200 velocity Verlet is within 1e-4.
BOOST_AUTO_TEST_CASE_TEMPLATE(hertz_contact_duration, D, Dims) {
    const mm::HertzMindlin law(young, poisson, 1.0, 0.0);
    const double m = mm::sphere_mass(rho, a_mean);
    for (double v : {0.01, 1.0}) {
        const double tc = hertz_duration(m, a_mean, v);
        const auto c = mm::measure_normal_collision<D::value>(law, m, a_mean, m, a_mean, v, tc / 200);
        BOOST_TEST_MESSAGE(D::value << "D v = " << v << ": t_c " << c.contact_duration << " s against " << tc << ", e "
                                    << c.restitution);
        BOOST_TEST(rel(c.contact_duration, tc) < 1e-4);
        BOOST_TEST(std::abs(c.restitution - 1.0) < 1e-4);
    }
}

// The damping of contact/hertz_mindlin.hpp gives the restitution asked for whatever the impact
// speed (over two decades, on equal and on unequal particles), within 2e-3 at t_c/200.
BOOST_AUTO_TEST_CASE_TEMPLATE(restitution_is_the_same_at_every_speed, D, Dims) {
    for (double e : {0.5, 0.9}) {
        const mm::HertzMindlin law(young, poisson, e, 0.0);
        for (double a2 : {a_mean, 0.5 * a_mean}) {
            const double m1 = mm::sphere_mass(rho, a_mean), m2 = mm::sphere_mass(rho, a2);
            for (double v : {0.01, 0.1, 1.0}) {
                const double dt = hertz_duration(m1, a_mean, v) / 400;
                const auto c = mm::measure_normal_collision<D::value>(law, m1, a_mean, m2, a2, v, dt);
                BOOST_TEST_MESSAGE(D::value << "D e = " << e << ", a2 = " << a2 << ", v = " << v << ": " << c.restitution);
                BOOST_TEST(std::abs(c.restitution - e) < 2e-3);
            }
        }
    }
}

// Sliding throughout (tan theta well above mu), the tangential force is mu f_n at every instant:
// an elastic impact (normal impulse m v_n between equal particles) spins the target at
// mu m v_n a / I = 2.5 mu v_n / a (sphere inertia, also the 2D default). That holds for an
// instantaneous impact; the normal turns while the particles touch, which changes the converged
// spin by a share of order v_t t_c / a: 1.8e-3 with E = 1e8 Pa, 2.8e-4 with the stiffer material
// taken here (t_c 6.3x shorter).
BOOST_AUTO_TEST_CASE_TEMPLATE(sliding_impact_gives_coulomb_impulse, D, Dims) {
    constexpr double mu_value = 0.05, speed = 0.5, b = 0.8e-3;
    const mm::HertzMindlin law(100 * young, poisson, 1.0, mu_value);
    const double m = mm::sphere_mass(rho, a_mean);
    const double v_n = speed * std::sqrt(1.0 - b * b / (4.0 * a_mean * a_mean));
    const double dt = hertz_duration(m, a_mean, v_n) / 200 / std::pow(100.0, 0.4);
    const auto got = mm::measure_oblique_impact<D::value>(law, m, a_mean, speed, b, dt);
    const double expected = 2.5 * mu_value * v_n / a_mean;
    BOOST_TEST_MESSAGE(D::value << "D spin " << got.target_spin.norm() << " rad/s against " << expected);
    BOOST_TEST(rel(got.target_spin.norm(), expected) < 1e-3);
}

// Sticking (mu = 5), elastic: the Mindlin spring carries the contact, and the spin's error
// against t_c/6400 falls at second order, 15x from t_c/50 to t_c/200 (first order: 4x). It is
// taken relative to v/a: the converged spin is nearly zero (the spring gives back what it took).
// With the normal dashpot (e < 1) its delta^(1/4) is not smooth where the contact begins and
// ends, and the errors stop falling regularly at about 1e-4 of v/a (measured: 8e-4, 3e-5, 1e-4
// at t_c/50, 100, 200 with e = 0.7), as the restitution's own error does above.
BOOST_AUTO_TEST_CASE_TEMPLATE(sticking_impact_converges_at_second_order, D, Dims) {
    constexpr double speed = 0.5, b = 0.8e-3;
    const mm::HertzMindlin law(young, poisson, 1.0, 5.0);
    const double m = mm::sphere_mass(rho, a_mean);
    const double tc = hertz_duration(m, a_mean, speed * std::sqrt(1.0 - b * b / (4.0 * a_mean * a_mean)));
    auto spin = [&](double steps) { return mm::measure_oblique_impact<D::value>(law, m, a_mean, speed, b, tc / steps).target_spin; };
    const auto reference = spin(6400);
    const double at50 = (spin(50) - reference).norm() / (speed / a_mean);
    const double at200 = (spin(200) - reference).norm() / (speed / a_mean);
    BOOST_TEST_MESSAGE(D::value << "D spin error " << at50 << " at t_c/50, " << at200 << " at t_c/200 (of v/a)");
    BOOST_TEST(at50 < 3e-4);
    BOOST_TEST(at50 / at200 > 8.0);
}

// The averages receive each contact's tangent stiffnesses: d f_n / d delta = 1.5 k_n delta^(1/2)
// (checked against a difference quotient of the law's own force) and k_t = 8 G* sqrt(R* delta),
// between particles and on a wall (R* = a, the rigid wall's E* and G* twice the pair's).
BOOST_AUTO_TEST_CASE_TEMPLATE(snapshot_has_each_contacts_stiffness, D, Dims) {
    constexpr int dim = D::value;
    using V = mm::Vec<dim>;
    const mm::HertzMindlin law(young, poisson, 0.5, 0.5);
    mm::BasicSimulation<dim, double, mm::HertzMindlin, mm::Walls<dim>, mm::VelocityVerlet, mm::BruteForce> sim(law);
    const double m = mm::sphere_mass(rho, a_mean), gap = 2e-6, wall_gap = 3e-6;
    V x1 = V::Zero(), x2 = V::Zero();
    x2[1] = 2 * a_mean - gap;  // above particle 0, out of the wall's reach
    sim.particles().add(x1, a_mean, m);
    sim.particles().add(x2, a_mean, m);
    V up = V::Zero();
    up[1] = 1.0;
    sim.walls().add(up, V(-(a_mean - wall_gap) * up));  // touches particle 0 from below
    sim.set_time_step(1e-7);
    sim.prepare();
    const auto s = mm::take_snapshot(sim);
    BOOST_TEST(s.contacts.size() == 2u);
    for (const auto& c : s.contacts) {
        const double delta = c.wall ? wall_gap : gap, radius = c.wall ? a_mean : a_mean / 2;
        mm::ContactKinematics<dim> k{{V::UnitX(), delta, 0.0, V::Zero()}, a_mean, c.wall ? INFINITY : a_mean, 1.0 / m,
                                     c.wall ? 0.0 : 1.0 / m, 0.0};
        auto force_at = [&](double d) { k.overlap = d; return law.normal_force(k).total(); };
        const double h = 1e-3 * delta, quotient = (force_at(delta + h) - force_at(delta - h)) / (2 * h);
        BOOST_TEST(rel(c.k, quotient) < 1e-6);
        BOOST_TEST(rel(c.kt, 8.0 * law.effective_shear(c.wall) * std::sqrt(radius * delta)) < 1e-12);
    }
}

BOOST_AUTO_TEST_SUITE_END()
