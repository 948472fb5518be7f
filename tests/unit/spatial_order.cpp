// sort_spatially(): renumbering the particles in row order (spatial_order) brings partners close
// in memory and changes no physics. Every contact keeps its force to the last bit (a pair whose
// partners swap roles sees exactly the negated force, its tangential spring is negated), and
// the run continues on the same trajectory up to the round-off of another summation order.
// Built with MICROMACRO_FMA (fused multiply-adds) a contact's arithmetic is not symmetric in its
// two particles (a b + c d fuses one product or the other), and a swapped pair's force and
// energy agree to round-off instead of to the bit. The engine sorts on its own from 2048
// particles; a scene assembled elsewhere takes over when the next neighbour search falls
// (search_state).
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <string>
#include <map>
#include <numeric>
#include <random>

#include <micromacro/io/state.hpp>

#include "support/expect_error.hpp"
#include "support/scenes.hpp"

BOOST_AUTO_TEST_SUITE(unit_spatial_order)  // the file's cases, run as the CTest test of this file's name

using namespace mmtest;

namespace {
template <int dim>
auto shaken_packing() {
    auto sim = shaken_walled_packing<dim>(2000, 7, 0.3);
    sim.set_auto_sort(false);  // in the order of placement, partners anywhere (the test sorts)
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
    double worst_force = 0.0;
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
        worst_force = std::max(worst_force, (c.force() - sign * o.force()).norm() / o.force().norm());
#ifdef MICROMACRO_FP_CONTRACT
        const bool same_force = (c.force() - sign * o.force()).norm() <= 1e-12 * o.force().norm();  // measured 3e-14 (2D), 5e-15 (3D)
        const bool same_energy = std::abs(c.elastic_energy() - o.elastic_energy()) <= 1e-12 * o.elastic_energy();
#else
        const bool same_force = c.force() == mm::Vec<dim>(sign * o.force());
        const bool same_energy = c.elastic_energy() == o.elastic_energy();
#endif
        differ += !same_force + !same_energy + !(c.sliding == o.sliding);
    });
    BOOST_TEST(matched == old_contacts.size());
    BOOST_TEST(matched == sorted.contact_count());
    BOOST_TEST(turned > 0u);
    BOOST_TEST(differ == 0u);
    BOOST_TEST_MESSAGE(dim << "D: " << matched << " contacts, " << turned << " turned round, " << sliding
                           << " sliding; largest relative force difference " << worst_force);

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

// The order itself, exactly: a grid of particles in a box elongated differently along each axis
// (extents 40, 7 and 3 spacings, the long axis first), numbered at random, comes out in row
// order with the shortest axis fastest: particle k sits at grid index (k / (7 * 3), (k / 3) % 7,
// k % 3) in 3D and (k / 7, k % 7) in 2D. Partners then lie 1, one row or one layer apart.
BOOST_AUTO_TEST_CASE_TEMPLATE(row_order_runs_along_the_shortest_axis_first, D, Dims) {
    constexpr int dim = D::value;
    const std::array<int, 3> extent{40, 7, 3};
    const double spacing = 2e-3, a = 0.45 * spacing;
    std::vector<mm::Vec<dim>> x;
    std::vector<double> r;
    std::array<int, 3> g{0, 0, 0};
    for (g[0] = 0; g[0] < extent[0]; ++g[0])
        for (g[1] = 0; g[1] < extent[1]; ++g[1])
            for (g[2] = 0; g[2] < (dim == 3 ? extent[2] : 1); ++g[2]) {
                mm::Vec<dim> p;
                // Off the grid by 0.1-0.2 spacings, except the first particle, which sets the cells'
                // origin: every cell edge then lies clear of the particles.
                for (int k = 0; k < dim; ++k) {
                    const double s = std::sin(7.0 * double(x.size()) + k);
                    p[k] = (g[k] + 0.25) * spacing + (x.empty() ? 0.0 : (0.1 + 0.1 * s * s) * spacing);
                }
                x.push_back(p);
                r.push_back(a);
            }
    std::vector<std::size_t> shuffled(x.size());
    std::iota(shuffled.begin(), shuffled.end(), std::size_t{0});
    std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(5));
    std::vector<mm::Vec<dim>> xs;
    for (std::size_t s : shuffled) xs.push_back(x[s]);
    const mm::Domain<dim> open;  // no periodic axes: the extents are the particles'
    const std::vector<mm::Index> order = mm::spatial_order(xs, r, open, spacing);
    std::size_t wrong = 0;
    for (std::size_t k = 0; k < order.size(); ++k) {
        const mm::Vec<dim>& p = xs[order[k]];
        const std::size_t layer = extent[1], row = dim == 3 ? extent[2] : 1;  // grid points along the faster axes
        const std::array<std::size_t, 3> expected{k / (layer * row), (k / row) % layer, k % row};
        for (int c = 0; c < dim; ++c) wrong += static_cast<std::size_t>(std::floor(p[c] / spacing)) != expected[c];
    }
    BOOST_TEST(wrong == 0u);
}

// The engine sorts on its own (set_auto_sort, on by default) in scenes of
// auto_sort_min_particles or more: when it first builds its neighbour lists, and again at a
// rebuild that finds the candidates' mean index distance doubled since the last sort. Ids follow
// the particles, and the run is the unsorted scene's up to the round-off of another summation
// order. Below the threshold, and with the option off, the particles keep their numbers.
BOOST_AUTO_TEST_CASE_TEMPLATE(the_engine_sorts_on_its_own_and_ids_follow, D, Dims) {
    constexpr int dim = D::value;
    const std::size_t n = 3000;  // randomly placed: partners anywhere in the numbering
    auto kept = shaken_walled_packing<dim>(n, 7, 0.3);
    BOOST_TEST_REQUIRE(n >= kept.auto_sort_min_particles);
    kept.set_auto_sort(false);
    auto sorted = shaken_walled_packing<dim>(n, 7, 0.3);
    BOOST_TEST(sorted.auto_sort());
    kept.prepare();
    sorted.prepare();
    BOOST_TEST(kept.spatial_sorts() == 0u);
    BOOST_TEST(sorted.spatial_sorts() == 1u);
    const double before = median_index_distance(kept), after = median_index_distance(sorted);
    BOOST_TEST_MESSAGE(dim << "D: median |i - j| over contacts " << before << " in the given order, " << after << " sorted by the engine");
    BOOST_TEST(after < before / 10);

    // The ids: the given order's are the indices; the sorted scene's lead to the same particles.
    for (std::size_t i = 0; i < n; ++i) BOOST_TEST_REQUIRE(kept.particles().id(i) == i);
    const std::vector<mm::Index> where = sorted.particles().index_by_id();
    for (std::size_t id = 0; id < n; ++id) {
        BOOST_TEST_REQUIRE(sorted.particles().id(where[id]) == id);
        BOOST_TEST_REQUIRE((sorted.particles().position()[where[id]] == kept.particles().position()[id]));
        BOOST_TEST_REQUIRE(sorted.particles().radius()[where[id]] == kept.particles().radius()[id]);
    }
    // The order decays (here at once: the caller numbers the particles at random); the next
    // neighbour search sorts them again, and the springs keep their pairs through both.
    std::vector<mm::Index> random(n);
    std::iota(random.begin(), random.end(), mm::Index{0});
    std::shuffle(random.begin(), random.end(), std::mt19937(11));
    sorted.renumber(random);
    BOOST_TEST(median_index_distance(sorted) > 10 * after);
    kept.prepare();  // a neighbour search (as after set_skin or added particles), in both
    sorted.prepare();
    BOOST_TEST(sorted.spatial_sorts() == 2u);
    BOOST_TEST(median_index_distance(sorted) < 2 * after);

    kept.run(500);
    sorted.run(500);
    const std::vector<mm::Index> now = sorted.particles().index_by_id();
    double worst = 0.0;
    for (std::size_t id = 0; id < n; ++id)
        worst = std::max(worst, kept.domain().separation(sorted.particles().position()[now[id]], kept.particles().position()[id]).norm());
    BOOST_TEST_MESSAGE(dim << "D: largest position difference after 500 steps: " << worst << " m");
    BOOST_TEST(worst < 1e-12);  // radii 5e-4..1.5e-3 m
    BOOST_TEST(std::abs(sorted.books().dissipated() / kept.books().dissipated() - 1.0) < 1e-10);
    BOOST_TEST(kept.spatial_sorts() == 0u);

    // Below the threshold the engine leaves the numbering alone.
    auto small = shaken_walled_packing<dim>(500, 7, 0.3);
    small.prepare();
    BOOST_TEST(small.spatial_sorts() == 0u);
    BOOST_CHECK_THROW(sorted.renumber(std::vector<mm::Index>(n, 0)), std::invalid_argument);
    BOOST_CHECK_THROW(sorted.renumber(std::vector<mm::Index>(n - 1, 0)), std::invalid_argument);
}

// set_pair_order: the scene sorted in row order but with its pairs ordered by the particles'
// former numbers (their keys) sums every particle's forces as the unsorted scene does, each pair
// turned as there: 500 steps later every position, velocity, angular velocity, force and torque
// is the unsorted run's to the bit, with fused multiply-adds too (each contact's arithmetic runs
// as in the unsorted scene). How the ranks of a distributed run sum in the serial order. Keys
// for another particle count or one key twice are refused, and so is saving the scene's state.
BOOST_AUTO_TEST_CASE_TEMPLATE(pairs_in_the_order_of_keys_sum_as_that_numbering_does, D, Dims) {
    constexpr int dim = D::value;
    auto kept = shaken_packing<dim>();
    auto sorted = kept;
    const std::vector<mm::Index> order = sorted.sort_spatially();
    sorted.set_pair_order(std::vector<std::uint64_t>(order.begin(), order.end()));  // the unsorted numbers
    auto plain = sorted;  // sorted, pairs by index: another order of the sums
    plain.set_pair_order({});
    kept.run(500);
    sorted.run(500);
    plain.run(500);
    const auto& a = kept.particles();
    const auto& b = sorted.particles();
    std::size_t differ = 0, differ_plain = 0;
    for (std::size_t k = 0; k < order.size(); ++k) {
        const std::size_t o = order[k];
        differ += !(b.position()[k] == a.position()[o] && b.velocity()[k] == a.velocity()[o] && b.force()[k] == a.force()[o] &&
                    b.template get<mm::field::AngularVelocity>()[k] == a.template get<mm::field::AngularVelocity>()[o] &&
                    b.template get<mm::field::Torque>()[k] == a.template get<mm::field::Torque>()[o]);
        differ_plain += !(plain.particles().position()[k] == a.position()[o]);
    }
    BOOST_TEST_MESSAGE(dim << "D: " << differ << " particles differ from the unsorted run with the pairs in key order, "
                           << differ_plain << " of " << order.size() << " positions in index order");
    BOOST_TEST(differ == 0u);
    BOOST_TEST(differ_plain > 0u);  // the test sees the order of the sums
    BOOST_TEST(sorted.contact_count() == kept.contact_count());

    // Keys are not part of a state, whose pairs go in index order: a scene with keys saves none.
    const auto file = std::filesystem::temp_directory_path() / ("keyed_" + std::to_string(dim) + "d.state");
    std::filesystem::remove(file);
    mmtest::expect_error([&] { mm::io::save_state(sorted, file); }, {"set_pair_order({})", "no state to save"});
    BOOST_TEST(!std::filesystem::exists(file));
    mmtest::expect_error([&] { sorted.set_pair_order({1, 2, 3}); }, {"3 keys", "2000 particles"});
    std::vector<std::uint64_t> twice(order.size());
    std::iota(twice.begin(), twice.end(), std::uint64_t{0});
    twice[7] = 3;
    mmtest::expect_error([&] { sorted.set_pair_order(twice); }, {"the key 3", "two particles"});
}

// What the next neighbour search waits on (search_state) goes to a scene assembled elsewhere:
// a copy whose lists were built again (prepare()) well after the original's last search searches
// at other steps; given the original's state it searches at the original's steps, and sorts as
// often. Sizes are checked.
BOOST_AUTO_TEST_CASE_TEMPLATE(a_search_state_carries_the_searches, D, Dims) {
    constexpr int dim = D::value;
    auto original = shaken_walled_packing<dim>(3000, 7, 0.03);
    original.prepare();
    std::size_t quiet = 0;  // steps since the original's last search
    for (int s = 0; s < 2000 && quiet < 5; ++s) {
        const std::size_t before = original.neighbor_rebuilds();
        original.step();
        quiet = original.neighbor_rebuilds() == before ? quiet + 1 : 0;
    }
    BOOST_TEST_REQUIRE(quiet == 5u);
    const auto state = original.search_state();
    auto rebuilt = original, carried = original;
    rebuilt.prepare();  // the lists built again now: searches count from here
    carried.prepare();
    carried.restore_search_state(state);
    auto searches = [](auto& sim) {  // the steps at which the next 400 steps search
        std::vector<std::size_t> at;
        for (int s = 0; s < 400; ++s) {
            const std::size_t before = sim.neighbor_rebuilds();
            sim.step();
            if (sim.neighbor_rebuilds() != before) at.push_back(sim.steps_done());
        }
        return at;
    };
    const auto at_original = searches(original), at_rebuilt = searches(rebuilt), at_carried = searches(carried);
    BOOST_TEST_MESSAGE(dim << "D: " << at_original.size() << " searches in 400 steps; the first at step "
                           << (at_original.empty() ? 0 : at_original.front()) << ", the rebuilt copy's at "
                           << (at_rebuilt.empty() ? 0 : at_rebuilt.front()));
    BOOST_TEST_REQUIRE(at_original.size() > 2u);
    BOOST_TEST(at_carried == at_original, boost::test_tools::per_element());
    BOOST_TEST((at_rebuilt != at_original), "the copy built again searches elsewhere: else the test would not see the state");
    BOOST_TEST(carried.spatial_sorts() == original.spatial_sorts());

    auto wrong = state;
    wrong.particles.pop_back();
    mmtest::expect_error([&] { carried.restore_search_state(wrong); }, {"positions of 2999 particles", "3000 particles", "prepare()"});
}

BOOST_AUTO_TEST_SUITE_END()
