// Periodic boundaries: a pair crossing the boundary keeps its contact and tangential spring;
// a periodic lattice has exactly the contacts of the minimum-image brute-force search.
#include <boost/test/unit_test.hpp>

#include "support/scenes.hpp"

BOOST_AUTO_TEST_SUITE(physics_periodic)  // the file's cases, run as the CTest test of this file's name

using namespace mmtest;

// Two colliding particles with a loaded tangential spring drift fast across the boundary during
// their contact; the same pair in a box too large to cross is the reference.
BOOST_AUTO_TEST_CASE_TEMPLATE(crossing_keeps_contact_and_spring, D, Dims) {
    constexpr int dim = D::value;
    using V = mm::Vec<dim>;
    const double a = 1e-3, m = mm::sphere_mass(rho, a), tc = mm::contact_duration(k, 0.0, m / 2);
    auto run = [&](double L, double start) {
        mm::Simulation<dim, mm::FrictionalLinear> sim(
            mm::FrictionalLinear{mm::LinearSpringDashpot(k, 0.0), mm::CundallStrack(0.2 * k, 0.0, 10.0)},
            periodic_box<dim>(L));
        V x1 = V::Constant(0.5 * L), x2 = x1;
        x1[0] = start;
        x2[0] = start + 2.0 * a;  // touching
        sim.particles().add(x1, a, m);
        sim.particles().add(x2, a, m);
        V drift = V::Zero(), approach = V::Zero(), shear = V::Zero();
        drift[0] = 200.0;    // 2 mm per contact duration: both particles cross during the contact
        approach[0] = 0.05;  // they press together ...
        shear[1] = 0.01;     // ... and slide past each other slowly, loading the spring
        sim.particles().velocity()[0] = drift + approach + shear;
        sim.particles().velocity()[1] = drift - approach - shear;
        sim.set_time_step(tc / 100);
        sim.run(60);  // 0.6 t_c: still in contact
        std::vector<double> out;
        sim.for_each_contact([&](const mm::ContactView<dim>& c) {
            out.push_back(c.geometry.overlap);
            out.push_back(c.tangential_force.norm());
            out.push_back(c.elastic_energy());
        });
        out.push_back(sim.particles().position()[0][0]);
        return std::pair{out, sim.neighbor_rebuilds()};
    };
    const auto [crossing, rebuilds] = run(10e-3, 9e-3);  // x1 1 mm left of the boundary, x2 beyond it
    const auto [reference, unused] = run(1.0, 0.1);
    (void)unused;
    BOOST_TEST(rebuilds > 5u);                  // the history also survived neighbour-list rebuilds
    BOOST_TEST_REQUIRE(crossing.size() == 4u);  // still one contact
    BOOST_TEST_REQUIRE(reference.size() == 4u);
    BOOST_TEST(crossing[3] < 9e-3);  // particle 0 crossed the boundary and was wrapped
    BOOST_TEST(reference[1] > 0.0);  // the spring is loaded
    for (int q = 0; q < 3; ++q) BOOST_TEST(std::abs(crossing[q] - reference[q]) <= 1e-6 * std::abs(reference[q]));
}

// Square (2D) and simple cubic (3D) lattices of slightly overlapping equal particles: every
// particle touches 2 dim neighbours, also across the boundary, and the contact set equals the
// brute-force minimum-image set; small boxes exercise the two-cells-per-axis case.
BOOST_AUTO_TEST_CASE_TEMPLATE(periodic_lattice_contacts, D, Dims) {
    constexpr int dim = D::value;
    using V = mm::Vec<dim>;
    const double a = 1e-3, spacing = 1.98e-3;
    for (int cells : {3, 4, 7}) {
        const double L = cells * spacing;
        std::vector<V> x;
        std::vector<double> r;
        int total = 1;
        for (int d = 0; d < dim; ++d) total *= cells;
        for (int n = 0; n < total; ++n) {
            V p;
            for (int d = 0, t = n; d < dim; ++d, t /= cells) p[d] = (t % cells + 0.5) * spacing;
            x.push_back(p);
            r.push_back(a);
        }
        mm::Simulation<dim, mm::FrictionlessLinear> sim(mm::FrictionlessLinear{mm::LinearSpringDashpot(k, gamma0)},
                                                        periodic_box<dim>(L));
        for (std::size_t i = 0; i < x.size(); ++i) sim.particles().add(x[i], a, mm::sphere_mass(rho, a));
        sim.set_time_step(1e-7);
        sim.set_skin(0.1 * a);
        sim.prepare();
        BOOST_TEST(sim.contact_count() == static_cast<std::size_t>(dim * total));
        std::vector<mm::IndexPair> brute;
        mm::BruteForce().find_pairs(x, r, periodic_box<dim>(L), 0.0, brute);
        std::vector<mm::IndexPair> found;
        sim.for_each_contact([&](const mm::ContactView<dim>& c) { found.push_back({c.i, c.j}); });
        BOOST_TEST((found == brute));
        // By symmetry every force cancels.
        double worst = 0.0;
        for (const auto& f : sim.particles().force()) worst = std::max(worst, f.norm());
        BOOST_TEST(worst < 1e-9 * k * 0.02e-3);
    }
}

BOOST_AUTO_TEST_SUITE_END()
