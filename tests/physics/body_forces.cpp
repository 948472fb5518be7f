// Body forces and the integrators on exactly solvable motions: free fall (both integrators are
// exact for a constant force, each in its own discrete form), background damping (Eq. 30)
// against exponential decay, translational and rotational; per-particle potential energy.
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <type_traits>

#include "support/scenes.hpp"

BOOST_AUTO_TEST_SUITE(physics_body_forces)  // the file's cases, run as the CTest test of this file's name

using namespace mmtest;

namespace {
namespace tt = boost::test_tools;
template <class A>
void spin_up(A& w) {  // 10 rad/s about the out-of-plane axis in 2D, about each axis in 3D
    if constexpr (std::is_arithmetic_v<A>)
        w = 10.0;
    else
        w = A::Constant(10.0);
}
template <class A>
double magnitude(const A& w) {
    if constexpr (std::is_arithmetic_v<A>)
        return std::abs(w);
    else
        return w.norm();
}
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

// A drag alone has a stability limit too. A free particle under f = -gamma v*, v* velocity
// Verlet's predicted velocity: the one-step map of (v, a) has trace 1 - 3c/2 and determinant -c/2,
// c = gamma dt / m, so an eigenvalue reaches -1 at c = 1 exactly. stable_time_step() says
// m / gamma_b, and I / gamma_r for the spin; prepare() refuses a step above it; at 0.99 of it the
// motion decays (the map's eigenvalue -0.98668), at 1.01 it grows (-1.01335). The affine damping's
// drag counts the same, and a drag adds to the contacts' damping in the bound.
BOOST_AUTO_TEST_CASE_TEMPLATE(a_drag_alone_is_stable_below_m_over_gamma, D, Dims) {
    constexpr int dim = D::value;
    using V = mm::Vec<dim>;
    using Sim = mm::Simulation<dim, mm::FrictionalLinear, mm::NoWalls, mm::VelocityVerlet, mm::LinkedCells, mm::BackgroundDamping,
                               mm::AffineDamping>;
    const double m = 1e-5, a = 1e-3, inertia = 0.4 * m * a * a, gamma = 2e-3;
    for (const bool spin : {false, true}) {
        for (const bool affine : {false, true}) {
            const mm::BackgroundDamping lab = spin ? mm::BackgroundDamping(0.0, gamma * a * a) : mm::BackgroundDamping(gamma, 0.0);
            const mm::AffineDamping flow = spin ? mm::AffineDamping(0.0, gamma * a * a) : mm::AffineDamping(gamma, 0.0);
            auto scene = [&] {
                Sim sim(frictional, {}, {}, {}, {}, affine ? mm::BackgroundDamping() : lab, affine ? flow : mm::AffineDamping());
                sim.particles().add(V::Zero(), a, m);
                sim.particles().velocity()[0] = V::Constant(0.1);
                spin_up(sim.particles().template get<mm::field::AngularVelocity>()[0]);
                return sim;
            };
            const double limit = spin ? inertia / (gamma * a * a) : m / gamma;  // I / gamma_r, m / gamma_b
            BOOST_TEST(scene().stable_time_step() == limit, tt::tolerance(1e-14));
            auto motion = [&](const Sim& sim) {
                return spin ? magnitude(sim.particles().template get<mm::field::AngularVelocity>()[0]) : sim.particles().velocity()[0].norm();
            };
            for (const double fraction : {0.99, 1.01}) {
                Sim sim = scene();
                sim.set_time_step(fraction * limit);
                if (fraction > 1.0) {
                    BOOST_CHECK_THROW(sim.prepare(), mm::InputError);
                    sim.allow_unstable_time_step(true);
                }
                // The other eigenvalue, 0.50 per step, leaves the motion within a few dozen steps;
                // round-off then excites the slow mode, whose rate the last 100 of 1000 steps give.
                sim.run(900);
                const double before = motion(sim);
                sim.run(100);
                const double per_step = std::pow(motion(sim) / before, 1.0 / 100);
                const double c = fraction, trace = 1 - 1.5 * c, det = -0.5 * c;  // c = gamma dt / m
                const double slow = std::abs(trace - std::sqrt(trace * trace - 4 * det)) / 2;
                BOOST_TEST(per_step == slow, tt::tolerance(1e-9));
            }
        }
    }
    // With a contact: the drag adds to the normal dashpot's damping (Eq. 22's oscillator with
    // 2 eta = gamma_n (2/m) + gamma_b / m).
    Sim pair(frictional, {}, {}, {}, {}, mm::BackgroundDamping(gamma, 0.0), mm::AffineDamping());
    pair.particles().add(V::Zero(), a, m);
    pair.particles().add(V::Constant(3 * a), a, m);
    const mm::StiffnessBound b = frictional.stiffness_bound(0.5 * a, 0.5 * m);
    const double normal = mm::VelocityVerlet::stability_limit(std::sqrt(b.normal_stiffness * 2 / m), 0.5 * (b.normal_damping * 2 / m + gamma / m));
    BOOST_TEST(pair.stable_time_step() <= normal * (1 + 1e-14));
    BOOST_TEST(pair.stable_time_step() < mm::normal_time_step_limit<mm::VelocityVerlet>(b.normal_stiffness, b.normal_damping, 2 / m));
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

// ---- damping policies ------------------------------------------------------------------------

// Cundall's local damping takes alpha |F_k| from every component against the velocity along it:
// (1 - alpha) F_k where the particle moves along the force, (1 + alpha) F_k where it moves against
// it, F_k where it does not move along k; a particle under zero net force feels nothing. The same
// for torques. The books take alpha |F_k| |v_k| dt.
BOOST_AUTO_TEST_CASE_TEMPLATE(local_damping_scales_each_component, D, Dims) {
    constexpr int dim = D::value;
    using V = mm::Vec<dim>;
    const double alpha = 0.3, dt = 1e-6;
    mm::Particles<dim, true, double> p;
    p.add(V::Zero(), 1e-3, 1e-5);
    p.add(V::Constant(0.01), 1e-3, 1e-5);
    V f = V::Zero(), v = V::Zero();
    f[0] = 2.0, v[0] = 0.5;    // along the force
    f[1] = 3.0, v[1] = -0.25;  // against it
    if constexpr (dim == 3) f[2] = -1.0;  // no motion along z
    p.template get<mm::field::Force>()[0] = f;
    p.velocity()[0] = v;
    p.velocity()[1] = V::Constant(0.7);  // moving, no force
    auto& t = p.template get<mm::field::Torque>();
    auto& w = p.template get<mm::field::AngularVelocity>();
    if constexpr (dim == 2) {
        t[0] = -4.0;
        w[0] = 10.0;
    } else {
        t[0] = mm::Vec<3>(-4.0, 1.0, 0.0);
        w[0] = mm::Vec<3>(10.0, 0.0, 5.0);
    }
    mm::EnergyBooks books;
    mm::LocalDamping(alpha).apply<true>(p, books, mm::BodyForceStep<dim>{dt});
    const V g = p.template get<mm::field::Force>()[0];
    BOOST_TEST(std::abs(g[0] - 2.0 * (1 - alpha)) < 1e-15);
    BOOST_TEST(std::abs(g[1] - 3.0 * (1 + alpha)) < 1e-15);
    if constexpr (dim == 3) BOOST_TEST(g[2] == -1.0);
    BOOST_TEST((p.template get<mm::field::Force>()[1] == V::Zero()));
    double power = alpha * (2.0 * 0.5 + 3.0 * 0.25);
    power += alpha * 4.0 * 10.0;  // the torque opposes the spin
    if constexpr (dim == 2) BOOST_TEST(std::abs(t[0] + 4.0 * (1 + alpha)) < 1e-15);
    else BOOST_TEST((t[0] - mm::Vec<3>(-4.0 * (1 + alpha), 1.0, 0.0)).norm() < 1e-15);  // opposing, not turning, zero
    BOOST_TEST(std::abs(books.dissipated_background - power * dt) < 1e-15 * power * dt);
    BOOST_CHECK_THROW(mm::LocalDamping(1.0), mm::InputError);
    BOOST_CHECK_THROW(mm::LocalDamping(-0.1), mm::InputError);
}

// In flight under gravity (listed before the damping), a particle thrown up decelerates at
// (1 + alpha) g and falls back at (1 - alpha) g: exact under velocity Verlet away from the step
// that holds the top of its flight. Without gravity it keeps its speed: no drag on steady motion.
BOOST_AUTO_TEST_CASE_TEMPLATE(local_damping_in_free_flight, D, Dims) {
    constexpr int dim = D::value;
    using V = mm::Vec<dim>;
    const double alpha = 0.2, g = 9.81, dt = 1e-4;
    V down = V::Zero();
    down[dim - 1] = -1.0;
    using Scene = mm::Simulation<dim, mm::FrictionlessLinear, mm::NoWalls, mm::VelocityVerlet, mm::LinkedCells, mm::Gravity<dim>,
                                 mm::LocalDamping>;
    const mm::FrictionlessLinear law{mm::LinearSpringDashpot(k, 0.0)};
    Scene sim(law, {}, {}, {}, {}, mm::Gravity<dim>{g * down}, mm::LocalDamping(alpha));
    sim.particles().add(V::Zero(), 1e-3, 1e-5);
    const double up0 = 1.0;  // m/s: the top comes after 1 / ((1 + alpha) g) = 85 ms
    sim.particles().velocity()[0] = -up0 * down;
    sim.set_time_step(dt);
    sim.run(500);
    BOOST_TEST(std::abs(-sim.particles().velocity()[0].dot(down) - (up0 - (1 + alpha) * g * sim.time())) < 1e-12);
    sim.run(1000);  // past the top
    const double t1 = sim.time(), v1 = sim.particles().velocity()[0].dot(down);
    sim.run(500);
    const double v2 = sim.particles().velocity()[0].dot(down);
    BOOST_TEST(v1 > 0.0);
    BOOST_TEST(std::abs((v2 - v1) - (1 - alpha) * g * (sim.time() - t1)) < 1e-12);

    mm::Simulation<dim, mm::FrictionlessLinear, mm::NoWalls, mm::VelocityVerlet, mm::LinkedCells, mm::LocalDamping> coasting(
        law, {}, {}, {}, {}, mm::LocalDamping(alpha));
    coasting.particles().add(V::Zero(), 1e-3, 1e-5);
    coasting.particles().velocity()[0] = V::Constant(0.3);
    coasting.set_time_step(dt);
    coasting.run(100);
    BOOST_TEST((coasting.particles().velocity()[0] == V::Constant(0.3)));
    BOOST_TEST(coasting.books().dissipated_background == 0.0);
}

// A harmonic oscillator (a particle resting on a wall under gravity, undamped contact spring,
// set moving at its rest position) under local damping: moving out, the spring is stiffened to
// (1 + alpha) k, coming back softened to (1 - alpha) k, so each half swing leaves the speed at
// the rest position sqrt((1 - alpha) / (1 + alpha)) of the one before. The energy books close.
BOOST_AUTO_TEST_CASE_TEMPLATE(local_damping_oscillator_decays_as_closed_form, D, Dims) {
    constexpr int dim = D::value;
    using V = mm::Vec<dim>;
    const double alpha = 0.2, g = 9.81, a = 1e-3, m = mm::sphere_mass(rho, a);
    const int up = dim - 1;
    V down = V::Zero();
    down[up] = -1.0;
    mm::Walls<dim> walls;
    walls.add_axis_aligned(up, true, 0.0);
    mm::Simulation<dim, mm::FrictionlessLinear, mm::Walls<dim>, mm::VelocityVerlet, mm::BruteForce, mm::Gravity<dim>,
                   mm::LocalDamping>
        sim(mm::FrictionlessLinear{mm::LinearSpringDashpot(k, 0.0)}, {}, walls, {}, {}, mm::Gravity<dim>{g * down},
            mm::LocalDamping(alpha));
    const double rest = m * g / k;  // overlap at rest, 8e-10 m
    V x = V::Zero();
    x[up] = a - rest;
    sim.particles().add(x, a, m);
    const double v0 = 0.2 * rest * std::sqrt(k / m);  // swings of 0.2 of the rest overlap: never lifts off
    sim.particles().velocity()[0] = -v0 * down;
    sim.set_time_step(mm::contact_duration(k, 0.0, m) / 200);
    sim.prepare();
    const double e0 = sim.energy().total();
    // The speed each time the particle passes its rest position (linear interpolation).
    std::vector<double> passes;
    double h_before = sim.particles().position()[0][up] - x[up];
    double v_before = sim.particles().velocity()[0][up];
    while (passes.size() < 7) {
        sim.step();
        const double h = sim.particles().position()[0][up] - x[up], v = sim.particles().velocity()[0][up];
        if ((h > 0) != (h_before > 0)) passes.push_back(std::abs(v_before + (v - v_before) * h_before / (h_before - h)));
        h_before = h;
        v_before = v;
    }
    const double per_half = std::sqrt((1 - alpha) / (1 + alpha));
    for (std::size_t n = 1; n < passes.size(); ++n) {
        BOOST_TEST_MESSAGE(dim << "D half swing " << n << ": speed ratio " << passes[n] / passes[n - 1] << ", closed form "
                               << per_half);
        BOOST_TEST(std::abs(passes[n] / passes[n - 1] / per_half - 1) < 1e-4);  // measured 5e-6 at t_c/200
    }
    // The books: what the damping took is what the oscillation lost.
    const double lost = e0 - sim.energy().total(), booked = sim.books().dissipated_background;
    BOOST_TEST_MESSAGE(dim << "D: energy lost " << lost << " J, booked " << booked << " J");
    BOOST_TEST(booked > 0.5 * 0.5 * m * v0 * v0);
    BOOST_TEST(std::abs(booked - lost) < 1e-3 * booked);
}

// Damping against the walls' mean flow: in a box whose upper walls move, a packing that moves
// with the box's affine field (and does not spin) feels no force at all; a particle off the field
// is pulled back by -gamma_b times its deviation.
BOOST_AUTO_TEST_CASE_TEMPLATE(affine_damping_leaves_the_box_flow_alone, D, Dims) {
    constexpr int dim = D::value;
    using V = mm::Vec<dim>;
    mm::Walls<dim> walls;
    const V lo = V::Constant(-0.01), hi = V::Constant(0.03);
    walls.add_box(lo, hi);
    for (int axis = 0; axis < dim; ++axis) walls[2 * axis + 1].speed = 0.1 * (axis + 1);  // inward speeds: compression
    walls[0].speed = -0.05;                                                                // the lower x wall moves out
    const mm::AffineField<dim> field = walls.affine_field();
    for (int axis = 0; axis < dim; ++axis) {
        const double u_lo = axis == 0 ? -0.05 : 0.0, u_hi = -0.1 * (axis + 1);  // along +axis
        BOOST_TEST(std::abs(field.velocity(lo)[axis] - u_lo) < 1e-15);
        BOOST_TEST(std::abs(field.velocity(hi)[axis] - u_hi) < 1e-15);
        BOOST_TEST(std::abs(field.gradient(axis, axis) - (u_hi - u_lo) / 0.04) < 1e-12);
    }
    const auto p_sample = random_packing<dim>(50, 0.5e-3, 1.5e-3, 0.02, 5);
    mm::Particles<dim, true, double> p;
    for (std::size_t i = 0; i < p_sample.x.size(); ++i) {
        p.add(p_sample.x[i], p_sample.r[i], mm::sphere_mass(rho, p_sample.r[i]));
        p.velocity()[i] = field.velocity(p_sample.x[i]);
    }
    const V off = V::Constant(0.02);
    p.velocity()[3] += off;
    mm::EnergyBooks books;
    const double gamma_b = 0.05, gamma_r = 1e-8;
    mm::AffineDamping(gamma_b, gamma_r).apply<true>(p, books, mm::BodyForceStep<dim>{1e-6, field});
    for (std::size_t i = 0; i < p.size(); ++i) {
        const V expected = i == 3 ? V(-gamma_b * off) : V(V::Zero());
        BOOST_TEST((p.template get<mm::field::Force>()[i] - expected).norm() < 1e-15);
    }
    // What the drag took from the particles: gamma (v - u) . v over the step, for the one particle off the flow.
    const double taken = gamma_b * off.dot(p.velocity()[3]) * 1e-6;
    BOOST_TEST(std::abs(books.dissipated_background - taken) < 1e-12 * std::abs(taken));
}

// The engine hands the walls' field to the policy as the walls move: a free particle in a box
// compressed along x is carried with the flow by a strong AffineDamping (relaxation time 50 steps
// against a wall motion of 20 000), while Eq. 30 holds it at rest.
BOOST_AUTO_TEST_CASE_TEMPLATE(affine_damping_carries_a_particle_with_the_box, D, Dims) {
    constexpr int dim = D::value;
    using V = mm::Vec<dim>;
    const double a = 1e-3, m = mm::sphere_mass(rho, a), dt = 1e-6, gamma = m / (50 * dt);
    const double L = 0.04, travel = 0.01, period = 2 * 20000 * dt;  // the wall moves for T/2
    auto run = [&]<class Damping>(Damping damping) {
        mm::Walls<dim> walls;
        walls.add_box(V::Zero(), V::Constant(L));
        walls[1].motion = mm::StrainControlled{travel, period, 0.0};
        mm::Simulation<dim, mm::FrictionlessLinear, mm::Walls<dim>, mm::VelocityVerlet, mm::BruteForce, Damping> sim(
            mm::FrictionlessLinear{mm::LinearSpringDashpot(k, 0.0)}, {}, walls, {}, {}, damping);
        sim.particles().add(V::Constant(0.75 * L), a, m);
        sim.set_time_step(dt);
        sim.run(10000);  // the wall at full speed, travel omega / 2 = 0.79 m/s
        const double u = sim.walls().affine_field().velocity(sim.particles().position()[0].template cast<double>())[0];
        return std::pair{sim.particles().velocity()[0][0], u};
    };
    const auto [carried, u] = run(mm::AffineDamping(gamma, 0.0));
    const auto [held, u_lab] = run(mm::BackgroundDamping(gamma, 0.0));
    BOOST_TEST_MESSAGE(dim << "D: flow at the particle " << u << " m/s; carried at " << carried << ", with Eq. 30 " << held);
    BOOST_TEST(u < -0.2);
    BOOST_TEST(std::abs(carried / u - 1) < 1e-3);  // measured 6e-5
    BOOST_TEST(std::abs(held) < 1e-12);
}

BOOST_AUTO_TEST_SUITE_END()
