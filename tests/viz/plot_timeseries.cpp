// plot_timeseries under Xvfb: a synthetic time series plots at the requested size, with the
// first curve's colour where the curve must be (found through the PNG's plot-area sidecar) and
// background elsewhere; without a display, or with a damaged series, it refuses with a clear
// message and writes nothing.
#define BOOST_TEST_MODULE viz_plot_timeseries
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>

#include <nlohmann/json.hpp>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>

#include "support/programs.hpp"

namespace fs = std::filesystem;

namespace {
const fs::path dir = fs::temp_directory_path() / "micromacro_plot_test";

// A 2D series: every column the plots use; tr F = 3 + 5 eps, nu C = 2, the rest simple lines.
void write_series(const fs::path& path) {
    std::vector<std::string> names{"time", "strain_22", "trF", "trF_over_g2", "volume_fraction", "coordination",
                                   "deviatoric_fabric", "phi_F", "sigma_11", "sigma_22", "sigma_wall_11", "sigma_wall_22",
                                   "volumetric_strain"};
    for (std::string e : {"1111", "2222", "1122", "1212", "1112", "1222"}) names.push_back("C_n_" + e);
    for (std::string e : {"1111", "2222", "1122", "1212", "2121", "1112", "1222", "1121", "2122"}) names.push_back("C_t_" + e);
    std::ofstream out(path);
    out << "# synthetic\n";
    for (std::size_t i = 0; i < names.size(); ++i) out << (i ? "," : "") << names[i];
    out << "\n";
    for (int r = 0; r <= 100; ++r) {
        const double eps = 0.002 * r;
        for (std::size_t i = 0; i < names.size(); ++i) {
            double v = 1.0;
            if (names[i] == "strain_22") v = eps;
            else if (names[i] == "trF") v = 3.0 + 5.0 * eps;
            else if (names[i] == "trF_over_g2") v = 2.5;
            else if (names[i] == "volume_fraction") v = 0.8;
            else if (names[i] == "coordination") v = 2.5;
            out << (i ? "," : "") << v;
        }
        out << "\n";
    }
}
}  // namespace

BOOST_AUTO_TEST_CASE(curve_where_it_must_be) {
    fs::remove_all(dir);
    fs::create_directories(dir);
    write_series(dir / "timeseries.csv");
    const auto r = mmtest::run_program(std::string(XVFB_RUN) + " -a -s \"-screen 0 1280x1024x24\" " + PLOT_TIMESERIES,
                                       (dir / "timeseries.csv").string() + " --size 800x500 --out " + (dir / "plots").string(), dir);
    BOOST_TEST_REQUIRE(r.status == 0, r.err);
    for (std::string name : {"fabric", "fabric_deviator", "stiffness_normal", "stiffness_tangential", "stress", "volumetric"})
        BOOST_TEST(fs::exists(dir / "plots" / (name + ".png")), name);
    vtkNew<vtkPNGReader> reader;
    reader->SetFileName((dir / "plots" / "fabric.png").string().c_str());
    reader->Update();
    auto* image = reader->GetOutput();
    int dims[3];
    image->GetDimensions(dims);
    BOOST_TEST(dims[0] == 800);
    BOOST_TEST(dims[1] == 500);
    const auto side = nlohmann::json::parse(std::ifstream(dir / "plots" / "fabric.png.json"));
    const double x0 = side["plot_area"][0], y0 = side["plot_area"][1], x1 = side["plot_area"][2], y1 = side["plot_area"][3];
    const double xmin = side["x_range"][0], xmax = side["x_range"][1], ymin = side["y_range"][0], ymax = side["y_range"][1];
    auto pixel = [&](double x, double y) {  // from the bottom-left, as VTK images count
        return std::array<int, 2>{static_cast<int>(x0 + (x - xmin) / (xmax - xmin) * (x1 - x0)),
                                  static_cast<int>(y0 + (y - ymin) / (ymax - ymin) * (y1 - y0))};
    };
    auto reddish_near = [&](std::array<int, 2> p) {  // the first curve's colour within 2 pixels
        for (int dx = -2; dx <= 2; ++dx)
            for (int dy = -2; dy <= 2; ++dy) {
                const double rr = image->GetScalarComponentAsDouble(p[0] + dx, p[1] + dy, 0, 0);
                const double gg = image->GetScalarComponentAsDouble(p[0] + dx, p[1] + dy, 0, 1);
                const double bb = image->GetScalarComponentAsDouble(p[0] + dx, p[1] + dy, 0, 2);
                if (rr > 150 && gg < 110 && bb < 110) return true;
            }
        return false;
    };
    for (double eps : {0.02, 0.1, 0.18}) BOOST_TEST(reddish_near(pixel(eps, 3.0 + 5.0 * eps)), "tr F at eps " << eps);
    // Far from every curve (tr F from 3 to 4, the others at 2 and 2.5): background.
    const auto empty = pixel(0.1, 3.6);
    BOOST_TEST(!reddish_near(empty));
    BOOST_TEST(image->GetScalarComponentAsDouble(empty[0], empty[1] - 40, 0, 1) > 200);  // white-ish (grid lines aside)
}

BOOST_AUTO_TEST_CASE(no_display_is_a_clear_error) {
    const auto r = mmtest::run_program("env -u DISPLAY " + std::string(PLOT_TIMESERIES), (dir / "timeseries.csv").string(), dir);
    BOOST_TEST(r.status != 0);
    BOOST_TEST(r.err.find("run under xvfb-run") != std::string::npos, r.err);
}

// A plot is never written over its input: a series kept as plots/stress.png (a name the plots
// take) is refused as --out's, and left as it was.
BOOST_AUTO_TEST_CASE(the_input_is_never_written_over) {
    const fs::path plots = dir / "over" / "plots";
    fs::remove_all(dir / "over");
    fs::create_directories(plots);
    write_series(plots / "stress.png");
    const std::string before = mmtest::slurp(plots / "stress.png");
    const auto r = mmtest::run_program(std::string(XVFB_RUN) + " -a -s \"-screen 0 1280x1024x24\" " + PLOT_TIMESERIES,
                                       (plots / "stress.png").string() + " --out " + plots.string(), dir);
    BOOST_TEST(r.exit_code() == 1);
    BOOST_TEST(r.err.find("is the input " + (plots / "stress.png").string()) != std::string::npos, r.err);
    BOOST_TEST((mmtest::slurp(plots / "stress.png") == before));
    BOOST_TEST(!fs::exists(plots / "fabric.png"));  // refused before any plot
}

// Damaged series are refused with the file, line and column, before any picture is written: a
// missing column (no partial set of plots), a field that is not a number, a row of another
// length (two runs' rows glued together), an infinite value.
BOOST_AUTO_TEST_CASE(damaged_series_write_nothing) {
    fs::create_directories(dir);
    write_series(dir / "timeseries.csv");
    std::ifstream in(dir / "timeseries.csv");
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    struct Case {
        std::string name, expect;
        std::vector<std::string> lines;
    };
    auto edited = [&](std::size_t k, const std::string& line) {
        auto copy = lines;
        copy[k] = line;
        return copy;
    };
    const std::string header = lines[1];
    const std::string no_trF = std::regex_replace(header, std::regex(",trF,"), ",trX,");
    std::string short_row = lines[5].substr(0, lines[5].rfind(','));
    const Case cases[] = {
        {"missing", "has no column trF", edited(1, no_trF)},
        {"text", "timeseries.csv:6: column 'time' holds 'abc', not a finite number", edited(5, "abc" + lines[5].substr(lines[5].find(',')))},
        {"short", "timeseries.csv:6: " + std::to_string(std::count(header.begin(), header.end(), ',')) + " fields where the header has",
         edited(5, short_row)},
        {"infinite", "column 'time' holds 'inf'", edited(7, "inf" + lines[7].substr(lines[7].find(',')))},
    };
    for (const auto& c : cases) {
        const fs::path series = dir / c.name / "timeseries.csv", plots = dir / c.name / "plots";
        fs::remove_all(dir / c.name);
        fs::create_directories(dir / c.name);
        std::ofstream out(series);
        for (const auto& line : c.lines) out << line << "\n";
        out.close();
        const auto r = mmtest::run_program(std::string(XVFB_RUN) + " -a -s \"-screen 0 1280x1024x24\" " + PLOT_TIMESERIES,
                                           series.string() + " --out " + plots.string(), dir);
        BOOST_TEST(r.exit_code() == 1, c.name);
        BOOST_TEST(r.err.find(c.expect) != std::string::npos, c.name << ": " << r.err);
        BOOST_TEST(!fs::exists(plots), c.name);
    }
}
