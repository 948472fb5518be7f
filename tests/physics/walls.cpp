// Walls: the strain-controlled motion of Eq. 17, the stress-controlled wall of Eq. 18 against the
// damped-oscillator solution, and the energy the walls put in.
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <numbers>

#include "support/scenes.hpp"

BOOST_AUTO_TEST_SUITE(physics_walls)  // the file's cases, run as the CTest test of this file's name

using namespace mmtest;

namespace {
template <int dim>
using WallScene = mm::Simulation<dim, mm::FrictionlessLinear, mm::Walls<dim>, mm::VelocityVerlet, mm::BruteForce>;
}

// Eq. 17 for the top wall: z(t) = z_f + (z0 - z_f)/2 (1 + cos(omega t)) until omega t = pi, then z_f.
BOOST_AUTO_TEST_CASE_TEMPLATE(strain_controlled_wall_follows_eq17, D, Dims) {
    constexpr int dim = D::value;
    const int up = dim - 1;
    const double z0 = 0.09, zf = 0.072, T = 1e-3, pi = std::numbers::pi;
    mm::Walls<dim> walls;
    walls.add_axis_aligned(up, true, 0.0);
    walls.add_axis_aligned(up, false, z0, mm::StrainControlled{z0 - zf, T});
    WallScene<dim> sim(mm::FrictionlessLinear{mm::LinearSpringDashpot(k, gamma0)}, {}, walls);
    mm::Vec<dim> x = mm::Vec<dim>::Constant(0.01);
    x[up] = 0.01;
    sim.particles().add(x, 1e-3, mm::sphere_mass(rho, 1e-3));  // far from the moving wall
    sim.set_time_step(T / 1000 / 3);                          // T/2 is not a whole number of steps
    double worst = 0.0;
    bool stopped_exactly = true;
    sim.run(2000, [&](const auto& s) {
        const double t = s.time();
        const double z = s.walls()[1].coordinate();
        const double expected = 2.0 * pi * t / T <= pi ? zf + 0.5 * (z0 - zf) * (1.0 + std::cos(2.0 * pi * t / T)) : zf;
        worst = std::max(worst, std::abs(z - expected));
        if (2.0 * pi * t / T > pi) stopped_exactly &= (z == zf && s.walls()[1].speed == 0.0);
    });
    BOOST_TEST(worst < 1e-15);
    BOOST_TEST(stopped_exactly);
    BOOST_TEST(sim.walls()[0].coordinate() == 0.0);  // the fixed wall stays
    const double strain = 1.0 - sim.walls()[1].coordinate() / z0;
    BOOST_TEST(std::abs(strain - 0.2) < 1e-15);
}

// A stress-controlled wall pressed onto one immovable particle (mass 1e20 kg) is a damped
// oscillator: m_w d'' = p A - k d - gamma_w d', d = overlap, starting touching and at rest.
// Solution: d(t) = d_eq [1 - exp(-eta t)(cos(w t) + eta/w sin(w t))], d_eq = p A / k.
// The area A comes from the box: side walls at distance L (2D: A = L; 3D: A = L^2).
BOOST_AUTO_TEST_CASE_TEMPLATE(stress_controlled_wall_is_a_damped_oscillator, D, Dims) {
    constexpr int dim = D::value;
    const int up = dim - 1;
    const double a = 1e-3, L = 0.05, p = dim == 2 ? 20.0 : 400.0;
    const double A = std::pow(L, dim - 1);
    const double mw = 1e-3, omega0 = std::sqrt(k / mw), eta = 0.2 * omega0, gamma_w = 2.0 * mw * eta;
    mm::Walls<dim> walls;
    for (int axis = 0; axis < up; ++axis) {
        walls.add_axis_aligned(axis, true, -0.5 * L);
        walls.add_axis_aligned(axis, false, 0.5 * L);
    }
    const std::size_t top = walls.size();
    walls.add_axis_aligned(up, false, a, mm::StressControlled{p, mw, gamma_w});
    WallScene<dim> sim(mm::FrictionlessLinear{mm::LinearSpringDashpot(k, 0.0)}, {}, walls);
    sim.particles().add(mm::Vec<dim>::Zero(), a, 1e20);
    const double dt = 1e-3 / omega0;
    sim.set_time_step(dt);
    const double d_eq = p * A / k, omega = std::sqrt(omega0 * omega0 - eta * eta);
    double worst = 0.0;
    sim.run(static_cast<std::size_t>(20.0 / eta / dt), [&](const auto& s) {  // 20 decay times
        const double t = s.time();
        const double d = a - s.walls()[top].coordinate();
        const double exact = d_eq * (1.0 - std::exp(-eta * t) * (std::cos(omega * t) + eta / omega * std::sin(omega * t)));
        worst = std::max(worst, std::abs(d - exact));
    });
    BOOST_TEST_MESSAGE(dim << "D stress wall: max |d - exact| / d_eq = " << worst / d_eq);
    BOOST_TEST(worst < 2e-3 * d_eq);  // semi-implicit Euler, omega0 dt = 1e-3: first-order error
    // Settled where the particles' force balances the pressure: F = p A.
    const double push = -sim.walls()[top].force.dot(sim.walls()[top].normal);
    BOOST_TEST(std::abs(push / (p * A) - 1.0) < 1e-6);
    BOOST_TEST(std::abs(sim.walls()[top].speed) < 1e-6 * d_eq * omega0);
    // Books: pressure work = elastic energy + wall damping (+ wall kinetic energy, ~0 now).
    BOOST_TEST(sim.books().work_by_walls > 0.0);
    BOOST_TEST(std::abs(sim.energy_residual()) < 2e-3);
}

// With a following anchor (follow_time tau) the damper resists only changes of the wall's
// velocity: a free wall launched at v0 neither stops (as under Eq. 18) nor keeps v0; m v + gamma
// tau v_anchor is conserved, so it settles at v0 m / (m + gamma tau), and the books hold the
// kinetic energy it lost.
BOOST_AUTO_TEST_CASE_TEMPLATE(following_damper_does_not_resist_steady_motion, D, Dims) {
    constexpr int dim = D::value;
    const int up = dim - 1;
    const double mw = 1e-3, gamma_w = 0.5, tau = 4e-3, v0 = -0.2;  // outward, away from the particle
    for (const double follow : {0.0, tau}) {
        mm::Walls<dim> walls;
        const std::size_t top = walls.size();
        walls.add_axis_aligned(up, false, 0.01, mm::StressControlled{0.0, mw, gamma_w, 1.0, follow});
        walls[top].speed = -v0;  // speed is along the inward normal, which points down
        WallScene<dim> sim(mm::FrictionlessLinear{mm::LinearSpringDashpot(k, 0.0)}, {}, walls);
        sim.particles().add(mm::Vec<dim>::Zero(), 1e-3, 1.0);
        sim.set_time_step(1e-6);
        sim.run(static_cast<std::size_t>(20 * mw / gamma_w / 1e-6));  // 20 damper times
        const double v = -sim.walls()[top].speed;
        const double expected = follow > 0 ? v0 * mw / (mw + gamma_w * tau) : 0.0;
        BOOST_TEST_MESSAGE(dim << "D, follow_time " << follow << ": wall speed " << v << ", expected " << expected);
        BOOST_TEST(std::abs(v - expected) < 2e-3 * std::abs(v0));
        BOOST_TEST(std::abs(sim.books().dissipated_walls - 0.5 * mw * (v0 * v0 - v * v)) < 1e-3 * 0.5 * mw * v0 * v0);
    }
}

// A strain-controlled wall squeezing a particle against a fixed wall does work; slowly and with
// background-free damping, the books close on that work.
BOOST_AUTO_TEST_CASE_TEMPLATE(driven_wall_work_is_booked, D, Dims) {
    constexpr int dim = D::value;
    const int up = dim - 1;
    const double a = 1e-3, m = mm::sphere_mass(rho, a);
    mm::Walls<dim> walls;
    walls.add_axis_aligned(up, true, 0.0);
    walls.add_axis_aligned(up, false, 2.0 * a, mm::StrainControlled{2e-5, 2e-3});  // squeeze by 20 um over 1 ms
    WallScene<dim> sim(mm::FrictionlessLinear{mm::LinearSpringDashpot(k, gamma0)}, {}, walls);
    mm::Vec<dim> x = mm::Vec<dim>::Zero();
    x[up] = a;
    sim.particles().add(x, a, m);
    const double tc = mm::contact_duration(k, gamma0, m);
    sim.set_time_step(tc / 50);
    sim.run(static_cast<std::size_t>(2e-3 / (tc / 50)));
    const auto e = sim.energy();
    BOOST_TEST_MESSAGE(dim << "D driven wall: work " << sim.books().work_by_walls << " elastic " << e.elastic_normal
                           << " residual " << sim.energy_residual());
    // Two walls share the 20 um squeeze: each overlap 10 um, elastic energy 2 x k/2 (1e-5)^2.
    BOOST_TEST(std::abs(e.elastic_normal / (k * 1e-10) - 1.0) < 1e-3);
    BOOST_TEST(sim.books().work_by_walls >= e.elastic_normal);
    BOOST_TEST(std::abs(sim.energy_residual()) < 1e-3);
}

BOOST_AUTO_TEST_SUITE_END()
