// Float storage (BasicSimulation<dim, float, ...>): every force is computed in double, and summed
// in double, but each stored position and velocity is rounded to float. Its positions resolve only
// ulp(|x|) ~ 6e-8 |x|, so the forces agree with the double engine to about that over the
// overlap (position_resolution() / delta); prepare() refuses such a scene unless the user
// accepts it, and the particles' state takes half the memory.
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <limits>
#include <filesystem>
#include <random>
#include <type_traits>

#include "support/expect_error.hpp"
#include "support/scenes.hpp"

BOOST_AUTO_TEST_SUITE(physics_precision)  // the file's cases, run as the CTest test of this file's name

using namespace mmtest;

namespace {
constexpr double overlap = 1e-5;  // 1% of the radius: float resolves it to ~4e-4 at these coordinates

// The support's jittered lattice with that overlap, stored in Real.
template <int dim, class Real>
auto lattice(bool allow_coarse) {
    auto sim = jittered_lattice<dim, Real>(overlap);
    sim.allow_coarse_positions(allow_coarse);
    return sim;
}
}  // namespace

BOOST_AUTO_TEST_CASE_TEMPLATE(float_agrees_with_double_to_its_resolution, D, Dims) {
    constexpr int dim = D::value;
    auto exact = lattice<dim, double>(false);
    auto coarse = lattice<dim, float>(true);
    const double contact_force = k * overlap;
    auto largest_difference = [&] {
        double d = 0.0;
        for (std::size_t i = 0; i < exact.particles().size(); ++i)
            d = std::max(d, (exact.particles().force()[i] - coarse.particles().force()[i].template cast<double>()).norm());
        return d / contact_force;
    };
    exact.prepare();
    coarse.prepare();
    const double predicted = coarse.position_resolution() / overlap;
    const double at_start = largest_difference();
    exact.run(100);
    coarse.run(100);
    const double later = largest_difference();
    BOOST_TEST_MESSAGE(dim << "D float: resolution " << coarse.position_resolution() << " m (predicted force error "
                           << predicted << " of k delta); measured " << at_start << " at the start, " << later
                           << " after 100 steps");
    const double box_ulp = coarse.domain().hi().maxCoeff() * std::numeric_limits<float>::epsilon();
    BOOST_TEST(coarse.position_resolution() <= box_ulp);  // the farthest particle sits in the box's last cell
    BOOST_TEST(coarse.position_resolution() >= 0.9 * box_ulp);
    BOOST_TEST(exact.contact_count() == coarse.contact_count());
    BOOST_TEST(at_start < 2 * predicted);
    BOOST_TEST(at_start > 0.01 * predicted);  // float really rounds: the estimate is not vacuous
    BOOST_TEST(later < 10 * predicted);
    // The averages see the same packing: the snapshot holds the same contacts.
    BOOST_TEST(mm::take_snapshot(coarse).contacts.size() == mm::take_snapshot(exact).contacts.size());
}

BOOST_AUTO_TEST_CASE_TEMPLATE(float_is_refused_unless_accepted, D, Dims) {
    auto coarse = lattice<D::value, float>(false);
    expect_error([&] { coarse.prepare(); }, {"in float", "more than 1e-6 of the smallest radius", "store in double",
                                             "allow_coarse_positions(true)"});
    coarse.allow_coarse_positions(true);
    coarse.prepare();  // accepted
}

// The state halves; the id (a whole number) and the forces and torques (double sums) do not.
BOOST_AUTO_TEST_CASE_TEMPLATE(float_halves_the_state_memory, D, Dims) {
    constexpr int dim = D::value;
    const auto exact = lattice<dim, double>(false);
    const auto coarse = lattice<dim, float>(true);
    using P = std::decay_t<decltype(coarse.particles())>;
    static_assert(std::is_same_v<typename P::FV, mm::Vec<dim>> && std::is_same_v<typename P::FA, mm::Angular<dim>>);
    static_assert(std::is_same_v<std::decay_t<decltype(coarse.particles().force()[0])>, mm::Vec<dim>>);
    const std::size_t unhalved = sizeof(mm::Index) + sizeof(mm::Vec<dim>) + sizeof(mm::Angular<dim>);
    BOOST_TEST(2 * (coarse.particles().bytes_per_particle() - unhalved) == exact.particles().bytes_per_particle() - unhalved);
}

namespace {
// The support's lattice with every number a float holds exactly (positions, radii, masses,
// inertias) and float-exact random velocities and spins, stored in Real.
template <int dim, class Real>
auto float_exact_lattice() {
    auto source = jittered_lattice<dim, double>(overlap);
    auto sim = jittered_lattice<dim, Real>(overlap);
    sim.allow_coarse_positions(true);
    sim.particles() = {};
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> speed(-0.05, 0.05), spin(-50.0, 50.0);
    // Through memory: GCC 12 folds an in-register double -> float -> double round trip of
    // packed values to nothing (ARCHITECTURE.md, "One time step").
    auto rounded = [](double x) {
        volatile float f = static_cast<float>(x);
        return double(f);
    };
    for (std::size_t i = 0; i < source.particles().size(); ++i) {
        mm::Vec<dim> x = source.particles().position()[i];
        for (int a = 0; a < dim; ++a) x[a] = rounded(x[a]);
        const double r = rounded(source.particles().radius()[i]), m = rounded(source.particles().mass()[i]);
        const std::size_t p = sim.particles().add(x, r, m, rounded(mm::sphere_inertia(m, r)));
        for (int a = 0; a < dim; ++a) sim.particles().velocity()[p][a] = static_cast<Real>(rounded(speed(rng)));
        auto& w = sim.particles().template get<mm::field::AngularVelocity>()[p];
        if constexpr (dim == 2) w = static_cast<Real>(rounded(spin(rng)));
        else
            for (int a = 0; a < 3; ++a) w[a] = static_cast<Real>(rounded(spin(rng)));
    }
    return sim;
}
}  // namespace

// A float scene computes in double from its stored numbers and sums forces and torques in
// double: its forces are, bit for bit, those of the double scene holding the same numbers (the
// contacts touch, move and turn: normal, tangential and dashpot forces and torques all enter).
BOOST_AUTO_TEST_CASE_TEMPLATE(float_forces_are_the_double_forces_of_its_numbers, D, Dims) {
    constexpr int dim = D::value;
    auto coarse = float_exact_lattice<dim, float>();
    auto exact = float_exact_lattice<dim, double>();
    coarse.prepare();
    exact.prepare();
    BOOST_TEST(coarse.contact_count() == exact.contact_count());
    BOOST_TEST(coarse.contact_count() > coarse.particles().size());
    std::size_t differ = 0;
    double largest_torque = 0.0;
    const auto& t = coarse.particles().template get<mm::field::Torque>();
    const auto& t_exact = exact.particles().template get<mm::field::Torque>();
    for (std::size_t i = 0; i < coarse.particles().size(); ++i) {
        differ += !(coarse.particles().force()[i] == exact.particles().force()[i]) + !(t[i] == t_exact[i]);
        largest_torque = std::max(largest_torque, std::sqrt(mm::DimTraits<dim>::squared_norm(t_exact[i])));
    }
    BOOST_TEST(differ == 0u);
    BOOST_TEST(largest_torque > 0.0);  // the tangential forces are there
}

// A float scene saves and restores like a double one: the restored run continues bit for bit,
// and a double scene refuses the float file (another scene type).
BOOST_AUTO_TEST_CASE_TEMPLATE(float_state_round_trip, D, Dims) {
    const auto file = std::filesystem::temp_directory_path() / ("micromacro_float_state_" + std::to_string(D::value) + "d.bin");
    auto original = lattice<D::value, float>(true);
    original.run(10);
    mm::io::save_state(original, file);
    auto restored = lattice<D::value, float>(true);
    mm::io::load_state(restored, file);
    original.run(10);
    restored.run(10);
    BOOST_TEST(original.particles().position() == restored.particles().position());
    auto other = lattice<D::value, double>(false);
    expect_error([&] { mm::io::load_state(other, file); }, {"holds a different scene", "real=32bit", "real=64bit"});
    std::filesystem::remove(file);
}

BOOST_AUTO_TEST_SUITE_END()
