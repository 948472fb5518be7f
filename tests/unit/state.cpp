// Saving and restoring a simulation: a restored run continues bit for bit; foreign, damaged,
// other-kind and other-dimension files are refused with a message, and a refused file leaves the
// simulation as it was.
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>

#include "support/expect_error.hpp"
#include "support/scenes.hpp"

BOOST_AUTO_TEST_SUITE(unit_state)  // the file's cases, run as the CTest test of this file's name

using namespace mmtest;
namespace fs = std::filesystem;

namespace {
template <int dim>
using Scene = mm::Simulation<dim, mm::FrictionalLinear, mm::Walls<dim>, mm::VelocityVerlet, mm::LinkedCells, mm::BackgroundDamping>;

template <int dim>
Scene<dim> make_scene() {
    const double L = dim == 2 ? 0.02 : 0.01;
    const auto p = random_packing<dim>(dim == 2 ? 150 : 200, 0.5e-3, 1.5e-3, L, 17, false, false);
    mm::Walls<dim> walls;
    walls.add_box(mm::Vec<dim>::Zero(), mm::Vec<dim>::Constant(L));
    walls[2 * dim - 1].motion = mm::StressControlled{dim == 2 ? 20.0 : 1e4, 1e-4, 0.6};
    walls[1].motion = mm::StrainControlled{1e-3, 0.01};
    Scene<dim> sim(mm::FrictionalLinear{mm::LinearSpringDashpot(k, gamma0), mm::CundallStrack(0.2 * k, 0.2 * gamma0, 0.5)}, {},
                   walls, {}, {}, mm::BackgroundDamping(1e-4, 1e-11));
    for (std::size_t i = 0; i < p.x.size(); ++i) {
        sim.particles().add(p.x[i], p.r[i], mm::sphere_mass(rho, p.r[i]));
        sim.particles().velocity()[i] = mm::Vec<dim>::Constant(0.05 * ((i % 7) - 3.0));
    }
    sim.set_time_step(mm::contact_duration(k, gamma0, mm::sphere_mass(rho, a_mean) / 2) / 50);
    return sim;
}
}  // namespace

BOOST_AUTO_TEST_CASE_TEMPLATE(restored_run_continues_bit_for_bit, D, Dims) {
    constexpr int dim = D::value;
    const auto file = fs::temp_directory_path() / ("micromacro_state_" + std::to_string(dim) + ".bin");
    auto original = make_scene<dim>();
    original.run(3000);
    mm::io::save_state(original, file, "settings");
    BOOST_TEST(!fs::exists(file.string() + ".partial"));
    auto restored = make_scene<dim>();  // same types, different state after loading
    restored.run(10);
    BOOST_TEST(mm::io::load_state(restored, file) == "settings");
    original.run(3000);
    restored.run(3000);
    BOOST_TEST(original.contact_count() > 0u);
    BOOST_TEST(restored.time() == original.time());
    BOOST_TEST(restored.steps_done() == original.steps_done());
    bool same = true;
    for (std::size_t i = 0; i < original.particles().size(); ++i) {
        same &= restored.particles().position()[i] == original.particles().position()[i];
        same &= restored.particles().velocity()[i] == original.particles().velocity()[i];
    }
    BOOST_TEST(same);
    BOOST_TEST(restored.walls()[2 * dim - 1].offset == original.walls()[2 * dim - 1].offset);
    BOOST_TEST(restored.books().dissipated() == original.books().dissipated());
    BOOST_TEST(restored.energy_residual() == original.energy_residual());
}

BOOST_AUTO_TEST_CASE(foreign_and_damaged_files_are_refused) {
    const auto dir = fs::temp_directory_path();
    auto two = make_scene<2>();
    two.run(10);
    mm::io::save_state(two, dir / "micromacro_state_2d.bin");
    auto three = make_scene<3>();
    try {
        mm::io::load_state(three, dir / "micromacro_state_2d.bin");
        BOOST_ERROR("a 2D state loaded into a 3D scene");
    } catch (const mm::InputError& e) {
        BOOST_TEST(std::string(e.what()).find("holds a different scene (dim=2") != std::string::npos, e.what());
    }
    std::ofstream(dir / "micromacro_not_state.bin") << "hello";
    try {
        mm::io::load_state(two, dir / "micromacro_not_state.bin");
        BOOST_ERROR("garbage loaded");
    } catch (const mm::InputError& e) {
        BOOST_TEST(std::string(e.what()).find("is not a micromacro state file") != std::string::npos, e.what());
    }
    // Truncated: the first half of a real file.
    std::ifstream in(dir / "micromacro_state_2d.bin", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(dir / "micromacro_half.bin", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    try {
        mm::io::load_state(two, dir / "micromacro_half.bin");
        BOOST_ERROR("half a file loaded");
    } catch (const mm::InputError& e) {
        BOOST_TEST(std::string(e.what()).find("damaged (its checksum") != std::string::npos, e.what());
    }
}

// A prepared state and a checkpoint are different kinds: each is refused where the other is
// expected, by load_state and state_text alike; without a kind asked for, any kind loads.
BOOST_AUTO_TEST_CASE(kinds_are_kept_apart) {
    const auto file = fs::temp_directory_path() / "micromacro_state_kind.bin";
    auto sim = make_scene<2>();
    sim.run(10);
    mm::io::save_state(sim, file, "text", "checkpoint");
    auto other = make_scene<2>();
    try {
        mm::io::load_state(other, file, "prepared");
        BOOST_ERROR("a checkpoint loaded as a prepared state");
    } catch (const mm::InputError& e) {
        BOOST_TEST(std::string(e.what()).find("is a checkpoint state, not a prepared state") != std::string::npos, e.what());
    }
    BOOST_CHECK_THROW(mm::io::state_text(file, "prepared"), mm::InputError);
    BOOST_TEST(mm::io::state_text(file, "checkpoint") == "text");
    BOOST_TEST(mm::io::load_state(other, file, "checkpoint") == "text");
    BOOST_TEST(mm::io::load_state(other, file) == "text");
}

// Every corruption of a state file is refused, never restored, never a crash: each of 10 000
// copies of a 2D state has one random byte replaced (any offset: header, arrays, checksum) or,
// one in four, a random run of 2-64 bytes overwritten. The simulation a refused file was offered
// to keeps its state.
BOOST_AUTO_TEST_CASE(ten_thousand_corruptions_are_refused) {
    const auto dir = fs::temp_directory_path();
    auto sim = make_scene<2>();
    sim.run(200);  // contacts with springs, moving walls
    mm::io::save_state(sim, dir / "micromacro_state_good.bin", "{\"rows\": 21}", "checkpoint");
    std::ifstream in(dir / "micromacro_state_good.bin", std::ios::binary);
    const std::string good((std::istreambuf_iterator<char>(in)), {});
    auto target = make_scene<2>();
    target.run(5);
    const auto position = target.particles().position()[7];
    const auto steps = target.steps_done();
    std::mt19937_64 rng(42);
    std::size_t refused = 0, trials = 10000;
    const auto bad = dir / "micromacro_state_bad.bin";
    for (std::size_t t = 0; t < trials; ++t) {
        std::string bytes = good;
        const std::size_t at = rng() % bytes.size();
        if (t % 4 == 3) {
            const std::size_t n = std::min<std::size_t>(2 + rng() % 63, bytes.size() - at);
            for (std::size_t k = 0; k < n; ++k) bytes[at + k] = static_cast<char>(rng());
        } else {
            bytes[at] = static_cast<char>(bytes[at] ^ (1 + rng() % 255));  // a different byte
        }
        if (bytes == good) continue;  // a run overwritten with what was there (never seen)
        std::ofstream(bad, std::ios::binary | std::ios::trunc) << bytes;
        try {
            mm::io::load_state(target, bad, "checkpoint");
        } catch (const mm::InputError&) {
            ++refused;
        }
    }
    BOOST_TEST_MESSAGE(refused << " of " << trials << " corrupted copies of a " << good.size() << "-byte state refused");
    BOOST_TEST(refused == trials);
    BOOST_TEST((target.particles().position()[7] == position));
    BOOST_TEST(target.steps_done() == steps);
    BOOST_TEST(mm::io::load_state(target, dir / "micromacro_state_good.bin", "checkpoint") == "{\"rows\": 21}");
    BOOST_TEST(target.steps_done() == sim.steps_done());
}

// A file whose checksum is right but whose contents do not hold together (as a program with a bug
// or a hand-made file could write) is refused by the checks of what was restored: here a position
// that is not a number.
BOOST_AUTO_TEST_CASE(restored_contents_are_checked) {
    auto sim = make_scene<2>();
    sim.run(10);
    sim.check_restored("fresh");  // a real state passes
    const auto file = fs::temp_directory_path() / "micromacro_state_inconsistent.bin";
    auto broken = sim;
    broken.particles().position()[3][0] = std::numeric_limits<double>::quiet_NaN();
    mm::io::save_state(broken, file);
    try {
        mm::io::load_state(sim, file);
        BOOST_ERROR("a state with a NaN position loaded");
    } catch (const mm::InputError& e) {
        BOOST_TEST(std::string(e.what()).find("particle 3 has a position or velocity that is not finite") != std::string::npos,
                   e.what());
    }
}

// State files name each wall's motion. A file that names a motion this build does not know (a
// later version's, or a damaged name under a recomputed checksum) is refused with the name, and
// the simulation it was loaded into is left as it was.
BOOST_AUTO_TEST_CASE(unknown_wall_motion_is_refused) {
    auto sim = make_scene<2>();
    sim.run(10);
    const auto file = fs::temp_directory_path() / "micromacro_state_unknown_motion.bin";
    mm::io::save_state(sim, file);
    std::vector<char> bytes;
    {
        std::ifstream in(file, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    const std::string known = "stress-controlled", unknown = "stress-sideways!!";
    BOOST_REQUIRE(known.size() == unknown.size());
    const auto at = std::search(bytes.begin(), bytes.end(), known.begin(), known.end());
    BOOST_REQUIRE(at != bytes.end());
    std::copy(unknown.begin(), unknown.end(), at);
    mm::io::Checksum sum;  // a valid checksum, so that the name itself is what is refused
    sum.add(bytes.data(), bytes.size() - sizeof(std::uint64_t));
    std::memcpy(bytes.data() + bytes.size() - sizeof(std::uint64_t), &sum.value, sizeof sum.value);
    {
        std::ofstream out(file, std::ios::binary | std::ios::trunc);
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    }
    const double time_before = sim.time();
    expect_error([&] { mm::io::load_state(sim, file); }, {"stress-sideways!!", "does not know", "stress-controlled"});
    BOOST_TEST(sim.time() == time_before);
    BOOST_TEST(sim.walls()[3].motion.index() == 2u);  // still the stress-controlled wall
    fs::remove(file);
}

namespace {
template <int dim>
using ShearedScene = mm::Simulation<dim, mm::FrictionalLinear, mm::NoWalls, mm::VelocityVerlet, mm::LinkedCells, mm::AffineDamping>;

// A periodic packing sheared (and, in 3D, compressed) by a moving cell at `rate`.
template <int dim>
ShearedScene<dim> make_sheared_scene(double rate) {
    const double L = dim == 2 ? 0.02 : 0.01;
    const auto p = random_packing<dim>(dim == 2 ? 150 : 200, 0.5e-3, 1.5e-3, L, 17, false, true);
    ShearedScene<dim> sim(mm::FrictionalLinear{mm::LinearSpringDashpot(k, gamma0), mm::CundallStrack(0.2 * k, 0.2 * gamma0, 0.5)},
                          mm::Domain<dim>::fully_periodic(mm::Vec<dim>::Zero(), mm::Vec<dim>::Constant(L)), {}, {}, {},
                          mm::AffineDamping(1e-4, 1e-11));
    for (std::size_t i = 0; i < p.x.size(); ++i) sim.particles().add(p.x[i], p.r[i], mm::sphere_mass(rho, p.r[i]));
    Eigen::Matrix<double, dim, dim> gradient = Eigen::Matrix<double, dim, dim>::Zero();
    gradient(0, dim - 1) = rate;
    if constexpr (dim == 3) gradient(1, 1) = -0.1 * rate;
    sim.set_velocity_gradient(gradient);
    sim.set_time_step(mm::contact_duration(k, gamma0, mm::sphere_mass(rho, a_mean) / 2) / 50);
    return sim;
}
}  // namespace

// A checkpoint of a sheared cell (tilted past half a period and re-based before it is taken, so
// the lattice differs from the one the simulation was built with) continues bit for bit, the
// cell's lattice, velocity gradient and books included, in a simulation built with a still cell.
BOOST_AUTO_TEST_CASE_TEMPLATE(sheared_cell_continues_bit_for_bit, D, Dims) {
    constexpr int dim = D::value;
    const auto file = fs::temp_directory_path() / ("micromacro_sheared_state_" + std::to_string(dim) + ".bin");
    auto original = make_sheared_scene<dim>(0.0);
    const double rate = 1.2 / (6000 * original.time_step());  // a shear strain of 1.2 over the run
    original = make_sheared_scene<dim>(rate);
    original.run(3000);
    BOOST_TEST(original.domain().tilt(0, dim - 1) < 0.0);  // 0.6 periods: re-based to -0.4
    mm::io::save_state(original, file);
    auto restored = make_sheared_scene<dim>(0.0);
    BOOST_TEST(!restored.domain().moving());
    mm::io::load_state(restored, file);
    BOOST_TEST(restored.domain().moving());
    original.run(3000);
    restored.run(3000);
    BOOST_TEST(original.contact_count() > 0u);
    BOOST_TEST(original.books().work_by_cell != 0.0);
    BOOST_TEST((restored.domain().lattice() == original.domain().lattice()));
    bool same = true;
    for (std::size_t i = 0; i < original.particles().size(); ++i) {
        same &= restored.particles().position()[i] == original.particles().position()[i];
        same &= restored.particles().velocity()[i] == original.particles().velocity()[i];
    }
    BOOST_TEST(same);
    BOOST_TEST(restored.books().work_by_cell == original.books().work_by_cell);
    BOOST_TEST(restored.energy_residual() == original.energy_residual());
}

BOOST_AUTO_TEST_SUITE_END()
