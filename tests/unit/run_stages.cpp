// run(n) merges one step's closing kick into the next step's pass over the particles (velocity
// Verlet) and lets the kick pass clear the force arrays; it must give exactly the bits of n
// calls of step(), in both precisions, with rotation, walls and neighbour-list rebuilds.
#define BOOST_TEST_MODULE unit_run_stages
#include <boost/test/unit_test.hpp>

#include "support/scenes.hpp"

using namespace mmtest;

namespace {
template <int dim, class Real, class Integrator>
auto shaken_packing() {
    const std::size_t n = 300;
    const double L = std::pow(n * mean_particle_volume<dim>(0.5e-3, 1.5e-3) / 0.6, 1.0 / dim);
    auto p = random_packing<dim>(n, 0.5e-3, 1.5e-3, L, 5, true, true);
    std::array<bool, dim> periodic;
    for (int a = 0; a < dim; ++a) periodic[a] = a < dim - 1;
    mm::Walls<dim> walls;
    walls.add_axis_aligned(dim - 1, true, 0.0);
    walls.add_axis_aligned(dim - 1, false, L);
    for (auto& x : p.x) x[dim - 1] = 2e-3 + (L - 4e-3) * x[dim - 1] / L;
    const mm::FrictionalLinear law{mm::LinearSpringDashpot(k, gamma0), mm::CundallStrack(0.2 * k, 0.02, 0.5)};
    mm::BasicSimulation<dim, Real, mm::FrictionalLinear, mm::Walls<dim>, Integrator> sim(
        law, mm::Domain<dim>(mm::Vec<dim>::Zero(), mm::Vec<dim>::Constant(L), periodic), walls);
    sim.allow_coarse_positions(true);
    std::mt19937_64 rng(3);
    std::normal_distribution<double> N(0.0, 0.3);
    for (std::size_t i = 0; i < p.x.size(); ++i) {
        sim.particles().add(p.x[i], p.r[i], mm::sphere_mass(rho, p.r[i]));
        for (int a = 0; a < dim; ++a) sim.particles().velocity()[i][a] = static_cast<Real>(N(rng));
    }
    sim.set_time_step(mm::contact_duration(k, gamma0, mm::sphere_mass(rho, 0.5e-3) / 2) / 50);
    return sim;
}

template <int dim, class Real, class Integrator>
void check_run_equals_steps() {
    auto stepped = shaken_packing<dim, Real, Integrator>();
    auto ran = shaken_packing<dim, Real, Integrator>();
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
