// Particle fields by name, storage that follows the scene, and contact history that survives a
// neighbour-list rebuild.
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <random>

#include "support/scenes.hpp"

BOOST_AUTO_TEST_SUITE(unit_storage)  // the file's cases, run as the CTest test of this file's name

using namespace mmtest;

BOOST_AUTO_TEST_CASE_TEMPLATE(fields_by_name, D, Dims) {
    constexpr int dim = D::value;
    mm::Particles<dim, true> p;
    const mm::Vec<dim> x = mm::Vec<dim>::Constant(0.25);
    p.add(x, 2e-3, 3.0);
    p.add(x, 1e-3, 1.0, 7.0);
    BOOST_TEST(p.size() == 2u);
    BOOST_TEST((p.template get<mm::field::Position>()[0] == x));
    BOOST_TEST(p.template get<mm::field::Radius>()[0] == 2e-3);
    BOOST_TEST(p.template get<mm::field::InverseMass>()[0] == 1.0 / 3.0);
    BOOST_TEST(p.template get<mm::field::Inertia>()[0] == mm::sphere_inertia(3.0, 2e-3));  // the default
    BOOST_TEST(p.template get<mm::field::Inertia>()[1] == 7.0);
    p.set_mass(1, 2.0);
    BOOST_TEST(p.template get<mm::field::InverseMass>()[1] == 0.5);
    // Angular velocity is a scalar in 2D and a vector in 3D.
    static_assert(std::is_same_v<std::decay_t<decltype(p.template get<mm::field::AngularVelocity>()[0])>,
                                 std::conditional_t<dim == 2, double, Eigen::Vector3d>>);
}

// reserve(n) makes room in every field: adding n particles then never reallocates (no
// doubling, no two copies alive at once), with and without rotational fields.
template <int dim, bool rotation>
void check_reserve() {
    mm::Particles<dim, rotation> p;
    p.reserve(1000);
    const auto* x = p.position().data();
    const auto* r = p.radius().data();
    const auto* inv_m = p.template get<mm::field::InverseMass>().data();
    for (int i = 0; i < 1000; ++i) p.add(mm::Vec<dim>::Constant(i), 1e-3, 1.0);
    BOOST_TEST(p.position().data() == x);
    BOOST_TEST(p.radius().data() == r);
    BOOST_TEST(p.template get<mm::field::InverseMass>().data() == inv_m);
    BOOST_TEST(p.position().capacity() == 1000u);
    BOOST_TEST(p.template get<mm::field::Force>().capacity() == 1000u);
    if constexpr (rotation) {
        BOOST_TEST(p.template get<mm::field::Torque>().capacity() == 1000u);
        BOOST_TEST(p.template get<mm::field::InverseInertia>().capacity() == 1000u);
    }
}
BOOST_AUTO_TEST_CASE_TEMPLATE(reserve_makes_room_in_every_field, D, Dims) {
    check_reserve<D::value, false>();
    check_reserve<D::value, true>();
}

BOOST_AUTO_TEST_CASE(scenes_store_only_what_they_use) {
    // No rotational arrays without rotation, no history without a tangential law, no wall lists
    // without walls.
    using P2 = mm::Particles<2, false>;
    using P2r = mm::Particles<2, true>;
    using P3r = mm::Particles<3, true>;
    BOOST_TEST(sizeof(P2) < sizeof(P2r));
    // position, velocity, force; radius, mass, 1/mass; the id; with rotation angular velocity,
    // torque, inertia, 1/inertia
    BOOST_TEST(P2().bytes_per_particle() == 3 * 16u + 3 * 8u + 4u);
    BOOST_TEST(P2r().bytes_per_particle() == 3 * 16u + 3 * 8u + 4u + 2 * 8u + 2 * 8u);
    BOOST_TEST(P3r().bytes_per_particle() == 3 * 24u + 3 * 8u + 4u + 2 * 24u + 2 * 8u);
    static_assert(!mm::ContactList<mm::NoHistory>::has_history);
    static_assert(mm::ContactList<mm::TangentialSpring<2>>::has_history);
    static_assert(sizeof(mm::ContactList<mm::NoHistory>) < sizeof(mm::ContactList<mm::TangentialSpring<2>>));
    // A spring's record: in 2D two numbers along the tangent, in 3D two vectors, each with the
    // last trial force (float) and three flags.
    BOOST_TEST(sizeof(mm::TangentialSpring<2>) == 2 * 8u + 4u + 4u);
    BOOST_TEST(sizeof(mm::TangentialSpring<3>) == 2 * 24u + 4u + 4u);
    using Frictionless = mm::Simulation<2, mm::FrictionlessLinear>;
    using Frictional = mm::Simulation<2, mm::FrictionalLinear>;
    using WithWalls = mm::Simulation<2, mm::FrictionlessLinear, mm::Walls<2>>;
    using NonRotating = mm::Simulation<2, mm::FrictionalLinearWithoutRotation>;
    static_assert(!Frictionless::rotation && Frictional::rotation);
    // Friction without rotation: the springs, but none of the angular fields.
    static_assert(!NonRotating::rotation && NonRotating::has_tangential);
    static_assert(std::is_same_v<NonRotating::History, Frictional::History>);
    static_assert(std::is_same_v<std::decay_t<decltype(std::declval<NonRotating&>().particles())>, P2>);
    static_assert(!Frictionless::has_walls && WithWalls::has_walls);
    BOOST_TEST(sizeof(Frictionless) < sizeof(Frictional));
    BOOST_TEST(sizeof(Frictionless) < sizeof(WithWalls));
}

BOOST_AUTO_TEST_CASE(history_survives_rebuild) {
    mm::ContactList<mm::TangentialSpring<2>> list;
    list.scratch() = {{0, 1}, {0, 5}, {2, 3}, {4, 9}};
    list.commit_scratch();
    list.history(1).spring = 1.5;  // (0, 5)
    list.history(3).spring = 2.5;  // (4, 9)
    list.history(3).sliding = true;
    // (0, 1) and (2, 3) leave, (1, 2) and (4, 7) arrive, (0, 5) and (4, 9) stay.
    list.scratch() = {{0, 5}, {1, 2}, {4, 7}, {4, 9}};
    list.commit_scratch();
    BOOST_TEST(list.size() == 4u);
    BOOST_TEST(list.history(0).spring == 1.5);
    BOOST_TEST(list.history(1).spring == 0.0);
    BOOST_TEST(list.history(2).spring == 0.0);
    BOOST_TEST(list.history(3).spring == 2.5);
    BOOST_TEST(list.history(3).sliding);
    BOOST_TEST(list.scratch().empty());
}

BOOST_AUTO_TEST_CASE_TEMPLATE(domain_minimum_image_and_wrap, D, Dims) {
    constexpr int dim = D::value;
    using V = mm::Vec<dim>;
    std::array<bool, dim> periodic{};
    periodic[0] = true;
    const mm::Domain<dim> box(V::Zero(), V::Constant(1.0), periodic);
    V a = V::Constant(0.5), b = V::Constant(0.5);
    a[0] = 0.95;
    b[0] = 0.05;
    BOOST_TEST(std::abs(box.separation(a, b)[0] - (-0.1)) < 1e-15);  // through the boundary
    a[1] = 0.95;
    b[1] = 0.05;
    BOOST_TEST(std::abs(box.separation(a, b)[1] - 0.9) < 1e-15);  // axis 1 is not periodic
    // The image of wrapped positions, one period off, to the bit of d - L round(d / L), on a
    // period that is not a power of two, with far apart (unwrapped) positions rounded as before.
    const mm::Domain<dim> odd(V::Constant(-0.3), V::Constant(0.7123), periodic);
    const double L = 0.7123 + 0.3;
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> inside(-0.3, 0.7123), far(-5.0, 5.0);
    bool same = true;
    for (int k = 0; k < 20000; ++k) {
        V p = V::Zero(), q = V::Zero();
        p[0] = inside(rng), q[0] = k % 4 == 0 ? far(rng) : inside(rng);
        const double d = p[0] - q[0];
        const double expected = std::abs(d) >= 0.5 * L ? d - L * std::round(d / L) : d;
        same &= odd.separation(p, q)[0] == expected;
    }
    BOOST_TEST(same);
    V h = V::Zero(), z = V::Zero();
    h[0] = 0.5 * L;  // half a period: both images are as near, the one rounding gives
    BOOST_TEST(odd.separation(h, z)[0] == 0.5 * L - L * std::round(0.5));
    BOOST_TEST(odd.separation(z, h)[0] == -0.5 * L + L);
    V c = V::Constant(0.5);
    c[0] = 2.25;
    box.wrap(c);
    BOOST_TEST(std::abs(c[0] - 0.25) < 1e-15);
    c[0] = -1e-18;  // rounds to 1.0 after the shift: must land inside [0, 1)
    box.wrap(c);
    BOOST_TEST((c[0] >= 0.0 && c[0] < 1.0));
}

BOOST_AUTO_TEST_SUITE_END()
