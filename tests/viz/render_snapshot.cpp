// render_snapshot under Xvfb: a known configuration of a few disks with known energies renders at
// the requested size, the pixel at every centre has its colour-map colour (highest red, lowest
// black), background pixels are background; without a display it refuses with a clear message.
#define BOOST_TEST_MODULE viz_render_snapshot
#include <boost/test/unit_test.hpp>

#include <filesystem>
#include <fstream>

#include <micromacro/io/vtk.hpp>
#include <vtkImageData.h>
#include <vtkPNGReader.h>

#include "snapshot_view.hpp"
#include "support/programs.hpp"

namespace fs = std::filesystem;
namespace mm = micromacro;

BOOST_AUTO_TEST_CASE(colours_at_the_centres) {
    const fs::path dir = fs::temp_directory_path() / "micromacro_render_test";
    fs::remove_all(dir);
    fs::create_directories(dir);
    // Five disks in a row, energies 0, 1, 2, 3, 4 (normalised 0, 1/4, ..., 1), one far corner disk
    // to set the bounds.
    mm::io::ParticleFrame<2> f;
    const double a = 1e-3;
    for (int i = 0; i < 5; ++i) {
        f.position.push_back({3e-3 * i, 0.0});
        f.potential_energy.push_back(double(i));
    }
    f.position.push_back({12e-3, 6e-3});
    f.potential_energy.push_back(2.0);
    const std::size_t n = f.position.size();
    f.radius.assign(n, a);
    f.velocity.assign(n, mm::Vec<2>::Zero());
    f.force.assign(n, mm::Vec<2>::Zero());
    f.kinetic_energy.assign(n, 0.0);
    f.coordination.assign(n, 0);
    f.stress.assign(n, mm::Tensor2<2>::Zero());
    mm::io::write_particles(f, dir / "p.vtp");

    const int width = 640, height = 480;
    const auto png = dir / "p.png";
    const auto r = mmtest::run_program(std::string(XVFB_RUN) + " -a -s \"-screen 0 1280x1024x24\" " + RENDER_SNAPSHOT,
                                       (dir / "p.vtp").string() + " --size 640x480 -o " + png.string(), dir);
    BOOST_TEST_REQUIRE(r.status == 0, r.err);
    vtkNew<vtkPNGReader> reader;
    reader->SetFileName(png.string().c_str());
    reader->Update();
    auto* image = reader->GetOutput();
    int dims[3];
    image->GetDimensions(dims);
    BOOST_TEST(dims[0] == width);
    BOOST_TEST(dims[1] == height);
    auto rgb = [&](int col, int row) {  // row 0 at the top, as View::pixel counts
        std::array<double, 3> c;
        for (int k = 0; k < 3; ++k) c[k] = image->GetScalarComponentAsDouble(col, height - 1 - row, 0, k) / 255.0;
        return c;
    };
    const auto view = viz::View::fit(0.0 - a, 12e-3 + a, -a, 6e-3 + a, width, height);
    for (int i = 0; i < 5; ++i) {
        const auto [col, row] = view.pixel(3e-3 * i, 0.0);
        const auto got = rgb(col, row), want = viz::energy_colour(i / 4.0);
        for (int k = 0; k < 3; ++k) BOOST_TEST(std::abs(got[k] - want[k]) < 0.02, "disk " << i << " channel " << k);
    }
    const auto red = rgb(view.pixel(12e-3, 0.0)[0], view.pixel(12e-3, 0.0)[1]);  // energy 4: the highest
    BOOST_TEST((red[0] > 0.95 && red[1] < 0.05 && red[2] < 0.05));
    const auto black = rgb(view.pixel(0.0, 0.0)[0], view.pixel(0.0, 0.0)[1]);  // energy 0: the lowest
    BOOST_TEST((black[0] < 0.05 && black[1] < 0.05 && black[2] < 0.05));
    for (auto [x, y] : {std::pair{1.5e-3, 0.0}, std::pair{6e-3, 4e-3}, std::pair{-0.9e-3, 5e-3}}) {
        const auto [col, row] = view.pixel(x, y);
        const auto bg = rgb(col, row);
        for (int k = 0; k < 3; ++k) BOOST_TEST(std::abs(bg[k] - viz::background[k]) < 0.02, "background at " << x << ", " << y);
    }
}

BOOST_AUTO_TEST_CASE(no_display_is_a_clear_error) {
    const fs::path dir = fs::temp_directory_path() / "micromacro_render_test";
    const auto r = mmtest::run_program("env -u DISPLAY " + std::string(RENDER_SNAPSHOT), (dir / "p.vtp").string() + " -o " + (dir / "q.png").string(), dir);
    BOOST_TEST(r.status != 0);
    BOOST_TEST(r.err.find("run under xvfb-run") != std::string::npos, r.err);
    BOOST_TEST(!fs::exists(dir / "q.png"));
}

// Damaged input is refused, not drawn in part: a particles file cut short, a walls file of
// garbage, a .pvd collection cut before its end. No picture is written.
BOOST_AUTO_TEST_CASE(damaged_files_are_refused) {
    const fs::path dir = fs::temp_directory_path() / "micromacro_render_test";
    BOOST_TEST_REQUIRE(fs::exists(dir / "p.vtp"));  // from colours_at_the_centres
    const std::string whole = mmtest::slurp(dir / "p.vtp");
    std::ofstream(dir / "cut.vtp", std::ios::binary) << whole.substr(0, whole.size() * 2 / 3);
    std::ofstream(dir / "walls.vtp", std::ios::binary) << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\"> garbage";
    std::ofstream(dir / "cut.pvd") << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n"
                                      "    <DataSet timestep=\"0\" group=\"\" part=\"0\" file=\"p.vtp\"/>\n";
    struct Case {
        std::string args, expect;
    };
    const Case cases[] = {
        {(dir / "cut.vtp").string(), "cut.vtp is damaged or truncated"},
        {(dir / "p.vtp").string() + " --walls " + (dir / "walls.vtp").string(), "walls.vtp is damaged or truncated"},
        {(dir / "cut.pvd").string(), "cut.pvd is truncated"},
    };
    for (const auto& c : cases) {
        fs::remove(dir / "damaged.png");
        const auto r = mmtest::run_program(std::string(XVFB_RUN) + " -a -s \"-screen 0 1280x1024x24\" " + RENDER_SNAPSHOT,
                                           c.args + " -o " + (dir / "damaged.png").string(), dir);
        BOOST_TEST(r.exit_code() == 1, c.args);
        BOOST_TEST(r.err.find(c.expect) != std::string::npos, c.args << ": " << r.err);
        BOOST_TEST(!fs::exists(dir / "damaged.png"), c.args);
    }
}
