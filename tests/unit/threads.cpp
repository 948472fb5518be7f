// Threads (OpenMP): a fixed thread count gives the same bits every run, and another count the
// same trajectory up to round-off. Without OpenMP, set_threads refuses anything but one thread.
#include <boost/test/unit_test.hpp>

#include "support/scenes.hpp"

BOOST_AUTO_TEST_SUITE(unit_threads)  // the file's cases, run as the CTest test of this file's name

using namespace mmtest;

namespace {
// A dense, moving frictional packing with walls on the last axis: contacts open, close and slide.
// 4000 particles: 2000 per thread, fewer run serially (see active_threads).
template <int dim>
auto shaken_packing(int threads, std::size_t particles = 4000, std::size_t steps = 1000) {
    auto sim = shaken_walled_packing<dim>(particles, 11, 0.1);
    sim.set_threads(threads);
    sim.run(steps);
    BOOST_TEST_REQUIRE(sim.active_threads() == threads);
    return sim;
}
}  // namespace

#ifdef _OPENMP
// Labelled long (1000 steps of 4000 particles, six runs): the paths it takes, a frictional scene on
// two threads with spills and its bits run again, are the shorter cases' below too.
BOOST_TEST_DECORATOR(*boost::unit_test::label("long"))
BOOST_AUTO_TEST_CASE_TEMPLATE(fixed_thread_count_same_bits_other_count_round_off, D, Dims) {
    constexpr int dim = D::value;
    const auto one = shaken_packing<dim>(1);
    const auto two = shaken_packing<dim>(2), again = shaken_packing<dim>(2);
    BOOST_TEST_REQUIRE(one.contact_count() > one.particles().size() / 2);  // a dense scene
    double worst = 0.0;
    for (std::size_t i = 0; i < one.particles().size(); ++i) {
        BOOST_TEST_REQUIRE((two.particles().position()[i] == again.particles().position()[i]));
        BOOST_TEST_REQUIRE((two.particles().velocity()[i] == again.particles().velocity()[i]));
        worst = std::max(worst, one.domain().separation(one.particles().position()[i], two.particles().position()[i]).norm());
    }
    BOOST_TEST(two.books().dissipated() == again.books().dissipated());
    // Summation order differs between counts; 1000 steps of a dense packing amplify the last
    // bit, but nowhere near a visible distance (1e-6 of a radius).
    BOOST_TEST_MESSAGE(dim << "D: largest position difference 1 vs 2 threads: " << worst << " m");
    BOOST_TEST(worst < 1e-9);
    BOOST_TEST(std::abs(one.books().dissipated() / two.books().dissipated() - 1.0) < 1e-9);
}

// Three threads (more than this machine's cores, fewer steps): the middle share receives the
// first's spilled partner forces and spills into the last, the case two threads cannot reach.
BOOST_AUTO_TEST_CASE_TEMPLATE(three_threads, D, Dims) {
    constexpr int dim = D::value;
    const auto one = shaken_packing<dim>(1, 6000, 200);
    const auto three = shaken_packing<dim>(3, 6000, 200), again = shaken_packing<dim>(3, 6000, 200);
    double worst = 0.0;
    for (std::size_t i = 0; i < one.particles().size(); ++i) {
        BOOST_TEST_REQUIRE((three.particles().position()[i] == again.particles().position()[i]));
        worst = std::max(worst, one.domain().separation(one.particles().position()[i], three.particles().position()[i]).norm());
    }
    BOOST_TEST_MESSAGE(dim << "D: largest position difference 1 vs 3 threads: " << worst << " m");
    BOOST_TEST(worst < 1e-12);
    BOOST_TEST(std::abs(one.books().dissipated() / three.books().dissipated() - 1.0) < 1e-9);
}

// The frictionless scene (no torques, no springs: its spill entries carry a force only).
BOOST_AUTO_TEST_CASE_TEMPLATE(frictionless_two_threads, D, Dims) {
    constexpr int dim = D::value;
    auto run = [](int threads) {
        auto sim = shaken_walled_packing<dim, double, mm::VelocityVerlet, mm::FrictionlessLinear>(4000, 11, 0.1);
        sim.set_threads(threads);
        sim.run(300);
        BOOST_TEST_REQUIRE(sim.active_threads() == threads);
        return sim;
    };
    const auto one = run(1), two = run(2), again = run(2);
    BOOST_TEST_REQUIRE(one.contact_count() > one.particles().size() / 2);
    double worst = 0.0;
    for (std::size_t i = 0; i < one.particles().size(); ++i) {
        BOOST_TEST_REQUIRE((two.particles().position()[i] == again.particles().position()[i]));
        worst = std::max(worst, one.domain().separation(one.particles().position()[i], two.particles().position()[i]).norm());
    }
    BOOST_TEST_MESSAGE(dim << "D frictionless: largest position difference 1 vs 2 threads: " << worst << " m");
    BOOST_TEST(worst < 1e-12);
    BOOST_TEST(std::abs(one.books().dissipated() / two.books().dissipated() - 1.0) < 1e-9);
}
#else
BOOST_AUTO_TEST_CASE(threads_need_openmp) {
    mm::Simulation<2, mm::FrictionlessLinear> sim(mm::FrictionlessLinear{mm::LinearSpringDashpot(k, gamma0)});
    BOOST_CHECK_EXCEPTION(sim.set_threads(2), mm::InputError, [](const mm::InputError& e) {
        return std::string(e.what()).find("-fopenmp") != std::string::npos;
    });
}
#endif

BOOST_AUTO_TEST_CASE(bad_thread_counts_refused) {
    mm::Simulation<2, mm::FrictionlessLinear> sim(mm::FrictionlessLinear{mm::LinearSpringDashpot(k, gamma0)});
    BOOST_CHECK_THROW(sim.set_threads(0), mm::InputError);
    BOOST_CHECK_THROW(sim.set_threads(-3), mm::InputError);
    sim.set_threads(1);
    BOOST_TEST(sim.threads() == 1);
}

BOOST_AUTO_TEST_CASE(small_scenes_run_serially) {
    mm::Simulation<2, mm::FrictionlessLinear> sim(mm::FrictionlessLinear{mm::LinearSpringDashpot(k, gamma0)});
    for (int i = 0; i < 3000; ++i) sim.particles().add(mm::Vec<2>(0.003 * i, 0.0), 1e-3, 1.0);
#ifdef _OPENMP
    sim.set_threads(2);
    BOOST_TEST(sim.active_threads() == 1);  // 1500 per thread: a team would cost more than it saves
#endif
    BOOST_TEST(sim.active_threads() == 1);
}

BOOST_AUTO_TEST_SUITE_END()
