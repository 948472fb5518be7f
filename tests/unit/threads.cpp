// Threads (OpenMP): a fixed thread count gives the same bits every run, and another count the
// same trajectory up to round-off. Without OpenMP, set_threads refuses anything but one thread.
#define BOOST_TEST_MODULE unit_threads
#include <boost/test/unit_test.hpp>

#include "support/scenes.hpp"

using namespace mmtest;

namespace {
// A dense, moving frictional packing with walls on the last axis: contacts open, close and slide.
template <int dim>
auto shaken_packing(int threads) {
    const std::size_t n = 4000;  // 2000 per thread: fewer run serially (see active_threads)
    const double L = std::pow(n * mean_particle_volume<dim>(0.5e-3, 1.5e-3) / 0.6, 1.0 / dim);
    auto p = random_packing<dim>(n, 0.5e-3, 1.5e-3, L, 11, true, true);
    std::array<bool, dim> periodic;
    for (int a = 0; a < dim; ++a) periodic[a] = a < dim - 1;
    mm::Walls<dim> walls;
    walls.add_axis_aligned(dim - 1, true, 0.0);
    walls.add_axis_aligned(dim - 1, false, L);
    for (auto& x : p.x) x[dim - 1] = 2e-3 + (L - 4e-3) * x[dim - 1] / L;  // inside the walls
    const mm::FrictionalLinear law{mm::LinearSpringDashpot(k, gamma0), mm::CundallStrack(0.2 * k, 0.02, 0.5)};
    mm::Simulation<dim, mm::FrictionalLinear, mm::Walls<dim>> sim(
        law, mm::Domain<dim>(mm::Vec<dim>::Zero(), mm::Vec<dim>::Constant(L), periodic), walls);
    std::mt19937_64 rng(3);
    std::normal_distribution<double> N(0.0, 0.1);
    for (std::size_t i = 0; i < p.x.size(); ++i) {
        sim.particles().add(p.x[i], p.r[i], mm::sphere_mass(rho, p.r[i]));
        for (int a = 0; a < dim; ++a) sim.particles().velocity()[i][a] = N(rng);
    }
    sim.set_threads(threads);
    sim.set_time_step(mm::contact_duration(k, gamma0, mm::sphere_mass(rho, 0.5e-3) / 2) / 50);
    sim.run(1000);
    BOOST_TEST_REQUIRE(sim.active_threads() == threads);
    return sim;
}
}  // namespace

#ifdef _OPENMP
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
