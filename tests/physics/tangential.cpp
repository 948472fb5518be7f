// The Cundall-Strack tangential spring (Eq. 23-29) against exact answers, in 2D and 3D.
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <numbers>
#include <random>

#include "support/scenes.hpp"

BOOST_AUTO_TEST_SUITE(physics_tangential)  // the file's cases, run as the CTest test of this file's name

using namespace mmtest;

namespace {
template <int dim, class Integrator = mm::VelocityVerlet, class Law = mm::FrictionalLinear>
using FrictionScene = mm::Simulation<dim, Law, mm::Walls<dim>, Integrator, mm::BruteForce, mm::Gravity<dim>>;

template <int dim>
mm::Vec<dim> unit(int axis) {
    mm::Vec<dim> e = mm::Vec<dim>::Zero();
    e[axis] = 1.0;
    return e;
}
constexpr double g = 9.81, mu = 0.5;
const double a = 1e-3, m = mm::sphere_mass(rho, a);

mm::FrictionalLinear paper_law(double mu_s = mu, double mu_d = mu) {
    return {mm::LinearSpringDashpot(k, gamma0), mm::CundallStrack(0.2 * k, 0.2 * gamma0, mu_s, mu_d)};
}
double wall_dt() { return mm::contact_duration(k, gamma0, m) / 50; }

/// A touching contact's record holding the spring xi (a vector in the tangent plane of n) with
/// no advance of its last step.
template <int dim>
mm::TangentialSpring<dim> holding(const mm::Vec<dim>& n, const mm::Vec<dim>& xi) {
    mm::TangentialSpring<dim> h;
    if constexpr (dim == 2)
        h.spring = h.ahead = mm::tangent_of(n).dot(xi);
    else
        h.spring = h.ahead = xi;
    h.touching = true;
    return h;
}
}  // namespace

// A particle launched sliding without spin on a frictional floor ends rolling at
// v0 / (1 + I/(m a^2)): friction acts at the contact, so angular momentum about the floor is
// conserved. 5/7 for sphere inertia, 2/3 for disk inertia, in 2D and 3D alike, under both
// integrators (each kick changes m a v and I w by equal and opposite amounts).
template <int dim, class Integrator>
void check_rolling() {
    const int up = dim - 1;
    for (double inertia_factor : {0.4, 0.5}) {
        mm::Walls<dim> walls;
        walls.add_axis_aligned(up, true, 0.0);
        FrictionScene<dim, Integrator> sim(paper_law(), {}, walls, {}, {}, mm::Gravity<dim>{-g * unit<dim>(up)});
        mm::Vec<dim> x = mm::Vec<dim>::Zero();
        x[up] = a - m * g / k;  // resting overlap
        sim.particles().add(x, a, m, inertia_factor * m * a * a);
        mm::Vec<dim> v0 = mm::Vec<dim>::Zero();
        v0[0] = 0.03;
        if constexpr (dim == 3) v0[1] = 0.04;  // oblique launch in 3D
        sim.particles().velocity()[0] = v0;
        sim.set_time_step(wall_dt());
        sim.run(static_cast<std::size_t>(0.03 / wall_dt()));  // sliding takes ~ 2/7 v0 / (mu g) = 3 ms
        const mm::Vec<dim> v = sim.particles().velocity()[0];
        const double expected = v0.norm() / (1.0 + inertia_factor);
        BOOST_TEST_MESSAGE(dim << "D " << Integrator::name << " I = " << inertia_factor << " m a^2: v/v0 = " << v.norm() / v0.norm());
        BOOST_TEST(std::abs(v.norm() / expected - 1.0) < 1e-6);
        BOOST_TEST((v - v.dot(v0.normalized()) * v0.normalized()).norm() < 1e-9 * v0.norm());  // no side drift
        BOOST_TEST(std::abs(v[up]) < 1e-9 * v0.norm());
    }
}

// Friction from 0 to 10: the same launch ends rolling at v0 / (1 + I/(m a^2)) for every mu > 0
// (only the sliding time, 2/7 v0 / (mu g), changes; at mu = 10 the contact sticks at once and the
// tangential spring rings down) and keeps sliding untouched at mu = 0. Kinetic energy never grows.
BOOST_AUTO_TEST_CASE_TEMPLATE(friction_from_zero_to_ten, D, Dims) {
    constexpr int dim = D::value;
    const int up = dim - 1;
    for (double mu_value : {0.0, 0.1, 0.5, 2.0, 10.0}) {
        mm::Walls<dim> walls;
        walls.add_axis_aligned(up, true, 0.0);
        FrictionScene<dim> sim(paper_law(mu_value, mu_value), {}, walls, {}, {}, mm::Gravity<dim>{-g * unit<dim>(up)});
        mm::Vec<dim> x = mm::Vec<dim>::Zero();
        x[up] = a - m * g / k;
        sim.particles().add(x, a, m, 0.4 * m * a * a);
        const mm::Vec<dim> v0 = 0.03 * unit<dim>(0);
        sim.particles().velocity()[0] = v0;
        sim.set_time_step(wall_dt());
        const double e0 = 0.5 * m * v0.squaredNorm();
        double highest = 0.0;
        for (int chunk = 0; chunk < 30; ++chunk) {  // 30 ms: sliding lasts 8.7 ms at mu = 0.1
            sim.run(static_cast<std::size_t>(1e-3 / wall_dt()));
            const auto e = sim.energy();
            highest = std::max(highest, e.kinetic() + e.elastic_tangential);
        }
        const double v = sim.particles().velocity()[0][0];
        const double expected = mu_value > 0 ? v0[0] / 1.4 : v0[0];
        BOOST_TEST_MESSAGE(dim << "D mu = " << mu_value << ": v/v0 = " << v / v0[0] << ", max (kinetic + tangential) / E0 = "
                               << highest / e0);
        BOOST_TEST(std::abs(v / expected - 1.0) < 1e-6, "mu = " << mu_value);
        BOOST_TEST(highest <= e0 * (1 + 1e-9), "mu = " << mu_value);
    }
}

BOOST_AUTO_TEST_CASE_TEMPLATE(sliding_particle_ends_rolling, D, Dims) {
    check_rolling<D::value, mm::VelocityVerlet>();
    check_rolling<D::value, mm::SymplecticEuler>();
}

// On a wall marked frictionless the same particle keeps sliding: no tangential force, no spin.
BOOST_AUTO_TEST_CASE_TEMPLATE(frictionless_wall_does_not_brake, D, Dims) {
    constexpr int dim = D::value;
    const int up = dim - 1;
    mm::Walls<dim> walls;
    walls.add_axis_aligned(up, true, 0.0).frictionless = true;
    FrictionScene<dim> sim(paper_law(), {}, walls, {}, {}, mm::Gravity<dim>{-g * unit<dim>(up)});
    mm::Vec<dim> x = mm::Vec<dim>::Zero();
    x[up] = a - m * g / k;
    sim.particles().add(x, a, m);
    sim.particles().velocity()[0] = 0.03 * unit<dim>(0);
    sim.set_time_step(wall_dt());
    sim.run(static_cast<std::size_t>(0.01 / wall_dt()));
    BOOST_TEST(std::abs(sim.particles().velocity()[0][0] - 0.03) < 1e-12);
    BOOST_TEST(mm::DimTraits<dim>::squared_norm(sim.particles().template get<mm::field::AngularVelocity>()[0]) == 0.0);
}

// A block (no rotation: huge moment of inertia) on a plane tilted by theta stays put while
// tan(theta) < mu and slides with acceleration g (sin theta - mu_d cos theta) above. A sphere that
// may roll instead rolls down any incline below tan(theta) = 7/2 mu with a = 5/7 g sin(theta).
BOOST_AUTO_TEST_CASE_TEMPLATE(tilted_wall_stick_slide_roll, D, Dims) {
    constexpr int dim = D::value;
    const int up = dim - 1;
    struct Case {
        double tan_theta;
        double inertia;  // in m a^2
        double expected_acceleration_over_g;
    };
    auto sin_of = [](double t) { return std::sin(std::atan(t)); };
    auto cos_of = [](double t) { return std::cos(std::atan(t)); };
    const Case cases[] = {
        {0.45, 1e12, 0.0},                                      // sticks
        {0.55, 1e12, sin_of(0.55) - mu * cos_of(0.55)},         // slides
        {0.45, 0.4, 5.0 / 7.0 * sin_of(0.45)},                  // rolls
        {2.0, 0.4, sin_of(2.0) - mu * cos_of(2.0)},             // slides while spinning up (tan > 3.5 mu)
    };
    for (const auto& c : cases) {
        const double theta = std::atan(c.tan_theta);
        // The plane is tilted about the last horizontal axis; gravity stays vertical.
        mm::Vec<dim> normal = std::cos(theta) * unit<dim>(up) - std::sin(theta) * unit<dim>(0);
        mm::Vec<dim> downhill = -std::cos(theta) * unit<dim>(0) - std::sin(theta) * unit<dim>(up);
        mm::Walls<dim> walls;
        walls.add(normal, mm::Vec<dim>::Zero());
        FrictionScene<dim> sim(paper_law(), {}, walls, {}, {}, mm::Gravity<dim>{-g * unit<dim>(up)});
        const double rest = m * g * std::cos(theta) / k;
        sim.particles().add((a - rest) * normal, a, m, c.inertia * m * a * a);
        sim.set_time_step(wall_dt());
        // Settle 10 ms (the tangential spring's transient decays in ~1 ms), then measure the mean
        // acceleration over 10 ms.
        const auto settle = static_cast<std::size_t>(1e-2 / wall_dt()), measure = static_cast<std::size_t>(1e-2 / wall_dt());
        sim.run(settle);
        const double v1 = sim.particles().velocity()[0].dot(downhill), t1 = sim.time();
        sim.run(measure);
        const double v2 = sim.particles().velocity()[0].dot(downhill), t2 = sim.time();
        const double acc = (v2 - v1) / (t2 - t1) / g;
        BOOST_TEST_MESSAGE(dim << "D tan = " << c.tan_theta << " I = " << c.inertia << ": a/g = " << acc << " expected "
                               << c.expected_acceleration_over_g);
        if (c.expected_acceleration_over_g == 0.0) {
            BOOST_TEST(std::abs(acc) < 1e-7);
            BOOST_TEST(std::abs(v2) < 1e-8);
        } else {
            BOOST_TEST(std::abs(acc / c.expected_acceleration_over_g - 1.0) < 1e-3);
        }
    }
}

namespace {
template <int dim>
using NonRotatingScene = FrictionScene<dim, mm::VelocityVerlet, mm::FrictionalLinearWithoutRotation>;
mm::FrictionalLinearWithoutRotation non_rotating_law() {
    return {mm::LinearSpringDashpot(k, gamma0), mm::CundallStrackWithoutRotation(0.2 * k, 0.2 * gamma0, mu)};
}
}  // namespace

// A particle that cannot rotate, launched along a frictional floor, slides: Coulomb friction
// brakes it at mu g until it stops at t = v0 / (mu g), v0^2 / (2 mu g) from where it started, and
// static friction then holds it (a particle that may rotate ends rolling at 5/7 v0 instead, see
// above). Its kinetic energy goes into the books, almost all of it as sliding dissipation.
BOOST_AUTO_TEST_CASE_TEMPLATE(non_rotating_particle_slides_to_rest, D, Dims) {
    constexpr int dim = D::value;
    const int up = dim - 1;
    mm::Walls<dim> walls;
    walls.add_axis_aligned(up, true, 0.0);
    NonRotatingScene<dim> sim(non_rotating_law(), {}, walls, {}, {}, mm::Gravity<dim>{-g * unit<dim>(up)});
    mm::Vec<dim> x0 = mm::Vec<dim>::Zero();
    x0[up] = a - m * g / k;  // resting overlap
    sim.particles().add(x0, a, m);
    mm::Vec<dim> v0 = 0.03 * unit<dim>(0);
    if constexpr (dim == 3) v0 = mm::Vec<dim>(0.018, 0.024, 0.0);  // oblique in 3D, |v0| = 0.03
    sim.particles().velocity()[0] = v0;
    sim.set_time_step(wall_dt());
    sim.prepare();
    const double e0 = sim.energy().total();
    const double stop_time = v0.norm() / (mu * g), distance = v0.squaredNorm() / (2 * mu * g);
    // Half way through the braking: v = v0 / 2 along v0.
    sim.run(static_cast<std::size_t>(0.5 * stop_time / sim.time_step()));
    const double t_half = sim.time();
    const mm::Vec<dim> v = sim.particles().velocity()[0];
    const mm::Vec<dim> expected_v = v0 * (1.0 - t_half / stop_time);
    BOOST_TEST_MESSAGE(dim << "D without rotation, at t = " << t_half << " s: v = " << v.transpose() << ", expected "
                           << expected_v.transpose());
    BOOST_TEST((v - expected_v).norm() < 1e-4 * v0.norm());
    // Long after the stop: at rest where the braking distance puts it.
    sim.run(static_cast<std::size_t>(2.0 * stop_time / sim.time_step()));
    const mm::Vec<dim> x = sim.particles().position()[0];
    BOOST_TEST_MESSAGE(dim << "D without rotation: travelled " << (x - x0).norm() << " m, expected " << distance << " m");
    BOOST_TEST(std::abs((x - x0).norm() / distance - 1.0) < 1e-4);
    BOOST_TEST(((x - x0) - (x - x0).dot(v0.normalized()) * v0.normalized()).norm() < 1e-9 * distance);  // straight
    sim.run(static_cast<std::size_t>(stop_time / sim.time_step()));  // held by static friction
    BOOST_TEST((sim.particles().position()[0] - x).norm() < 1e-6 * distance);
    const auto& books = sim.books();
    const double kinetic0 = 0.5 * m * v0.squaredNorm();
    BOOST_TEST_MESSAGE(dim << "D without rotation: sliding dissipated " << books.dissipated_sliding / kinetic0
                           << " of the kinetic energy, the tangential dashpot " << books.dissipated_tangential / kinetic0);
    BOOST_TEST(books.dissipated_sliding > 0.99 * kinetic0);
    BOOST_TEST(std::abs(sim.energy().total() + books.dissipated() - e0) < 1e-3 * kinetic0);
}

// On a plane tilted by theta a particle that cannot rotate behaves as a block: it stays put while
// tan(theta) < mu, where a sphere would roll, and slides with a = g (sin theta - mu cos theta)
// above; the same numbers as the block given a huge moment of inertia above.
BOOST_AUTO_TEST_CASE_TEMPLATE(non_rotating_particle_on_incline, D, Dims) {
    constexpr int dim = D::value;
    const int up = dim - 1;
    for (double tan_theta : {0.45, 0.55, 2.0}) {
        const double theta = std::atan(tan_theta);
        const double expected = tan_theta < mu ? 0.0 : std::sin(theta) - mu * std::cos(theta);
        const mm::Vec<dim> normal = std::cos(theta) * unit<dim>(up) - std::sin(theta) * unit<dim>(0);
        const mm::Vec<dim> downhill = -std::cos(theta) * unit<dim>(0) - std::sin(theta) * unit<dim>(up);
        mm::Walls<dim> walls;
        walls.add(normal, mm::Vec<dim>::Zero());
        NonRotatingScene<dim> sim(non_rotating_law(), {}, walls, {}, {}, mm::Gravity<dim>{-g * unit<dim>(up)});
        sim.particles().add((a - m * g * std::cos(theta) / k) * normal, a, m);
        sim.set_time_step(wall_dt());
        const auto ten_ms = static_cast<std::size_t>(1e-2 / wall_dt());
        sim.run(ten_ms);  // the spring's transient decays in ~1 ms
        const double v1 = sim.particles().velocity()[0].dot(downhill), t1 = sim.time();
        sim.run(ten_ms);
        const double v2 = sim.particles().velocity()[0].dot(downhill), t2 = sim.time();
        const double acc = (v2 - v1) / (t2 - t1) / g;
        BOOST_TEST_MESSAGE(dim << "D without rotation, tan = " << tan_theta << ": a/g = " << acc << " expected " << expected);
        if (expected == 0.0) {
            BOOST_TEST(std::abs(acc) < 1e-7);
            BOOST_TEST(std::abs(v2) < 1e-8);
        } else {
            BOOST_TEST(std::abs(acc / expected - 1.0) < 1e-3);
        }
    }
}

// An undamped sticking contact (gamma_0 = gamma_t = 0, mu = 10) rings for 50 periods of its
// tangential oscillation, with and without rotation, at the paper's t_c/50 and at 0.9 of the
// stability limit. The spring advances with the half-step velocity, as the positions do, so the
// contact is velocity Verlet's harmonic oscillator: it conserves K + U (1 - (omega_t dt)^2 / 4)
// exactly, its amplitude neither grows nor decays, and K + U stays within (omega_t dt)^2 / 4 /
// (1 - (omega_t dt)^2 / 4) of where it started. Evaluated with the spring of the last step
// (Eq. 26 as printed) the amplitude grows by (pi/2) omega_t dt per period (4.5% and 7.5% at
// t_c/50); with the trapezoid of two predicted velocities by about (omega_t dt)^3 per period
// (1e-4 at t_c/50, several percent near the limit).
template <int dim, class Law>
void check_undamped_contact_keeps_energy(double inertia_factor, bool near_limit) {
    const int up = dim - 1;
    mm::Walls<dim> walls;
    walls.add_axis_aligned(up, true, 0.0);
    using Tangential = decltype(Law::tangential);
    FrictionScene<dim, mm::VelocityVerlet, Law> sim(Law{mm::LinearSpringDashpot(k, 0.0), Tangential(0.2 * k, 0.0, 10.0)}, {},
                                                    walls, {}, {}, mm::Gravity<dim>{-g * unit<dim>(up)});
    mm::Vec<dim> x = mm::Vec<dim>::Zero();
    x[up] = a - m * g / k;  // resting overlap: no normal oscillation
    sim.particles().add(x, a, m, inertia_factor * m * a * a);
    const double v0 = 1e-4;
    sim.particles().velocity()[0] = v0 * unit<dim>(0);
    sim.set_time_step(near_limit ? 0.9 * sim.stable_time_step() : mm::contact_duration(k, 0.0, m) / 50);
    sim.prepare();
    const double e0 = sim.energy().total(), kinetic0 = 0.5 * m * v0 * v0;
    // Tangential mobility 1/m, plus a^2/I when the particle may turn.
    const double mobility = (1.0 + (Law::needs_rotation ? 1.0 / inertia_factor : 0.0)) / m;
    const double omega_dt = std::sqrt(0.2 * k * mobility) * sim.time_step();
    const double period = 2 * std::numbers::pi / omega_dt;  // in steps
    const auto steps = static_cast<std::size_t>(50 * period), five = static_cast<std::size_t>(5 * period);
    double worst = 0.0, spring_first = 0.0, spring_last = 0.0;
    for (std::size_t s = 0; s < steps; ++s) {
        sim.step();
        const auto e = sim.energy();
        worst = std::max(worst, std::abs(e.total() - e0));
        if (s < five) spring_first = std::max(spring_first, e.elastic_tangential);
        if (s >= steps - five) spring_last = std::max(spring_last, e.elastic_tangential);
    }
    // Amplitude growth per period from the spring energy's peaks 45 periods apart.
    const double growth = std::pow(spring_last / spring_first, 1.0 / (2 * 45)) - 1.0;
    const double band = omega_dt * omega_dt / 4 / (1 - omega_dt * omega_dt / 4);
    BOOST_TEST_MESSAGE(dim << "D undamped contact, rotation " << Law::needs_rotation << ", omega_t dt = " << omega_dt
                           << ": amplitude growth per period " << growth << "; largest |E - E0| / E_kin(0) = "
                           << worst / kinetic0 << " (leapfrog band " << band << ")");
    BOOST_TEST(!sim.particles().velocity()[0].hasNaN());
    // The peaks are sampled once a step: near the limit a sampled peak misses the true one by up
    // to 1 - cos(omega_t dt / 2), in the first and the last five periods alike.
    BOOST_TEST(std::abs(growth) < (near_limit ? 1e-3 : 1e-5));
    BOOST_TEST(worst <= 1.02 * band * kinetic0);
    BOOST_TEST(sim.books().dissipated_sliding == 0.0);  // it stuck throughout
}

BOOST_AUTO_TEST_CASE_TEMPLATE(undamped_sticking_contact_keeps_its_energy, D, Dims) {
    for (bool near_limit : {false, true}) {
        check_undamped_contact_keeps_energy<D::value, mm::FrictionalLinear>(0.4, near_limit);
        check_undamped_contact_keeps_energy<D::value, mm::FrictionalLinearWithoutRotation>(0.4, near_limit);
    }
}

// Direct checks of the law: the force never exceeds the Coulomb limit mu_s f_n; a sliding contact
// leaves its spring exactly at mu_d f_n / k_t; the spring stays in the tangent plane. The contacts
// stay closed (an overlap of 1 mm against speeds of order 1 m/s and a step of 10 us): the last
// evaluation before an opening stands for the rest of the contact and is checked below.
BOOST_AUTO_TEST_CASE_TEMPLATE(spring_respects_coulomb_limit, D, Dims) {
    constexpr int dim = D::value;
    using V = mm::Vec<dim>;
    const mm::CundallStrack law(2e4, 0.02, 0.6, 0.4);
    std::mt19937_64 rng(7);
    std::normal_distribution<double> N(0.0, 1.0);
    auto random_vec = [&] {
        V v;
        for (int i = 0; i < dim; ++i) v[i] = N(rng);
        return v;
    };
    int sliding_seen = 0, static_seen = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        mm::TangentialSpring<dim> h;
        V n = random_vec().normalized();
        for (int step = 0; step < 50; ++step) {
            const double fn = 2.0 * std::abs(N(rng)) - 0.2;  // sometimes tensile
            n = (n + 0.05 * random_vec()).normalized();      // the contact frame turns
            const V v = 0.5 * random_vec();
            const auto f = law.force<dim, false>(n, v, n.dot(v), fn, 1e-3, 1e-5, h);
            BOOST_TEST_REQUIRE(f.force.norm() <= 0.6 * std::max(fn, 0.0) * (1 + 1e-12) + 1e-300);
            BOOST_TEST_REQUIRE(std::abs(f.force.dot(n)) <= 1e-12 * (1 + f.force.norm()));
            if (f.sliding) {
                ++sliding_seen;
                const double spring = law.present_spring<dim>(n, h).norm();
                BOOST_TEST_REQUIRE(std::abs(2e4 * spring - 0.4 * std::max(fn, 0.0)) <= 1e-12 * (1 + fn));
                BOOST_TEST_REQUIRE(std::abs(f.force.norm() - 0.4 * std::max(fn, 0.0)) <= 1e-12 * (1 + fn));
            } else {
                ++static_seen;
            }
        }
    }
    BOOST_TEST(sliding_seen > 1000);
    BOOST_TEST(static_seen > 1000);
}

// A contact found open gets the rest of its last evaluation's impulse, the contact having opened
// s (<= dt) after that evaluation: a spring that held to the end pushed for s + dt/2 (half a step
// before the evaluation and s after), so the last evaluation's force plus the correction is
// (s + dt/2)/dt of the spring's; a contact that slid at the evaluation before too keeps mu_d f_n
// (velocity Verlet treats it as the normal force's own last sample): no correction.
BOOST_AUTO_TEST_CASE_TEMPLATE(rest_of_the_impulse_of_an_opened_contact, D, Dims) {
    constexpr int dim = D::value;
    using V = mm::Vec<dim>;
    const double kt = 2e4, dt = 1e-5, fn = 1.0, xi = 1e-6;  // a spring force of 0.02 N
    const V n = unit<dim>(dim - 1), t = unit<dim>(0);
    const double spring_force = kt * xi;
    for (double s : {0.1 * dt, 0.5 * dt, 0.9 * dt}) {
        // mu = 1e4: the Coulomb limit fell from 1e4 N to zero within the last 2e-6 of s.
        const mm::TangentialSpring<dim> held = holding<dim>(n, V(xi * t));
        const V total = V(-kt * xi * t) + mm::CundallStrack(kt, 0.0, 1e4).opening_correction<dim>(n, held, fn, s, dt);
        BOOST_TEST(total.dot(t) < 0.0);
        BOOST_TEST(total.norm() == spring_force * (s + 0.5 * dt) / dt, boost::test_tools::tolerance(1e-5));
        // mu = 1e-3, sliding with a trial force of 0.02 N: the limit, with f_n falling linearly
        // to the opening, was below it a step before too (at most 1e-3 (s + dt)/s = 1.1e-2 N).
        mm::TangentialSpring<dim> sliding = holding<dim>(n, V((1e-3 * fn / kt) * t));
        sliding.trial = static_cast<float>(spring_force);
        sliding.sliding = true;
        BOOST_TEST(mm::CundallStrack(kt, 0.0, 1e-3).opening_correction<dim>(n, sliding, fn, s, dt).norm() <= 1e-15 * fn);
    }
}

// The 2D law works on the spring's component along the tangent line (force_along_line), the 3D
// law on vectors; a 2D contact embedded in the plane z = 0 of 3D must give the same force,
// spring, sliding state and dissipation to round-off over long random histories (tensile spells,
// both friction states, both reversal cases) while its frame keeps its direction. Turning frames
// are the next test's.
BOOST_AUTO_TEST_CASE(line_form_matches_vector_form) {
    const mm::CundallStrack law(2e4, 0.02, 0.6, 0.4);
    std::mt19937_64 rng(11);
    std::normal_distribution<double> N(0.0, 1.0);
    int sliding_seen = 0, static_seen = 0, dissipating = 0;
    double worst = 0.0;
    for (int trial = 0; trial < 500; ++trial) {
        mm::TangentialSpring<2> h2;
        mm::TangentialSpring<3> h3;
        const double angle = 6.0 * N(rng);
        const mm::Vec<2> n2(std::cos(angle), std::sin(angle));
        const mm::Vec<3> n3(n2.x(), n2.y(), 0.0);
        for (int step = 0; step < 100; ++step) {
            const double fn = 2.0 * std::abs(N(rng)) - 0.2, dt = 1e-5;
            const mm::Vec<2> v2(0.5 * N(rng), 0.5 * N(rng));
            const mm::Vec<3> v3(v2.x(), v2.y(), 0.0);
            const auto f2 = law.force<2, true>(n2, v2, n2.dot(v2), fn, 1e-6, dt, h2);
            const auto f3 = law.force<3, true>(n3, v3, n3.dot(v3), fn, 1e-6, dt, h3);
            BOOST_TEST_REQUIRE(f2.sliding == f3.sliding);
            BOOST_TEST_REQUIRE(h2.sliding == h3.sliding);
            const double scale = 1.0 + std::abs(fn);
            const mm::Vec<2> spring2 = law.present_spring<2>(n2, h2);
            const mm::Vec<3> spring3 = law.present_spring<3>(n3, h3);
            worst = std::max({worst, (f2.force - f3.force.head<2>()).norm() / scale,
                              2e4 * (spring2 - spring3.head<2>()).norm() / scale});
            BOOST_TEST_REQUIRE(std::abs(f2.dissipated_viscous - f3.dissipated_viscous) <=
                               1e-12 * (std::abs(f3.dissipated_viscous) + 1e-12 * scale * scale));
            BOOST_TEST_REQUIRE(std::abs(f2.dissipated_sliding - f3.dissipated_sliding) <=
                               1e-9 * (std::abs(f3.dissipated_sliding) + 1e-9 * scale * scale));
            (f2.sliding ? sliding_seen : static_seen) += 1;
            dissipating += f3.dissipated_sliding != 0.0;
        }
    }
    BOOST_TEST_MESSAGE("largest force or spring-force difference over (1 + |f_n|): " << worst);
    BOOST_TEST(worst < 1e-14);
    BOOST_TEST(sliding_seen > 5000);
    BOOST_TEST(static_seen > 5000);
    BOOST_TEST(dissipating > 5000);
}

// A sticking contact whose frame turns without relative motion at the contact (a pair rolling
// round each other as one body): the spring turns with the frame and keeps its length. In 2D the
// spring is a component along the tangent and is kept exactly. In 3D each step projects the
// stored spring onto the new tangent plane (Eq. 23), which alone would shorten it by
// (turn per step)^2 / 2 per step, pi/4 of the turn per step over a quarter turn (1.6% at 0.02
// rad). With the last step's advance in `ahead` the first steps lose 3/4 of (turn per step)^2 in
// all while the advance builds up, and the steps after it lose at third order.
BOOST_AUTO_TEST_CASE_TEMPLATE(turning_sticking_contact_keeps_its_spring, D, Dims) {
    constexpr int dim = D::value;
    using V = mm::Vec<dim>;
    const mm::CundallStrack law(2e4, 0.0, 10.0);
    const double xi = 1e-6, dt = 1e-5;
    auto normal = [](double angle) {
        V n = V::Zero();
        n[0] = std::cos(angle);
        n[1] = std::sin(angle);
        return n;
    };
    auto tangent = [](double angle) {
        V t = V::Zero();
        t[0] = -std::sin(angle);
        t[1] = std::cos(angle);
        return t;
    };
    // The spring's loss of length after 10 steps and after a quarter turn.
    auto losses = [&](double turn) {
        mm::TangentialSpring<dim> h = holding<dim>(normal(0.0), V(xi * tangent(0.0)));
        const int steps = static_cast<int>(std::lround(0.5 * std::numbers::pi / turn));
        std::pair<double, double> loss;
        for (int s = 1; s <= steps; ++s) {
            const V n = normal(s * turn);
            const auto f = law.force<dim, false>(n, V::Zero(), 0.0, 1.0, 1e-6, dt, h);
            BOOST_TEST_REQUIRE(!f.sliding);
            const V spring = law.present_spring<dim>(n, h);
            BOOST_TEST_REQUIRE(spring.dot(tangent(s * turn)) > 0.0);  // turned with the frame
            (s == 10 ? loss.first : loss.second) = 1.0 - spring.norm() / xi;
        }
        return loss;
    };
    const auto coarse = losses(0.02), fine = losses(0.01);
    BOOST_TEST_MESSAGE(dim << "D: spring lost after 10 steps and a quarter turn " << coarse.first << ", " << coarse.second
                           << " (0.02 rad per step); " << fine.first << ", " << fine.second << " (0.01 rad per step)");
    if constexpr (dim == 2) {
        for (double loss : {coarse.first, coarse.second, fine.first, fine.second}) BOOST_TEST(std::abs(loss) < 1e-14);
    } else {
        BOOST_TEST(coarse.second < 0.02 * 0.02);  // against 1.6e-2 for the projection alone
        BOOST_TEST(fine.second < 0.01 * 0.01);
        const double order = std::log2((coarse.second - coarse.first) / (fine.second - fine.first));
        BOOST_TEST_MESSAGE("3D: order of the loss after the first 10 steps " << order);
        BOOST_TEST(order > 2.7);
        BOOST_TEST(order < 3.3);
    }
}

// Static/dynamic hysteresis: with mu_s > mu_d a sticking contact starts sliding only above
// mu_s f_n and a sliding one sticks again only below mu_d f_n.
BOOST_AUTO_TEST_CASE_TEMPLATE(static_and_dynamic_friction, D, Dims) {
    constexpr int dim = D::value;
    using V = mm::Vec<dim>;
    const double kt = 1.0;
    const mm::CundallStrack law(kt, 0.0, 0.6, 0.4);
    const V n = V::UnitX();
    V t = V::Zero();
    t[1] = 1.0;
    mm::TangentialSpring<dim> h;
    // Load the spring slowly: the force grows by kt * v * dt = 1e-3 per step.
    auto load = [&](double speed) { return law.force<dim, false>(n, speed * t, 0.0, 1.0, 1e-6, 1e-3, h); };  // v . n = 0
    auto spring = [&] { return law.present_spring<dim>(n, h).norm(); };
    double largest_static = 0.0, first_sliding = 0.0;
    for (int s = 0; s < 2000 && !h.sliding; ++s) {
        const auto f = load(1.0);
        (f.sliding ? first_sliding : largest_static) = f.force.norm();
    }
    BOOST_TEST(h.sliding);
    BOOST_TEST(largest_static <= 0.6 + 1e-12);         // sticks up to mu_s f_n ...
    BOOST_TEST(largest_static > 0.6 - 1e-3 - 1e-12);  // ... (within one load increment)
    BOOST_TEST(std::abs(first_sliding - 0.4) < 1e-12);  // then slides at mu_d f_n
    BOOST_TEST(std::abs(kt * spring() - 0.4) < 1e-12);  // with the spring at the limit
    // Continuing the motion keeps it sliding at mu_d f_n, not at mu_s f_n.
    for (int s = 0; s < 10; ++s) BOOST_TEST(std::abs(load(1.0).force.norm() - 0.4) < 1e-12);
    BOOST_TEST(h.sliding);
    // Reversing the motion sticks again and unloads the spring. The spring advances by the
    // half-step velocity, which the law infers from velocity Verlet's predicted velocities,
    // v*_{n+1} = (3 v_{n+1/2} - v_{n-1/2}) / 2: after the jump from +1 to -1 it is -1/3, then
    // -7/9, then -25/27 (a jump is an infinite acceleration; in a simulation v* changes smoothly).
    const auto back = load(-1.0);
    BOOST_TEST(!back.sliding);
    BOOST_TEST(std::abs(back.force.norm() - (0.4 - 1e-3 / 3)) < 1e-12);
    BOOST_TEST(std::abs(kt * spring() - (0.4 - 1e-3 / 3)) < 1e-12);
    const auto unloading = load(-1.0);
    BOOST_TEST(!unloading.sliding);
    BOOST_TEST(std::abs(unloading.force.norm() - (0.4 - 1e-3 / 3 - 7e-3 / 9)) < 1e-12);
}

// Rotating the whole scene rotates the result: an oblique, spinning frictional collision.
BOOST_AUTO_TEST_CASE_TEMPLATE(rotation_invariance, D, Dims) {
    constexpr int dim = D::value;
    using V = mm::Vec<dim>;
    using M = Eigen::Matrix<double, dim, dim>;
    M R;
    if constexpr (dim == 2) R = Eigen::Rotation2Dd(0.7).toRotationMatrix();
    else R = Eigen::AngleAxisd(0.7, V(1, 2, 3).normalized()).toRotationMatrix();
    auto run = [&](const M& rot) {
        mm::Simulation<dim, mm::FrictionalLinear, mm::NoWalls, mm::VelocityVerlet, mm::BruteForce> sim(paper_law());
        const double m2 = mm::sphere_mass(rho, 1.4e-3);
        V x2 = V::Zero();
        x2[0] = 2.25e-3;
        x2[1] = 0.9e-3;
        sim.particles().add(V::Zero(), a, m);
        sim.particles().add(rot * x2, 1.4e-3, m2);
        V v = V::Zero();
        v[0] = -0.2;
        sim.particles().velocity()[1] = rot * v;
        auto& w = sim.particles().template get<mm::field::AngularVelocity>();
        if constexpr (dim == 2) w[0] = 150.0;  // rotations in the plane commute with the scene's rotation
        else w[0] = rot * V(30.0, -120.0, 80.0);
        sim.set_time_step(mm::contact_duration(k, gamma0, mm::reduced_mass(m, m2)) / 100);
        sim.run(1500);  // contact after ~5 t_c, over after ~6 t_c
        return sim;
    };
    const auto plain = run(M::Identity());
    const auto turned = run(R);
    for (int i = 0; i < 2; ++i) {
        const V v_plain = plain.particles().velocity()[i], v_turned = turned.particles().velocity()[i];
        BOOST_TEST((R * v_plain - v_turned).norm() < 1e-12 * 0.2);
        const auto& w_plain = plain.particles().template get<mm::field::AngularVelocity>()[i];
        const auto& w_turned = turned.particles().template get<mm::field::AngularVelocity>()[i];
        if constexpr (dim == 2) BOOST_TEST(std::abs(w_plain - w_turned) < 1e-10 * 150);
        else BOOST_TEST((R * w_plain - w_turned).norm() < 1e-10 * 150);
    }
    BOOST_TEST(plain.books().dissipated_sliding + plain.books().dissipated_tangential > 0.0);  // friction acted
}

// ---- oblique impacts: the order of the tangential update -------------------------------------

namespace {
// Two equal spheres (a = 1 mm, rho = 2000, k = 1e5 N/m, k_t = 2e4 N/m, no dashpots), one at rest,
// the other arriving at 0.5 m/s with impact parameter b (in 3D spinning at 300 rad/s about its
// direction of flight, so the spring turns in its tangent plane): the target's spin and the
// relative velocity across the flight, both constant once the spheres have parted. The contact
// begins `phase` of a step before an evaluation: at coarse steps the result depends on where in a
// step the surfaces meet, and a packing meets every phase.
template <int dim>
mm::ObliqueImpact oblique_impact(double b, double mu_value, double steps_per_tc, double phase) {
    const mm::FrictionalLinear law{mm::LinearSpringDashpot(k, 0.0), mm::CundallStrack(2e4, 0.0, mu_value)};
    const double dt = mm::contact_duration(k, 0.0, m / 2) / steps_per_tc;
    return mm::measure_oblique_impact<dim>(law, m, a, 0.5, b, dt, phase, 300.0);
}

struct ImpactErrors {
    double spin, across;  // relative to the converged values: worst over the phases
    double spin_rms;      // the spin's, root mean square over the phases
};

// The relative errors over eight entry phases at `steps_per_tc`, against the same impact at
// t_c/12800 (whose own error is below 1e-7 of the values).
template <int dim>
ImpactErrors impact_errors(double b, double mu_value, double steps_per_tc) {
    ImpactErrors e{0.0, 0.0, 0.0};
    for (int p = 0; p < 8; ++p) {
        const double phase = (p + 0.5) / 8;
        const auto ref = oblique_impact<dim>(b, mu_value, 12800, phase), got = oblique_impact<dim>(b, mu_value, steps_per_tc, phase);
        const double spin = (got.target_spin - ref.target_spin).norm() / ref.target_spin.norm();
        e.spin = std::max(e.spin, spin);
        e.across = std::max(e.across, (got.across - ref.across).norm() / ref.across.norm());
        e.spin_rms += spin * spin / 8;
    }
    e.spin_rms = std::sqrt(e.spin_rms);
    return e;
}
}  // namespace

// At the paper's t_c/50 the spin and the tangential velocity after an oblique impact are within
// 1e-3 of the converged values at every entry phase: sticking, then sliding as the normal force
// fades (b = 0.3, 0.8, 1.5 mm, mu = 0.5; near head-on the sliding lasts less than a step),
// sliding, sticking, sliding (b = 1.9 mm), sticking until the surfaces part with the spring
// loaded (mu = 5), and within 1e-4 sliding throughout (mu = 0.05). While the spring carries the
// contact the error falls at second order: more than 64x from t_c/50 to t_c/800 (first order
// gives 16). Sliding throughout, the spring sits at the Coulomb limit at every step and its
// update hardly matters. A spring advanced by the end-of-step velocity alone, stored at the
// Coulomb limit after sliding or started half a step in has errors of order dt: 2e-3 to 1e-2
// here at t_c/50, 5e-4 to 1e-3 sliding. A spring still loaded when the contact opens needs the
// rest of the last evaluation's impulse (CundallStrack::opening_correction); as a plain sample
// it leaves an error of order dt that depends on where in a step the contact opens.
BOOST_AUTO_TEST_CASE_TEMPLATE(oblique_impacts_converge_at_second_order, D, Dims) {
    constexpr int dim = D::value;
    struct Case {
        double b, mu;
        double fine;  // the step t_c/fine of the order check (0: none, see below)
    };
    // Near head-on the sliding before the opening lasts 0.8 steps at t_c/50 and is resolved
    // between t_c/100 and t_c/400: the error falls at second order over that range (docs/
    // oblique-impacts.md) but not monotonically, so its order is not checked on two steps here.
    // With mu = 5 the reference's own error (1e-5) is reached before t_c/800.
    for (const Case c : {Case{0.3e-3, 0.5, 0}, Case{0.8e-3, 0.5, 800}, Case{1.5e-3, 0.5, 800}, Case{1.9e-3, 0.5, 800},
                         Case{0.3e-3, 5.0, 200}, Case{0.8e-3, 0.05, 0}}) {
        const ImpactErrors at50 = impact_errors<dim>(c.b, c.mu, 50);
        BOOST_TEST_MESSAGE(dim << "D b = " << c.b * 1e3 << " mm, mu = " << c.mu << ": worst spin error " << at50.spin
                               << ", tangential velocity " << at50.across << ", rms spin error " << at50.spin_rms << " at t_c/50");
        const bool sliding_throughout = c.mu < 0.1;
        BOOST_TEST(at50.spin < (sliding_throughout ? 1e-4 : 1e-3));
        BOOST_TEST(at50.across < (sliding_throughout ? 1e-4 : 1e-3));
        if (c.fine > 0) {  // second order: the error falls by (fine/50)^2; first order would give fine/50
            const ImpactErrors fine = impact_errors<dim>(c.b, c.mu, c.fine);
            const double ratio = at50.spin_rms / fine.spin_rms, first_order = c.fine / 50;
            BOOST_TEST_MESSAGE("    rms spin error " << fine.spin_rms << " at t_c/" << c.fine << ": " << ratio << "x smaller");
            BOOST_TEST(ratio > 4.0 * first_order);
        }
    }
}

// Evaluating the same instant twice (prepare() again after the law changed, as the biaxial
// program does between preparation and loading) must not advance the springs twice: a particle
// rocking on a sticking, undamped tangential spring follows the same trajectory whether or not the
// scene is re-prepared between two steps. The second evaluation sees the velocity after the last
// kick instead of the predicted one, so the two differ at O(dt^3): 1e-7 of v0 (measured);
// advancing the spring a second time shifts it by v_t dt and the velocity by 6e-3 of v0.
BOOST_AUTO_TEST_CASE_TEMPLATE(re_preparing_does_not_advance_the_springs, D, Dims) {
    constexpr int dim = D::value;
    const int up = dim - 1;
    auto scene = [&] {
        mm::Walls<dim> walls;
        walls.add_axis_aligned(up, true, 0.0);
        FrictionScene<dim> sim(mm::FrictionalLinear{mm::LinearSpringDashpot(k, 0.0), mm::CundallStrack(0.2 * k, 0.0, 10.0)}, {},
                               walls, {}, {}, mm::Gravity<dim>{-g * unit<dim>(up)});
        mm::Vec<dim> x = mm::Vec<dim>::Zero();
        x[up] = a - m * g / k;
        sim.particles().add(x, a, m);
        sim.particles().velocity()[0] = 1e-4 * unit<dim>(0);
        sim.set_time_step(mm::contact_duration(k, 0.0, m) / 50);
        return sim;
    };
    auto plain = scene(), again = scene();
    plain.run(37);  // part way through a tangential period: spring and velocity both loaded
    again.run(37);
    again.law();    // marks the scene for a new prepare() at the next step
    double worst = 0.0;
    for (int s = 0; s < 200; ++s) {
        plain.step();
        again.step();
        worst = std::max(worst, (plain.particles().velocity()[0] - again.particles().velocity()[0]).norm() / 1e-4);
    }
    BOOST_TEST_MESSAGE(dim << "D: largest velocity difference after a re-prepare, relative to v0: " << worst);
    BOOST_TEST(worst < 1e-6);
}

BOOST_AUTO_TEST_SUITE_END()
