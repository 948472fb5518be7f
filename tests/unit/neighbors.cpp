// Neighbour search: linked cells find exactly the pairs brute force finds, on polydisperse
// packings (size ratio 1:10), open and periodic, 2D and 3D; a search window (an MPI rank's slab
// of a periodic box) finds the periodic search's pairs and the engine the same forces; and
// results do not depend on the order of the particles.
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <numeric>

#include "support/scenes.hpp"

BOOST_AUTO_TEST_SUITE(unit_neighbors)  // the file's cases, run as the CTest test of this file's name

using namespace mmtest;

BOOST_AUTO_TEST_CASE_TEMPLATE(linked_cells_equal_brute_force, D, Dims) {
    constexpr int dim = D::value;
    for (bool periodic : {false, true})
        for (unsigned seed : {1u, 2u, 3u}) {
            const double L = dim == 2 ? 0.03 : 0.012;
            // Overlapping placement (dense, many pairs) with radii from 0.1 to 1 mm: ratio 1:10.
            const auto p = random_packing<dim>(dim == 2 ? 1500 : 1500, 1e-4, 1e-3, L, seed, true, periodic);
            const auto domain = periodic ? periodic_box<dim>(L) : mm::Domain<dim>();
            for (double skin : {0.0, 1e-4}) {
                std::vector<mm::IndexPair> cells, brute;
                mm::LinkedCells().find_pairs(p.x, p.r, domain, skin, cells);
                mm::BruteForce().find_pairs(p.x, p.r, domain, skin, brute);
                BOOST_TEST_REQUIRE(brute.size() > p.x.size());  // a real test: many pairs
                BOOST_TEST(std::is_sorted(cells.begin(), cells.end()));
                BOOST_TEST((cells == brute), "linked cells found " << cells.size() << " pairs, brute force " << brute.size());
            }
        }
}

// Few cells per periodic axis (two offsets reach the same cell) and one particle far away
// (the grid must coarsen instead of growing without bound).
BOOST_AUTO_TEST_CASE_TEMPLATE(linked_cells_edge_cases, D, Dims) {
    constexpr int dim = D::value;
    const double a = 1e-3, L = 5.5e-3;  // 2.75 interaction ranges: two cells per axis
    const auto p = random_packing<dim>(20, a, a, L, 5, true, true);
    std::vector<mm::IndexPair> cells, brute;
    mm::LinkedCells().find_pairs(p.x, p.r, periodic_box<dim>(L), 0.0, cells);
    mm::BruteForce().find_pairs(p.x, p.r, periodic_box<dim>(L), 0.0, brute);
    BOOST_TEST(!brute.empty());
    BOOST_TEST((cells == brute));

    auto q = random_packing<dim>(500, a, a, 0.02, 6, true, false);
    q.x.push_back(mm::Vec<dim>::Constant(1e6));  // a runaway
    q.r.push_back(a);
    cells.clear();
    brute.clear();
    mm::LinkedCells().find_pairs(q.x, q.r, mm::Domain<dim>(), 0.0, cells);
    mm::BruteForce().find_pairs(q.x, q.r, mm::Domain<dim>(), 0.0, brute);
    BOOST_TEST((cells == brute));
}

// Particles in a band across the periodic boundary of axis 0 (as an MPI rank holds them: its slab
// and ghosts, wrapped into the box): binned in a window of one period around the band, as along
// an open axis, linked cells find the pairs the periodic search finds, and an engine with the
// window steps to the same bits as one without (the pairs are measured by the minimum image in
// both).
BOOST_AUTO_TEST_CASE_TEMPLATE(a_search_window_finds_the_periodic_pairs, D, Dims) {
    constexpr int dim = D::value;
    const double L = dim == 2 ? 0.03 : 0.012, skin = 1e-4;
    auto p = random_packing<dim>(dim == 2 ? 600 : 700, 0.5e-3, 1.5e-3, L, 4, true, true);
    std::vector<mm::Vec<dim>> x;
    std::vector<double> r;
    for (std::size_t i = 0; i < p.x.size(); ++i)  // the band -L/5 <= x_0 < L/5, wrapped
        if (p.x[i][0] < 0.2 * L || p.x[i][0] >= 0.8 * L) x.push_back(p.x[i]), r.push_back(p.r[i]);
    const auto box = periodic_box<dim>(L);
    mm::SearchWindow<dim> window;
    window.unwrap[0] = true;
    window.origin[0] = -0.5 * L;  // [-L/2, L/2): the band lies within, away from both ends
    std::vector<mm::Vec<dim>> mapped;
    std::vector<mm::IndexPair> periodic, windowed;
    mm::LinkedCells().find_pairs(x, r, box, skin, periodic);
    mm::LinkedCells().find_pairs(window.map(x, box, mapped), r, window.search_domain(box), skin, windowed);
    BOOST_TEST_REQUIRE(periodic.size() > x.size());
    std::size_t across = 0;  // pairs across the boundary: the case the window is for
    for (const auto& q : periodic) across += std::abs(x[q.i][0] - x[q.j][0]) > 0.5 * L;
    BOOST_TEST(across > 20u);
    BOOST_TEST(!window.search_domain(box).periodic(0));
    BOOST_TEST((windowed == periodic), "the window found " << windowed.size() << " pairs, the periodic search " << periodic.size());

    auto run = [&](bool windowed_search) {
        mm::Simulation<dim, mm::FrictionalLinear> sim(
            mm::FrictionalLinear{mm::LinearSpringDashpot(k, gamma0), mm::CundallStrack(0.2 * k, 0.2 * gamma0, 0.5)}, box);
        for (std::size_t i = 0; i < x.size(); ++i) sim.particles().add(x[i], r[i], mm::sphere_mass(rho, r[i]));
        sim.set_time_step(mm::contact_duration(k, gamma0, mm::sphere_mass(rho, 0.5e-3) / 2) / 50);
        sim.set_skin(skin);
        if (windowed_search) sim.set_search_window(window);
        sim.run(100);  // overlapping: the band expands, the lists are rebuilt
        return sim;
    };
    const auto plain = run(false), with_window = run(true);
    BOOST_TEST(plain.neighbor_rebuilds() > 3u);
    BOOST_TEST((plain.particles().position() == with_window.particles().position()));
    BOOST_TEST((plain.particles().velocity() == with_window.particles().velocity()));
}

// The same packing with its particles renumbered evolves identically (up to round-off from the
// order of force summation).
BOOST_AUTO_TEST_CASE_TEMPLATE(results_do_not_depend_on_particle_order, D, Dims) {
    constexpr int dim = D::value;
    const double L = dim == 2 ? 0.02 : 0.008;
    const auto p = random_packing<dim>(300, 0.5e-3, 1.5e-3, L, 11, true, true);  // overlapping: it explodes apart
    std::vector<std::size_t> order(p.x.size());
    std::iota(order.begin(), order.end(), 0);
    std::reverse(order.begin(), order.end());
    std::rotate(order.begin(), order.begin() + 17, order.end());
    auto run = [&](bool permuted) {
        mm::Simulation<dim, mm::FrictionalLinear> sim(
            mm::FrictionalLinear{mm::LinearSpringDashpot(k, gamma0), mm::CundallStrack(0.2 * k, 0.2 * gamma0, 0.5)},
            periodic_box<dim>(L));
        for (std::size_t n = 0; n < p.x.size(); ++n) {
            const std::size_t i = permuted ? order[n] : n;
            sim.particles().add(p.x[i], p.r[i], mm::sphere_mass(rho, p.r[i]));
        }
        sim.set_time_step(mm::contact_duration(k, gamma0, mm::sphere_mass(rho, 0.5e-3) / 2) / 20);
        sim.run(300);
        return sim;
    };
    const auto plain = run(false), permuted = run(true);
    double worst = 0.0, scale = 0.0;
    for (std::size_t n = 0; n < p.x.size(); ++n) {
        const auto& v1 = plain.particles().velocity()[order[n]];
        const auto& v2 = permuted.particles().velocity()[n];
        worst = std::max(worst, (v1 - v2).norm());
        scale = std::max(scale, v1.norm());
    }
    BOOST_TEST(plain.contact_count() == permuted.contact_count());
    BOOST_TEST(scale > 0.0);
    BOOST_TEST(worst < 1e-9 * scale);
}

BOOST_AUTO_TEST_SUITE_END()
