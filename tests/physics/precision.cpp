// Float storage (BasicSimulation<dim, float, ...>): every force is computed in double, but each
// stored position, velocity and force is rounded to float. Its positions resolve only
// ulp(|x|) ~ 6e-8 |x|, so the forces agree with the double engine to about that over the
// overlap (position_resolution() / delta); prepare() refuses such a scene unless the user
// accepts it, and the particles take half the memory.
#define BOOST_TEST_MODULE physics_precision
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <limits>
#include <filesystem>
#include <random>

#include "support/expect_error.hpp"
#include "support/scenes.hpp"

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

BOOST_AUTO_TEST_CASE_TEMPLATE(float_halves_the_particles_memory, D, Dims) {
    const auto exact = lattice<D::value, double>(false);
    const auto coarse = lattice<D::value, float>(true);
    const std::size_t id = sizeof(mm::Index);  // the id is a whole number in either precision
    BOOST_TEST(2 * (coarse.particles().bytes_per_particle() - id) == exact.particles().bytes_per_particle() - id);
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
