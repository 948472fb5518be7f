// Body forces and the integrators on exactly solvable motions: free fall (both integrators are
// exact for a constant force, each in its own discrete form), background damping (Eq. 30)
// against exponential decay, translational and rotational; per-particle potential energy.
#define BOOST_TEST_MODULE physics_body_forces
#include <boost/test/unit_test.hpp>

#include <cmath>

#include "support/scenes.hpp"

using namespace mmtest;

namespace {
const mm::FrictionalLinear frictional{mm::LinearSpringDashpot(k, gamma0), mm::CundallStrack(0.2 * k, 0.2 * gamma0, 0.5)};
}

BOOST_AUTO_TEST_CASE_TEMPLATE(free_fall_is_exact, D, Dims) {
    constexpr int dim = D::value;
    using V = mm::Vec<dim>;
    V g = V::Zero();
    g[dim - 1] = -9.81;
    V v0 = V::Constant(0.3);
    const double dt = 1e-3;
    const int n = 1000;
    // Velocity Verlet: x_n = x0 + v0 t + g t^2 / 2 exactly.
    {
        mm::Simulation<dim, mm::FrictionlessLinear, mm::NoWalls, mm::VelocityVerlet, mm::LinkedCells, mm::Gravity<dim>> sim(
            mm::FrictionlessLinear{mm::LinearSpringDashpot(k, gamma0)}, {}, {}, {}, {}, mm::Gravity<dim>{g});
        sim.particles().add(V::Zero(), 1e-3, 1e-5);
        sim.particles().velocity()[0] = v0;
        sim.set_time_step(2.0 * dt);
        sim.run(n / 4);
        sim.set_time_step(dt);  // changing dt mid-run keeps state and books
        sim.run(n / 2);
        const double t = n * dt;
        BOOST_TEST(std::abs(sim.time() - t) < 1e-15);
        BOOST_TEST((sim.particles().position()[0] - (v0 * t + 0.5 * g * t * t)).norm() < 1e-12);
        BOOST_TEST((sim.particles().velocity()[0] - (v0 + g * t)).norm() < 1e-12);
        // Potential + kinetic energy is conserved exactly for a constant force under Verlet; the
        // bound is round-off, magnified ~1000x because m g dx is ~1000x the initial energy.
        BOOST_TEST(std::abs(sim.energy_residual()) < 1e-10);
    }
    // Symplectic Euler: x_n = x0 + v0 t + g t (t + dt) / 2 exactly (its known first-order lead).
    {
        mm::Simulation<dim, mm::FrictionlessLinear, mm::NoWalls, mm::SymplecticEuler, mm::LinkedCells, mm::Gravity<dim>> sim(
            mm::FrictionlessLinear{mm::LinearSpringDashpot(k, gamma0)}, {}, {}, {}, {}, mm::Gravity<dim>{g});
        sim.particles().add(V::Zero(), 1e-3, 1e-5);
        sim.particles().velocity()[0] = v0;
        sim.set_time_step(dt);
        sim.run(n);
        const double t = n * dt;
        BOOST_TEST((sim.particles().position()[0] - (v0 * t + 0.5 * g * t * (t + dt))).norm() < 1e-12);
        BOOST_TEST((sim.particles().velocity()[0] - (v0 + g * t)).norm() < 1e-12);
    }
}

// Eq. 30: m v' = -gamma_b v and I w' = -gamma_r w decay as exp(-gamma t / m) and exp(-gamma_r t / I);
// the books hold exactly the lost kinetic energy up to the integrator's error.
BOOST_AUTO_TEST_CASE_TEMPLATE(background_damping_decays_exponentially, D, Dims) {
    constexpr int dim = D::value;
    using V = mm::Vec<dim>;
    const double a = 1e-3, m = mm::sphere_mass(rho, a), I = mm::sphere_inertia(m, a);
    const double gamma_b = 1e-3, gamma_r = 1e-9;  // decay times m/gamma_b = 8.4 ms, I/gamma_r = 3.4 ms
    mm::Simulation<dim, mm::FrictionalLinear, mm::NoWalls, mm::VelocityVerlet, mm::LinkedCells, mm::BackgroundDamping> sim(
        frictional, {}, {}, {}, {}, mm::BackgroundDamping(gamma_b, gamma_r));
    sim.particles().add(V::Zero(), a, m);
    const V v0 = V::Constant(0.1);
    sim.particles().velocity()[0] = v0;
    auto& w = sim.particles().template get<mm::field::AngularVelocity>()[0];
    if constexpr (dim == 2) w = 50.0;
    else w = mm::Vec<3>(50.0, -20.0, 10.0);
    const auto w0 = w;
    const double e0 = 0.5 * m * v0.squaredNorm() + 0.5 * I * mm::DimTraits<dim>::squared_norm(w0);
    const double dt = 1e-5;
    sim.set_time_step(dt);
    sim.run(1000);
    const double t = sim.time();
    const V v_exact = v0 * std::exp(-gamma_b * t / m);
    BOOST_TEST((sim.particles().velocity()[0] - v_exact).norm() < 1e-6 * v0.norm());
    const auto w_exact = w0 * std::exp(-gamma_r * t / I);
    BOOST_TEST(std::sqrt(mm::DimTraits<dim>::squared_norm(w - w_exact)) < 1e-6 * std::sqrt(mm::DimTraits<dim>::squared_norm(w0)));
    BOOST_TEST(std::abs(sim.books().dissipated_background + sim.energy().kinetic() - e0) < 1e-6 * e0);
    BOOST_TEST(sim.books().dissipated_background > 0.5 * e0);
}

// The elastic energy of each spring is split half and half between the two partners; a wall gives
// its share to the particle. Three particles in a row on a wall: the sum is the total.
BOOST_AUTO_TEST_CASE_TEMPLATE(potential_energy_per_particle, D, Dims) {
    constexpr int dim = D::value;
    using V = mm::Vec<dim>;
    const double a = 1e-3;
    mm::Walls<dim> walls;
    walls.add_axis_aligned(0, true, 0.0);
    mm::Simulation<dim, mm::FrictionlessLinear, mm::Walls<dim>> sim(
        mm::FrictionlessLinear{mm::LinearSpringDashpot(k, gamma0)}, {}, walls);
    const double d1 = 1e-5, d2 = 2e-5, d3 = 3e-5;  // wall-0, 0-1, 1-2 overlaps
    V x = V::Constant(0.01);
    x[0] = a - d1;
    sim.particles().add(x, a, 1e-5);
    x[0] += 2 * a - d2;
    sim.particles().add(x, a, 1e-5);
    x[0] += 2 * a - d3;
    sim.particles().add(x, a, 1e-5);
    sim.set_time_step(1e-8);
    sim.prepare();
    const auto u = sim.potential_energy_per_particle();
    const double e1 = 0.5 * k * d1 * d1, e2 = 0.5 * k * d2 * d2, e3 = 0.5 * k * d3 * d3;
    BOOST_TEST(std::abs(u[0] - (e1 + 0.5 * e2)) < 1e-12 * e3);
    BOOST_TEST(std::abs(u[1] - 0.5 * (e2 + e3)) < 1e-12 * e3);
    BOOST_TEST(std::abs(u[2] - 0.5 * e3) < 1e-12 * e3);
    BOOST_TEST(std::abs(u[0] + u[1] + u[2] - sim.energy().elastic_normal) < 1e-12 * e3);
    BOOST_TEST(sim.contact_count() == 3u);
}
