// Saving and restoring a simulation: a restored run continues bit for bit; foreign, damaged and
// other-dimension files are refused with a message.
#define BOOST_TEST_MODULE unit_state
#include <boost/test/unit_test.hpp>

#include <filesystem>
#include <fstream>

#include "support/scenes.hpp"

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
        BOOST_TEST(std::string(e.what()).find("truncated") != std::string::npos, e.what());
    }
    // Truncated: the first half of a real file.
    std::ifstream in(dir / "micromacro_state_2d.bin", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(dir / "micromacro_half.bin", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    try {
        mm::io::load_state(two, dir / "micromacro_half.bin");
        BOOST_ERROR("half a file loaded");
    } catch (const mm::InputError& e) {
        BOOST_TEST(std::string(e.what()).find("truncated or damaged") != std::string::npos, e.what());
    }
}
