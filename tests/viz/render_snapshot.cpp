// render_snapshot under Xvfb: a known configuration of a few disks with known energies renders at
// the requested size, the pixel at every centre has its colour-map colour (highest red, lowest
// black), background pixels are background; one colour scale holds for every frame of a series
// (--range-from), a given one (--range) and a logarithmic one (--log) colour as they say; a slice
// of a 3D box shows only its slab; the force network's tubes are as wide as the forces say;
// without a display it refuses with a clear message.
#define BOOST_TEST_MODULE viz_render_snapshot
#include <boost/test/unit_test.hpp>

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <micromacro/io/vtk.hpp>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkImageData.h>
#include <vtkPNGReader.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkXMLPolyDataWriter.h>

#include "snapshot_view.hpp"
#include "support/programs.hpp"

namespace fs = std::filesystem;
namespace mm = micromacro;

namespace {
// A frame of particles at rest at `position`, of one radius, with the given potential energies;
// the fields a picture does not read are zero.
template <int dim>
mm::io::ParticleFrame<dim> at_rest(std::vector<mm::Vec<dim>> position, double radius, std::vector<double> energy) {
    mm::io::ParticleFrame<dim> f;
    const std::size_t n = position.size();
    f.position = std::move(position);
    f.potential_energy = std::move(energy);
    f.radius.assign(n, radius);
    f.velocity.assign(n, mm::Vec<dim>::Zero());
    f.force.assign(n, mm::Vec<dim>::Zero());
    f.kinetic_energy.assign(n, 0.0);
    f.coordination.assign(n, 0);
    f.stress.assign(n, mm::Tensor2<dim>::Zero());
    return f;
}
}  // namespace

BOOST_AUTO_TEST_CASE(colours_at_the_centres) {
    const fs::path dir = fs::temp_directory_path() / "micromacro_render_test";
    fs::remove_all(dir);
    fs::create_directories(dir);
    // Five disks in a row, energies 0, 1, 2, 3, 4 (normalised 0, 1/4, ..., 1), one far corner disk
    // to set the bounds.
    const double a = 1e-3;
    std::vector<mm::Vec<2>> row;
    std::vector<double> energies;
    for (int i = 0; i < 5; ++i) {
        row.push_back({3e-3 * i, 0.0});
        energies.push_back(double(i));
    }
    row.push_back({12e-3, 6e-3});
    energies.push_back(2.0);
    mm::io::write_particles(at_rest<2>(row, a, energies), dir / "p.vtp");

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

// A picture is never written over one of its inputs (the particles, a frame a .pvd lists, the walls,
// the contacts, the --range-from series); a size beyond the limit names the limit; on a full disk
// the program's own message comes first and no partial picture stays.
BOOST_AUTO_TEST_CASE(inputs_are_never_written_over) {
    const fs::path dir = fs::temp_directory_path() / "micromacro_render_test";
    BOOST_TEST_REQUIRE(fs::exists(dir / "p.vtp"));  // from colours_at_the_centres
    const std::string particles = mmtest::slurp(dir / "p.vtp");
    fs::copy_file(dir / "p.vtp", dir / "w.vtp", fs::copy_options::overwrite_existing);
    std::ofstream(dir / "s.pvd") << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n"
                                    "    <DataSet timestep=\"0\" group=\"\" part=\"0\" file=\"p.vtp\"/>\n  </Collection>\n</VTKFile>\n";
    const std::string xvfb = std::string(XVFB_RUN) + " -a -s \"-screen 0 1280x1024x24\" " + RENDER_SNAPSHOT;
    struct Case {
        std::string args, expect;
    };
    const std::string p = (dir / "p.vtp").string();
    const Case cases[] = {
        {p + " -o " + p, "-o " + p + " is the input " + p},
        {p + " --walls " + (dir / "w.vtp").string() + " -o " + (dir / "w.vtp").string(), " is --walls "},
        {(dir / "s.pvd").string() + " -o " + p, " is a frame of the input "},
        {p + " --range-from " + (dir / "s.pvd").string() + " -o " + (dir / "s.pvd").string(), " is --range-from "},
        {(dir / "s.pvd").string() + " --movie " + p, "--movie " + p + " is "},
        {p + " --size 100000x100000 -o " + (dir / "big.png").string(), "--size 100000x100000 is outside 16..8192 pixels"},
    };
    for (const auto& c : cases) {
        const auto r = mmtest::run_program(xvfb, c.args, dir);
        BOOST_TEST(r.exit_code() == 1, c.args);
        BOOST_TEST(r.err.find(c.expect) != std::string::npos, c.args << ": " << r.err);
        BOOST_TEST((mmtest::slurp(dir / "p.vtp") == particles), c.args << ": the input changed");
        BOOST_TEST((mmtest::slurp(dir / "w.vtp") == particles), c.args << ": the walls changed");
    }
    if (!mmtest::can_fill_a_disk()) {
        BOOST_WARN_MESSAGE(false, "this machine does not let a test mount a small disk (unshare -rm): the full disk is not tested here");
        return;
    }
    const fs::path disk = dir / "small_disk";
    const auto full = mmtest::run_on_a_small_disk(RENDER_SNAPSHOT, p + " -o " + (disk / "q.png").string(), disk, 8, dir / "work",
                                                  "ls -A " + disk.string() + " > " + (dir / "left.txt").string(),
                                                  std::string(XVFB_RUN) + " -a -s \"-screen 0 1280x1024x24\"");
    BOOST_TEST(full.exit_code() == 1, full.err);
    BOOST_TEST(full.err.rfind("render_snapshot: cannot write " + (disk / "q.png").string(), 0) == 0u, full.err);
    BOOST_TEST(mmtest::slurp(dir / "left.txt").empty(), mmtest::slurp(dir / "left.txt"));
}

namespace {
// Frames of disks in a row at x = 0, 3, 6, ... mm with the given energies; the last disk is set
// apart to fix the bounds alike in every frame.
fs::path frame(const fs::path& dir, const std::string& name, const std::vector<double>& energies) {
    std::vector<mm::Vec<2>> row;
    for (std::size_t i = 0; i < energies.size(); ++i) row.push_back({3e-3 * double(i), 0.0});
    row.push_back({12e-3, 6e-3});  // the bounds' corner, energy 0
    std::vector<double> with_corner = energies;
    with_corner.push_back(0.0);
    mm::io::write_particles(at_rest<2>(row, 1e-3, with_corner), dir / name);
    return dir / name;
}

struct Picture {
    mmtest::ProgramResult result;
    vtkSmartPointer<vtkImageData> image;
    std::array<double, 3> at(double x, double y) const {  // the colour at a world point
        const auto view = viz::View::fit(-1e-3, 13e-3, -1e-3, 7e-3, 640, 480);
        const auto [col, row] = view.pixel(x, y);
        std::array<double, 3> c;
        for (int k = 0; k < 3; ++k) c[k] = image->GetScalarComponentAsDouble(col, 480 - 1 - row, 0, k) / 255.0;
        return c;
    }
};

Picture render(const fs::path& dir, const std::string& args) {
    const auto png = dir / "picture.png";
    fs::remove(png);
    Picture p{mmtest::run_program(std::string(XVFB_RUN) + " -a -s \"-screen 0 1280x1024x24\" " + RENDER_SNAPSHOT,
                                  args + " --size 640x480 -o " + png.string(), dir),
              nullptr};
    if (p.result.status != 0) return p;
    vtkNew<vtkPNGReader> reader;
    reader->SetFileName(png.string().c_str());
    reader->Update();
    p.image = reader->GetOutput();
    return p;
}

bool close(const std::array<double, 3>& got, const std::array<double, 3>& want) {
    for (int k = 0; k < 3; ++k)
        if (std::abs(got[k] - want[k]) > 0.02) return false;
    return true;
}
}  // namespace

// One colour scale for a series: the same particle with the same energy has the same colour in two
// frames whose own extents differ (the first holds one hot particle), the scale runs from the
// series' smallest value to its 99th percentile, and what lies above is red and counted.
BOOST_AUTO_TEST_CASE(one_colour_scale_for_every_frame_of_a_series) {
    const fs::path dir = fs::temp_directory_path() / "micromacro_render_series_test";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const auto a = frame(dir, "particles_0.vtp", {1.0, 2.0, 100.0}), b = frame(dir, "particles_1.vtp", {1.0, 2.0, 3.0});
    mm::io::PvdCollection series(dir / "particles.pvd");
    series.add(0.0, a);
    series.add(1.0, b);
    series.write();
    const auto [lo, hi] = viz::colour_scale({1.0, 2.0, 100.0, 0.0, 1.0, 2.0, 3.0, 0.0}, false, true);
    BOOST_TEST(lo == 0.0);
    BOOST_TEST(hi == 3.0);  // the 99th percentile of 8 values: the 7th smallest
    const auto first = render(dir, a.string() + " --range-from " + (dir / "particles.pvd").string());
    const auto second = render(dir, b.string() + " --range-from " + (dir / "particles.pvd").string());
    BOOST_TEST_REQUIRE(first.result.status == 0, first.result.err);
    BOOST_TEST_REQUIRE(second.result.status == 0, second.result.err);
    for (int i : {0, 1}) {
        BOOST_TEST(close(first.at(3e-3 * i, 0.0), second.at(3e-3 * i, 0.0)), "disk " << i);
        BOOST_TEST(close(first.at(3e-3 * i, 0.0), viz::energy_colour((1.0 + i) / 3.0)), "disk " << i);
    }
    BOOST_TEST(close(first.at(6e-3, 0.0), {1.0, 0.0, 0.0}));   // 100: above the scale, red
    BOOST_TEST(close(second.at(6e-3, 0.0), {1.0, 0.0, 0.0}));  // 3: the top of the scale
    BOOST_TEST(first.result.out.find("25.0% of this frame above it") != std::string::npos, first.result.out);
    BOOST_TEST(second.result.out.find("0.0% of this frame above it") != std::string::npos, second.result.out);
    // Each frame on its own scale, the same disk differs: the reason for the option.
    const auto own = render(dir, a.string());
    BOOST_TEST_REQUIRE(own.result.status == 0, own.result.err);
    BOOST_TEST(!close(own.at(0.0, 0.0), first.at(0.0, 0.0)));
}

// --range gives the scale; --log spaces it by decades (a value at the scale's geometric middle
// takes the colour map's middle); bad scales are refused and nothing is written.
BOOST_AUTO_TEST_CASE(a_given_and_a_logarithmic_scale) {
    const fs::path dir = fs::temp_directory_path() / "micromacro_render_series_test";
    fs::create_directories(dir);
    const auto f = frame(dir, "scale.vtp", {1e-9, 1e-8, 1e-7, 5.0});
    const auto given = render(dir, f.string() + " --range 0 3e-7");
    BOOST_TEST_REQUIRE(given.result.status == 0, given.result.err);
    BOOST_TEST(close(given.at(6e-3, 0.0), viz::energy_colour(1.0 / 3.0)));  // 1e-7 of 3e-7
    BOOST_TEST(close(given.at(9e-3, 0.0), {1.0, 0.0, 0.0}));                // 5 > 3e-7: red
    const auto decades = render(dir, f.string() + " --range 1e-9 1e-7 --log");
    BOOST_TEST_REQUIRE(decades.result.status == 0, decades.result.err);
    BOOST_TEST(close(decades.at(0.0, 0.0), viz::energy_colour(0.0)));
    BOOST_TEST(close(decades.at(3e-3, 0.0), viz::energy_colour(0.5)));  // 1e-8: the geometric middle
    BOOST_TEST(close(decades.at(6e-3, 0.0), viz::energy_colour(1.0)));
    for (const std::string& bad : std::vector<std::string>{" --range 2 1", " --range 0 1 --log", " --range 0 1 --range-from " + (dir / "particles.pvd").string()}) {
        const auto r = render(dir, f.string() + bad);
        BOOST_TEST(r.result.exit_code() == 1, bad);
        BOOST_TEST(!r.result.err.empty(), bad);
        BOOST_TEST(!fs::exists(dir / "picture.png"), bad);
    }
}

// A movie of a series: every frame rendered (on the series' scale), then encoded by ffmpeg where it
// is installed (ffprobe counts the frames), else the numbered PNGs stay with the command printed.
// A .vtp input and an existing movie are refused.
BOOST_AUTO_TEST_CASE(a_movie_of_a_series) {
    const fs::path dir = fs::temp_directory_path() / "micromacro_render_series_test";
    BOOST_TEST_REQUIRE(fs::exists(dir / "particles.pvd"));  // from one_colour_scale_for_every_frame_of_a_series
    const auto movie = dir / "movie.mp4", frames = dir / "movie_frames";
    fs::remove_all(frames);
    fs::remove(movie);
    const std::string program = std::string(XVFB_RUN) + " -a -s \"-screen 0 1280x1024x24\" " + RENDER_SNAPSHOT;
    const auto r = mmtest::run_program(program, (dir / "particles.pvd").string() + " --size 320x240 --movie " + movie.string(), dir);
    BOOST_TEST_REQUIRE(r.exit_code() == 0, r.err);
    if (mmtest::installed("ffmpeg")) {
        BOOST_TEST(fs::exists(movie));
        BOOST_TEST(!fs::exists(frames));
        const auto count = mmtest::run_program("ffprobe", "-v error -count_frames -select_streams v:0 -show_entries "
                                                          "stream=nb_read_frames -of csv=p=0 " + movie.string(), dir);
        BOOST_TEST(std::stoi(count.out) == 2, count.out);
    } else {
        BOOST_TEST(fs::exists(frames / "frame_0000.png"));
        BOOST_TEST(fs::exists(frames / "frame_0001.png"));
        BOOST_TEST(!fs::exists(frames / "frame_0002.png"));
        BOOST_TEST(r.out.find("ffmpeg -loglevel error") != std::string::npos, r.out);
    }
    const auto single = mmtest::run_program(program, (dir / "particles_0.vtp").string() + " --movie " + (dir / "other.mp4").string(), dir);
    BOOST_TEST(single.exit_code() == 1);
    BOOST_TEST(single.err.find("needs a .pvd series") != std::string::npos, single.err);
    std::ofstream(dir / "taken.mp4") << "an earlier movie";
    const auto taken = mmtest::run_program(program, (dir / "particles.pvd").string() + " --movie " + (dir / "taken.mp4").string(), dir);
    BOOST_TEST(taken.exit_code() == 1);
    BOOST_TEST(mmtest::slurp(dir / "taken.mp4") == "an earlier movie");
}

namespace {
// A picture's colour at a pixel (row 0 at the top) and whether it is the background.
struct Image {
    vtkSmartPointer<vtkImageData> data;
    int height;
    std::array<double, 3> rgb(int col, int row) const {
        std::array<double, 3> c;
        for (int k = 0; k < 3; ++k) c[k] = data->GetScalarComponentAsDouble(col, height - 1 - row, 0, k) / 255.0;
        return c;
    }
    bool background(int col, int row) const { return close(rgb(col, row), viz::background); }
};

Image read_png(const fs::path& png, int height) {
    vtkNew<vtkPNGReader> reader;
    reader->SetFileName(png.string().c_str());
    reader->Update();
    return {reader->GetOutput(), height};
}

}  // namespace

// A slab of a 3D box: seen across y, only the spheres whose centres lie within the slab are drawn
// (x to the right, z up), and the picture spans the whole box so that slices line up; 'mid' takes
// the middle of the frame; the frame's own numbers are printed. Without --3d, or with a bad axis or
// thickness, --slice is refused.
BOOST_AUTO_TEST_CASE(a_slice_shows_only_the_particles_in_its_slab) {
    const fs::path dir = fs::temp_directory_path() / "micromacro_render_slice_test";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const double a = 1e-3;
    // Corners of the box's x-z extent (in the slab), one sphere in front of the slab (y = 4 mm)
    // and one behind it (y = -4 mm) where nothing in the slab covers them.
    auto f = at_rest<3>({{0, 0, 0}, {8e-3, 0, 8e-3}, {0, 0, 8e-3}, {8e-3, 4e-3, 0}, {4e-3, -4e-3, 4e-3}}, a, std::vector<double>(5, 1.0));
    f.values = {{"eps_zz", 0.125}};
    mm::io::write_particles(f, dir / "box.vtp");
    const int width = 640, height = 480;
    const std::string program = std::string(XVFB_RUN) + " -a -s \"-screen 0 1280x1024x24\" " + RENDER_SNAPSHOT;
    auto render3d = [&](const std::string& args) {
        fs::remove(dir / "slice.png");
        return mmtest::run_program(program, (dir / "box.vtp").string() + " --3d --size 640x480 " + args + " -o " + (dir / "slice.png").string(), dir);
    };
    const auto cut = render3d("--slice y 0 2e-3");
    BOOST_TEST_REQUIRE(cut.status == 0, cut.err);
    BOOST_TEST(cut.out.find("eps_zz = 0.125") != std::string::npos, cut.out);
    const auto view = viz::View::fit(-a, 8e-3 + a, -a, 8e-3 + a, width, height, 40);  // x-z, below the caption
    const auto image = read_png(dir / "slice.png", height);
    for (auto [x, z] : {std::pair{0.0, 0.0}, std::pair{8e-3, 8e-3}, std::pair{0.0, 8e-3}}) {
        const auto [col, row] = view.pixel(x, z);
        BOOST_TEST(!image.background(col, row), "the sphere in the slab at x = " << x << ", z = " << z);
    }
    for (auto [x, z] : {std::pair{8e-3, 0.0}, std::pair{4e-3, 4e-3}}) {
        const auto [col, row] = view.pixel(x, z);
        BOOST_TEST(image.background(col, row), "the sphere out of the slab at x = " << x << ", z = " << z);
    }
    // 'mid': the middle of the centres' y extent, 0 here; a slab at y = 4 mm holds only the one in front.
    const auto middle = render3d("--slice y mid 2e-3");
    BOOST_TEST_REQUIRE(middle.status == 0, middle.err);
    const auto same = read_png(dir / "slice.png", height);
    for (auto [x, z] : {std::pair{0.0, 0.0}, std::pair{8e-3, 0.0}, std::pair{4e-3, 4e-3}}) {
        const auto [col, row] = view.pixel(x, z);
        BOOST_TEST(same.background(col, row) == image.background(col, row), "'mid' at x = " << x << ", z = " << z);
    }
    const auto front = render3d("--slice y 4e-3 2e-3");
    BOOST_TEST_REQUIRE(front.status == 0, front.err);
    const auto shifted = read_png(dir / "slice.png", height);
    BOOST_TEST(!shifted.background(view.pixel(8e-3, 0.0)[0], view.pixel(8e-3, 0.0)[1]));
    BOOST_TEST(shifted.background(view.pixel(0.0, 0.0)[0], view.pixel(0.0, 0.0)[1]));
    for (const std::string bad : {"--slice w 0 1e-3", "--slice y 0 0", "--slice y zero 1e-3"}) {
        const auto r = render3d(bad);
        BOOST_TEST(r.exit_code() == 1, bad);
        BOOST_TEST(r.err.find("--slice") != std::string::npos, bad << ": " << r.err);
        BOOST_TEST(!fs::exists(dir / "slice.png"), bad);
    }
    const auto flat = mmtest::run_program(program, (dir / "box.vtp").string() + " --slice y 0 1e-3 -o " + (dir / "slice.png").string(), dir);
    BOOST_TEST(flat.exit_code() == 1);
    BOOST_TEST(flat.err.find("give --3d too") != std::string::npos, flat.err);
}

// The force network as tubes: a contact with twice the normal force is drawn twice as wide, the
// largest as wide as 0.6 mean radii (tube radius 0.3 a); a contact pulling (f_n <= 0) is not drawn.
BOOST_AUTO_TEST_CASE(the_force_network_as_tubes_scaled_by_force) {
    const fs::path dir = fs::temp_directory_path() / "micromacro_render_network_test";
    fs::remove_all(dir);
    fs::create_directories(dir);
    // One black disk (energy 0 on the scale 0..1) of radius 30 mm at z = 10 mm behind three
    // horizontal lines at z = -10, 15 and 30 mm with normal forces 2, 1 and 0 N; the second disk
    // sets the scale's top and the mean radius.
    const double a = 30e-3;
    mm::io::write_particles(at_rest<2>({{10e-3, 10e-3}, {100e-3, 10e-3}}, a, {0.0, 1.0}), dir / "p.vtp");
    {
        vtkNew<vtkPoints> points;
        vtkNew<vtkCellArray> lines;
        vtkNew<vtkDoubleArray> force;
        force->SetName("normal_force");
        const double heights[3] = {-10e-3, 15e-3, 30e-3}, forces[3] = {2.0, 1.0, 0.0};
        for (int k = 0; k < 3; ++k) {
            const vtkIdType ends[2] = {points->InsertNextPoint(0.0, heights[k], 0.0), points->InsertNextPoint(20e-3, heights[k], 0.0)};
            lines->InsertNextCell(2, ends);
            force->InsertNextValue(forces[k]);
        }
        vtkNew<vtkPolyData> contacts;
        contacts->SetPoints(points);
        contacts->SetLines(lines);
        contacts->GetCellData()->AddArray(force);
        vtkNew<vtkXMLPolyDataWriter> writer;
        writer->SetFileName((dir / "c.vtp").string().c_str());
        writer->SetInputData(contacts);
        BOOST_TEST_REQUIRE(writer->Write() == 1);
    }
    const int width = 640, height = 480;
    const auto r = mmtest::run_program(std::string(XVFB_RUN) + " -a -s \"-screen 0 1280x1024x24\" " + RENDER_SNAPSHOT,
                                       (dir / "p.vtp").string() + " --contacts " + (dir / "c.vtp").string() +
                                           " --size 640x480 -o " + (dir / "n.png").string(),
                                       dir);
    BOOST_TEST_REQUIRE(r.status == 0, r.err);
    BOOST_TEST(r.out.find("the widest tube 2 N") != std::string::npos, r.out);
    const auto image = read_png(dir / "n.png", height);
    const auto view = viz::View::fit(10e-3 - a, 100e-3 + a, 10e-3 - a, 10e-3 + a, width, height);
    const double metres_per_pixel = 2.0 * view.half_height / height;
    // The white band's height at x = 10 mm, about each line.
    auto band = [&](double z) {
        int rows = 0;
        const int col = view.pixel(10e-3, z)[0];
        for (int row = view.pixel(0.0, z + 9.5e-3)[1]; row <= view.pixel(0.0, z - 9.5e-3)[1]; ++row) {
            const auto c = image.rgb(col, row);
            rows += c[0] > 0.5 && c[1] > 0.5 && c[2] > 0.5;
        }
        return rows * metres_per_pixel;
    };
    const double widest = band(-10e-3), half = band(15e-3);
    BOOST_TEST(std::abs(widest - 0.6 * a) < 0.05 * 0.6 * a, "widest band " << widest << " m, tube diameter " << 0.6 * a);
    BOOST_TEST(std::abs(half - 0.3 * a) < 0.08 * 0.3 * a, "half-force band " << half << " m, tube diameter " << 0.3 * a);
    BOOST_TEST(band(30e-3) == 0.0, "a contact without normal force");
}
