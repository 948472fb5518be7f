// The biaxial test's initial placement (Experiment::build): random sequential addition in a box
// twice the expected side, each new particle checked against the particles placed so far in its
// own and the neighbouring cells of a grid at least two largest radii wide. Every particle lies
// inside the walls and overlaps no other: checked against every other particle at a few thousand,
// and by the engine's own contact search (no contact at all) at 200 000, a size that checking
// every placed particle (quadratic in N) took about a minute to place (16 s at 100 000 in 3D).
#define BOOST_TEST_MODULE tools_biaxial_placement
#include <boost/test/unit_test.hpp>

#include <cstddef>

#include "biaxial/biaxial.hpp"
#include "support/scenes.hpp"

namespace {
template <int dim>
biaxial::Config config_of(std::size_t particles, unsigned long long seed) {
    biaxial::Config c;
    c.dim = dim;
    biaxial::apply_preset(c, "quick");
    c.particles = particles;
    c.seed = seed;
    return c;
}
}  // namespace

BOOST_AUTO_TEST_CASE_TEMPLATE(no_particle_overlaps_another_or_a_wall, D, mmtest::Dims) {
    constexpr int dim = D::value;
    for (const unsigned long long seed : {1ull, 2ull}) {
        const auto c = config_of<dim>(3000, seed);
        biaxial::Experiment<dim> e(c);
        e.build();
        const auto& p = e.simulation().particles();
        BOOST_TEST_REQUIRE(p.size() == c.particles);
        const double L = c.box_factor * c.expected_side();
        for (std::size_t i = 0; i < p.size(); ++i) {
            const double a = p.radius()[i];
            BOOST_TEST_REQUIRE((a >= c.radius_min && a <= c.radius_max));
            for (int k = 0; k < dim; ++k) BOOST_TEST_REQUIRE((p.position()[i][k] >= a && p.position()[i][k] <= L - a));
            for (std::size_t j = 0; j < i; ++j)
                BOOST_TEST_REQUIRE((p.position()[i] - p.position()[j]).norm() > a + p.radius()[j], dim << "D: " << i << " and " << j);
        }
        BOOST_TEST(e.simulation().contact_count() == 0u);
    }
}

BOOST_AUTO_TEST_CASE_TEMPLATE(large_boxes_are_placed_without_contacts, D, mmtest::Dims) {
    constexpr int dim = D::value;
    const auto c = config_of<dim>(200000, 3);
    biaxial::Experiment<dim> e(c);
    e.build();
    BOOST_TEST(e.simulation().particles().size() == c.particles);
    BOOST_TEST(e.simulation().contact_count() == 0u);
}
