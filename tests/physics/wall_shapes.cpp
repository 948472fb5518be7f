// A wall shape written outside the library, as a user writes one (walls/shape.hpp): the inside
// of a sphere (a circle in 2D), a bowl. Against exact answers in 2D and 3D: a particle in the
// bowl under gravity swings as a pendulum of length R - a, sliding on a smooth bowl and rolling
// on a rough one; a bowl moved by a motion carries its particle and its load; a state names the
// shape, and what the shape cannot do is refused with a message.
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string_view>

#include "support/expect_error.hpp"
#include "support/scenes.hpp"

BOOST_AUTO_TEST_SUITE(physics_wall_shapes)  // the file's cases, run as the CTest test of this file's name

using namespace mmtest;

namespace {

/// The inside of the sphere of `radius` around `centre` + h axis (h the wall's offset).
template <int dim>
struct SphericalBowl {
    static constexpr std::string_view name = "spherical-bowl";
    mm::Vec<dim> centre;
    double radius;
    mm::Vec<dim> axis;  ///< unit: the direction the wall's motion moves the bowl

    mm::WallPoint<dim> nearest(const mm::Vec<dim>& x, double h) const {
        const mm::Vec<dim> inward = centre + h * axis - x;  // from the particle to the centre
        const double r = inward.norm();
        return {radius - r, r > 0.0 ? mm::Vec<dim>(inward / r) : axis};
    }
    mm::Vec<dim> direction() const { return axis; }
    bool finite() const { return centre.allFinite() && std::isfinite(radius) && axis.allFinite(); }
    template <class Archive>
    void serialize(Archive& ar) {
        ar.value(centre);
        ar.value(radius);
        ar.value(axis);
    }
};
static_assert(mm::WallShape<SphericalBowl<2>, 2> && mm::WallShape<SphericalBowl<3>, 3>);

template <int dim>
using Bowl = mm::Walls<dim, SphericalBowl<dim>>;
template <int dim>
using BowlScene = mm::Simulation<dim, mm::FrictionalLinear, Bowl<dim>, mm::VelocityVerlet, mm::BruteForce, mm::Gravity<dim>>;

constexpr double g = 9.81, a = 1e-3, R = 20e-3;
const double m = mm::sphere_mass(rho, a);

template <int dim>
mm::Vec<dim> up() {
    mm::Vec<dim> e = mm::Vec<dim>::Zero();
    e[dim - 1] = 1.0;
    return e;
}

mm::FrictionalLinear law() { return {mm::LinearSpringDashpot(k, gamma0), mm::CundallStrack(0.2 * k, 0.2 * gamma0, 0.5)}; }
double bowl_dt() { return mm::contact_duration(k, gamma0, m) / 50; }

/// A particle in a bowl centred at the origin, at angle theta from the bottom in the x-up plane,
/// resting against the surface (its overlap under gravity along the radius).
template <int dim>
BowlScene<dim> particle_in_bowl(double theta, bool smooth, mm::WallMotion motion = mm::FixedMotion{}) {
    Bowl<dim> bowl;
    bowl.add(SphericalBowl<dim>{mm::Vec<dim>::Zero(), R, up<dim>()}, motion).frictionless = smooth;
    BowlScene<dim> sim(law(), {}, bowl, {}, {}, mm::Gravity<dim>{-g * up<dim>()});
    const double arm = R - a + m * g * std::cos(theta) / k;
    mm::Vec<dim> x = mm::Vec<dim>::Zero();
    x[0] = arm * std::sin(theta);
    x[dim - 1] = -arm * std::cos(theta);
    sim.particles().add(x, a, m, 0.4 * m * a * a);
    sim.set_time_step(bowl_dt());
    return sim;
}

/// The mean period of x[0]'s oscillation over `periods` swings (upward zero crossings,
/// interpolated within a step).
template <int dim>
double swing_period(BowlScene<dim>& sim, int periods) {
    std::vector<double> crossings;
    double last = sim.particles().position()[0][0];
    while (static_cast<int>(crossings.size()) <= periods) {
        sim.step();
        const double now = sim.particles().position()[0][0];
        if (last < 0.0 && now >= 0.0) crossings.push_back(sim.time() - sim.time_step() * now / (now - last));
        last = now;
    }
    return (crossings.back() - crossings.front()) / periods;
}

}  // namespace

// Swings of theta0 = 0.02 rad: on a smooth bowl the particle slides, a pendulum of length R - a,
// T = 2 pi sqrt((R - a) / g) (1 + theta0^2 / 16); on a rough one it rolls without slipping, and
// its rotational inertia lengthens the period by sqrt(1 + I / (m a^2)), sqrt(7/5) for a sphere.
// What is left (3e-8) is the amplitude's next order, 11 theta0^4 / 3072, and the contact's
// compliance, m g / k over R - a.
BOOST_AUTO_TEST_CASE_TEMPLATE(a_particle_swings_in_a_bowl, D, Dims) {
    constexpr int dim = D::value;
    const double theta0 = 0.02, pendulum = 2.0 * std::numbers::pi * std::sqrt((R - a) / g) * (1.0 + theta0 * theta0 / 16.0);
    for (const bool smooth : {true, false}) {
        auto sim = particle_in_bowl<dim>(theta0, smooth);
        const double period = swing_period(sim, 3);
        const double expected = smooth ? pendulum : pendulum * std::sqrt(1.4);
        BOOST_TEST_MESSAGE(dim << "D " << (smooth ? "smooth" : "rough") << " bowl: T / expected - 1 = " << period / expected - 1.0);
        BOOST_TEST(std::abs(period / expected - 1.0) < 1e-6);
        if (smooth)  // no friction, no spin
            BOOST_TEST(mm::DimTraits<dim>::squared_norm(sim.particles().template get<mm::field::AngularVelocity>()[0]) == 0.0);
    }
}

// The bowl lifted by Eq. 17's ramp along its direction (2 mm over T/2 = 0.1 s) carries the
// resting particle the same distance, and at rest again the bowl's load, the particle's force on
// it along the direction, is the particle's weight.
BOOST_AUTO_TEST_CASE_TEMPLATE(a_moving_bowl_carries_its_particle_and_load, D, Dims) {
    constexpr int dim = D::value;
    const double travel = 2e-3;
    auto sim = particle_in_bowl<dim>(0.0, false, mm::StrainControlled{travel, 0.2});
    const mm::Vec<dim> start = sim.particles().position()[0];
    sim.run(static_cast<std::size_t>(0.15 / bowl_dt()));
    const auto& bowl = sim.walls()[0];
    BOOST_TEST(bowl.offset == travel);
    const mm::Vec<dim> moved = sim.particles().position()[0] - start;
    BOOST_TEST_MESSAGE(dim << "D: moved " << moved.transpose() << ", load / (m g) = " << bowl.load() / (m * g));
    BOOST_TEST(std::abs(moved[dim - 1] - travel) < 1e-6 * travel);
    BOOST_TEST(std::abs(moved[0]) < 1e-12);
    BOOST_TEST(std::abs(bowl.load() / (-m * g) - 1.0) < 1e-6);
}

// A state names its walls' shape: a bowl scene's state restores into a bowl scene bit for bit,
// and a plane scene refuses it, naming both shapes.
BOOST_AUTO_TEST_CASE_TEMPLATE(states_name_the_wall_shape, D, Dims) {
    constexpr int dim = D::value;
    const auto file = std::filesystem::temp_directory_path() / ("micromacro_bowl_" + std::to_string(dim) + ".bin");
    auto original = particle_in_bowl<dim>(0.02, false);
    original.run(2000);
    mm::io::save_state(original, file);
    auto restored = particle_in_bowl<dim>(0.0, true);
    mm::io::load_state(restored, file);
    original.run(2000);
    restored.run(2000);
    BOOST_TEST(restored.particles().position()[0] == original.particles().position()[0]);
    BOOST_TEST(restored.walls()[0].frictionless == false);
    mm::Walls<dim> plane;
    plane.add_axis_aligned(dim - 1, true, -R);
    mm::Simulation<dim, mm::FrictionalLinear, mm::Walls<dim>, mm::VelocityVerlet, mm::BruteForce, mm::Gravity<dim>> flat(
        law(), {}, plane, {}, {}, mm::Gravity<dim>{-g * up<dim>()});
    expect_error([&] { mm::io::load_state(flat, file); }, {"walls=spherical-bowl", "walls=plane"});
    std::filesystem::remove(file);
}

// What a bowl cannot do is refused up front: a direction that is not a unit vector, a
// stress-controlled motion without its own area (only an axis-aligned plane has the box's
// cross-section), an affine deformation (which maps planes only) and a periodic domain (a
// wall's distance is not wrapped).
BOOST_AUTO_TEST_CASE_TEMPLATE(what_a_bowl_cannot_do_is_refused, D, Dims) {
    constexpr int dim = D::value;
    Bowl<dim> bowl;
    expect_error([&] { bowl.add(SphericalBowl<dim>{mm::Vec<dim>::Zero(), R, 2.0 * up<dim>()}); },
                 {"spherical-bowl", "direction has length 2", "unit vector"});
    expect_error([&] { bowl.add(SphericalBowl<dim>{mm::Vec<dim>::Zero(), R, up<dim>()}, mm::StressControlled{10.0, 1e-3, 0.0}); },
                 {"not axis-aligned needs an explicit area"});
    auto sim = particle_in_bowl<dim>(0.0, false);
    sim.run(10);
    expect_error([&] { sim.deform_affinely(Eigen::Matrix<double, dim, dim>::Identity() * 0.999); },
                 {"maps plane walls only", "spherical-bowl"});
    Bowl<dim> fixed;
    fixed.add(SphericalBowl<dim>{mm::Vec<dim>::Zero(), R, up<dim>()});
    BowlScene<dim> periodic(law(), periodic_box<dim>(0.1), fixed, {}, {}, mm::Gravity<dim>{-g * up<dim>()});
    periodic.particles().add(mm::Vec<dim>::Constant(0.05) - R / 2 * up<dim>(), a, m);
    periodic.set_time_step(bowl_dt());
    expect_error([&] { periodic.prepare(); }, {"spherical-bowl", "periodic", "without periodic axes"});
}

BOOST_AUTO_TEST_SUITE_END()
