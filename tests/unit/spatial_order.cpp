// sort_spatially(): renumbering the particles in row order (spatial_order) brings partners close
// in memory and changes no physics. Every contact keeps its force to the last bit (a pair whose
// partners swap roles sees exactly the negated force, its tangential spring is negated), and
// the run continues on the same trajectory up to the round-off of another summation order.
#define BOOST_TEST_MODULE unit_spatial_order
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <map>

#include "support/scenes.hpp"

using namespace mmtest;

namespace {
template <int dim>
auto shaken_packing() {
    auto sim = shaken_walled_packing<dim>(2000, 7, 0.3);
    sim.run(500);  // contacts with loaded, partly sliding tangential springs
    return sim;
}

// The median over contacts of |i - j| (the jumps between rows and layers would dominate a mean).
template <class Sim>
double median_index_distance(const Sim& sim) {
    std::vector<double> d;
    sim.for_each_contact([&](const auto& c) {
        if (!c.wall) d.push_back(std::abs(double(c.i) - double(c.j)));
    });
    std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
    return d[d.size() / 2];
}
}  // namespace

BOOST_AUTO_TEST_CASE_TEMPLATE(renumbering_keeps_every_contact_force_to_the_bit, D, Dims) {
    constexpr int dim = D::value;
    auto kept = shaken_packing<dim>();
    auto sorted = shaken_packing<dim>();
    const double before = median_index_distance(sorted);
    const std::vector<mm::Index> order = sorted.sort_spatially();
    const double after = median_index_distance(sorted);
    BOOST_TEST_MESSAGE(dim << "D: median |i - j| over contacts " << before << " -> " << after << " (n = 2000)");
    BOOST_TEST(before > 300.0);  // random placement: partners anywhere
    BOOST_TEST(after < before / 10);

    // A permutation, with every per-particle field moved along.
    std::vector<bool> seen(order.size(), false);
    for (mm::Index o : order) seen.at(o) = true;
    BOOST_TEST(std::count(seen.begin(), seen.end(), true) == static_cast<long>(order.size()));
    for (std::size_t k2 = 0; k2 < order.size(); ++k2) {
        BOOST_TEST_REQUIRE((sorted.particles().position()[k2] == kept.particles().position()[order[k2]]));
        BOOST_TEST_REQUIRE((sorted.particles().velocity()[k2] == kept.particles().velocity()[order[k2]]));
        BOOST_TEST_REQUIRE(sorted.particles().radius()[k2] == kept.particles().radius()[order[k2]]);
        BOOST_TEST_REQUIRE((sorted.particles().template get<mm::field::AngularVelocity>()[k2] ==
                            kept.particles().template get<mm::field::AngularVelocity>()[order[k2]]));
    }

    // Every contact, found by its particles' old numbers: the same force, exactly.
    std::map<std::pair<mm::Index, mm::Index>, mm::ContactView<dim>> old_contacts;
    kept.for_each_contact([&](const mm::ContactView<dim>& c) { old_contacts.emplace(std::make_pair(c.i, c.wall ? ~c.j : c.j), c); });
    std::size_t matched = 0, turned = 0, sliding = 0, differ = 0;
    sorted.for_each_contact([&](const mm::ContactView<dim>& c) {
        mm::Index i = order[c.i], j = c.wall ? ~c.j : order[c.j];
        double sign = 1.0;
        if (!c.wall && j < i) {
            std::swap(i, j);
            sign = -1.0;
            ++turned;
        }
        const auto found = old_contacts.find({i, j});
        if (found == old_contacts.end()) return;
        ++matched;
        sliding += c.sliding;
        const auto& o = found->second;
        differ += !(c.force() == mm::Vec<dim>(sign * o.force())) + !(c.elastic_energy == o.elastic_energy) +
                  !(c.sliding == o.sliding);
    });
    BOOST_TEST(matched == old_contacts.size());
    BOOST_TEST(matched == sorted.contact_count());
    BOOST_TEST(turned > 0u);
    BOOST_TEST(differ == 0u);
    BOOST_TEST_MESSAGE(dim << "D: " << matched << " contacts, " << turned << " turned round, " << sliding << " sliding");

    // The trajectory goes on: the same up to round-off of the summation order.
    kept.run(500);
    sorted.run(500);
    double worst = 0.0;
    for (std::size_t k2 = 0; k2 < order.size(); ++k2)
        worst = std::max(worst, kept.domain().separation(sorted.particles().position()[k2], kept.particles().position()[order[k2]]).norm());
    BOOST_TEST_MESSAGE(dim << "D: largest position difference after 500 more steps: " << worst << " m");
    BOOST_TEST(worst < 1e-12);  // radii 5e-4..1.5e-3 m
    BOOST_TEST(std::abs(sorted.books().dissipated() / kept.books().dissipated() - 1.0) < 1e-10);
}
