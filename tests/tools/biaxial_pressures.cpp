// The biaxial preparation across pressures p/k = 1e-6 to 1e-2 (p d / k in 3D): the packing comes
// to rest with every wall at the target pressure and the largest overlap scales with p/k. With
// 60 particles the largest overlap is the largest of few contacts and depends on the packing: over
// seeds 1-7 in 3D it was 13-36 p/k of the smaller radius at p/k = 1e-6 and 1e-4, and 8-11 p/k at
// 1e-2, the pressure where the refusal above 1e-2 rests on it (overlaps of 10-20% of a radius
// beyond). The test asserts < 40 p/k, and < 15 p/k at 1e-2.
//
// A packing this small and this soft can creep instead of coming to rest: at p/k = 1e-6 in 3D,
// 1 of 11 seeds had a sphere rolling on two neighbours and sliding along a smooth wall at
// 4e-5 m/s for over a second, with the kinetic energy at 3e-5 of the elastic energy and rising;
// the same state run on at dt/4 creeps identically, so it is the physics of the packing, not the
// time step. The preparation then stops with its error naming the energy ratio and the fix, and
// the test takes the next seed (at most three).
#define BOOST_TEST_MODULE tools_biaxial_pressures
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <optional>
#include <string>

#include "biaxial/biaxial.hpp"
#include "support/expect_error.hpp"
#include "support/scenes.hpp"

namespace {
template <int dim>
biaxial::Config config_for(double pressure_over_stiffness) {
    biaxial::Config c;
    c.dim = dim;
    biaxial::apply_preset(c, "quick");
    c.particles = 60;  // the slowest case (3D, p/k = 1e-6) prepares in 1.5e6 steps
    c.pressure = dim == 2 ? pressure_over_stiffness * c.k : pressure_over_stiffness * c.k / (2 * c.mean_radius());
    return c;
}
}  // namespace

// Labelled long: 1.5e6 steps of the preparation that tools/biaxial.cpp and biaxial_float_rest.cpp
// take through shorter runs; the sanitizer build leaves it out (tests/CMakeLists.txt).
BOOST_TEST_DECORATOR(*boost::unit_test::label("long"))
BOOST_AUTO_TEST_CASE_TEMPLATE(prepared_at_every_pressure, D, mmtest::Dims) {
    constexpr int dim = D::value;
    for (double ratio : {1e-6, 1e-4, 1e-2}) {
        const auto c = config_for<dim>(ratio);
        BOOST_TEST_REQUIRE(c.pressure_over_stiffness() == ratio, boost::test_tools::tolerance(1e-12));
        biaxial::validate(c);
        std::optional<biaxial::Experiment<dim>> rested;
        for (unsigned long long seed = 1; seed <= 3 && !rested; ++seed) {
            auto seeded = c;
            seeded.seed = seed;
            biaxial::Experiment<dim> e(seeded);
            e.build();
            try {
                e.prepare();
                rested.emplace(std::move(e));
            } catch (const micromacro::InputError& error) {
                BOOST_TEST_MESSAGE(dim << "D p/k = " << ratio << ", seed " << seed << ": " << error.what());
                BOOST_TEST(std::string(error.what()).find("did not come to rest") != std::string::npos);
            }
        }
        BOOST_TEST_REQUIRE(rested.has_value(), "p/k = " << ratio << ": no seed of three came to rest");
        auto& e = *rested;
        const auto s = micromacro::take_snapshot(e.simulation());
        const auto wall = micromacro::wall_stress(s);
        double largest = 0.0;
        e.simulation().for_each_contact([&](const auto& contact) {
            const double a = contact.wall ? s.radius[contact.i] : std::min(s.radius[contact.i], s.radius[contact.j]);
            largest = std::max(largest, contact.geometry.overlap / a);
        });
        BOOST_TEST_MESSAGE(dim << "D p/k = " << ratio << ": " << e.simulation().steps_done() << " steps, largest overlap "
                               << largest / ratio << " p/k of the radius");
        // At rest each wall's push balances p (the walls' and particles' kinetic energy is below
        // 1e-6 of the elastic energy).
        for (int axis = 0; axis < dim; ++axis)
            BOOST_TEST(std::abs(wall(axis, axis) / c.pressure - 1) < 1e-3, "p/k = " << ratio << ", axis " << axis);
        BOOST_TEST(largest < (ratio < 1e-2 ? 40 : 15) * ratio, "p/k = " << ratio);
        BOOST_TEST(largest > 2 * ratio, "p/k = " << ratio);  // the overlap does scale with p/k
    }
}

BOOST_AUTO_TEST_CASE_TEMPLATE(pressure_above_the_small_overlap_range_is_refused, D, mmtest::Dims) {
    const auto c = config_for<D::value>(2e-2);
    mmtest::expect_error([&] { biaxial::validate(c); }, {"p/k = 0.02", "above 1e-2", "use --pressure <= "});
}
