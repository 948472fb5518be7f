// run(n) merges one step's closing kick into the next step's pass over the particles (velocity
// Verlet) and lets the kick pass clear the force arrays; it must give exactly the bits of n
// calls of step(), in both precisions, with rotation, walls and neighbour-list rebuilds.
#include <boost/test/unit_test.hpp>

#include "support/scenes.hpp"

BOOST_AUTO_TEST_SUITE(unit_run_stages)  // the file's cases, run as the CTest test of this file's name

using namespace mmtest;

namespace {
template <int dim, class Real, class Integrator>
void check_run_equals_steps() {
    auto stepped = shaken_walled_packing<dim, Real, Integrator>(300, 5, 0.3);
    auto ran = shaken_walled_packing<dim, Real, Integrator>(300, 5, 0.3);
    const std::size_t steps = 2000;
    for (std::size_t s = 0; s < steps; ++s) stepped.step();
    ran.run(steps / 2);  // two runs: the second starts from a completed step
    ran.run(steps / 2);
    BOOST_TEST_REQUIRE(stepped.neighbor_rebuilds() > 3);  // the particles moved through the lists
    BOOST_TEST_REQUIRE(stepped.contact_count() > 100);
    BOOST_TEST(ran.steps_done() == steps);
    BOOST_TEST(ran.time() == stepped.time());
    BOOST_TEST(ran.neighbor_rebuilds() == stepped.neighbor_rebuilds());
    const auto& a = stepped.particles();
    const auto& b = ran.particles();
    std::size_t differ = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        differ += !(a.position()[i] == b.position()[i]) + !(a.velocity()[i] == b.velocity()[i]) +
                  !(a.force()[i] == b.force()[i]) +
                  !(a.template get<mm::field::AngularVelocity>()[i] == b.template get<mm::field::AngularVelocity>()[i]);
    }
    BOOST_TEST(differ == 0u);
    BOOST_TEST(ran.books().dissipated() == stepped.books().dissipated());
    BOOST_TEST(ran.energy().total() == stepped.energy().total());
    BOOST_TEST(ran.walls()[1].force == stepped.walls()[1].force);
}
}  // namespace

BOOST_AUTO_TEST_CASE_TEMPLATE(velocity_verlet_run_is_step_by_step, D, Dims) {
    check_run_equals_steps<D::value, double, mm::VelocityVerlet>();
    check_run_equals_steps<D::value, float, mm::VelocityVerlet>();
}

BOOST_AUTO_TEST_CASE_TEMPLATE(symplectic_euler_run_is_step_by_step, D, Dims) {
    check_run_equals_steps<D::value, double, mm::SymplecticEuler>();
    check_run_equals_steps<D::value, float, mm::SymplecticEuler>();
}

BOOST_AUTO_TEST_SUITE_END()
