// plot_timeseries: the plots of the paper's Fig. 4 and 5 (and stress-strain curves) from a
// biaxial or element_test timeseries.csv, as PNG files, off-screen with VTK's charts.
//
//   xvfb-run -a -s "-screen 0 1280x1024x24" plot_timeseries runs/quick/timeseries.csv --out runs/quick/plots
//
// Writes fabric.png (tr F, tr F / g2, nu C against eps_zz: Fig. 4 left), fabric_deviator.png
// (deviatoric fabric and phi_F: Fig. 4 right), stiffness_normal.png (C^n entries / k: Fig. 5
// left), stiffness_tangential.png (C^t entries / k_t: Fig. 5 right), stress.png (inner-box and
// wall stresses) and volumetric.png; an element_test series gets the whole cell's stress and
// stress_ratio.png instead, against the strain its preset drives. Each PNG gets a .json sidecar with the plot area in pixels
// and the axis ranges, so a point of a curve can be found in the image. Needs an X server (VTK
// from Debian renders only through X): run under xvfb-run on a machine without a display.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <vtkAxis.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPen.h>
#include <vtkPlot.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTable.h>
#include <vtkTextProperty.h>
#include <vtkWindowToImageFilter.h>

#include <micromacro/io/whole_file.hpp>

#include "../examples/biaxial/timeseries.hpp"
#include "../examples/command_line.hpp"
#include "../examples/output_paths.hpp"
#include "offscreen.hpp"

namespace fs = std::filesystem;

namespace {
using viz::fail;

struct Series {
    std::string label;
    std::vector<double> y;
};

/// One chart: x against every series, written to `path` (PNG) and `path`.json.
void plot(const fs::path& path, const std::string& title, const std::string& xlabel, const std::string& ylabel,
          const std::vector<double>& x, const std::vector<Series>& series, int width, int height) {
    vtkNew<vtkTable> table;
    vtkNew<vtkDoubleArray> xs;
    xs->SetName(xlabel.c_str());
    for (double v : x) xs->InsertNextValue(v);
    table->AddColumn(xs);
    double ymin = 1e300, ymax = -1e300;
    for (const auto& s : series) {
        vtkNew<vtkDoubleArray> ys;
        ys->SetName(s.label.c_str());
        for (double v : s.y) {
            ys->InsertNextValue(v);
            ymin = std::min(ymin, v);
            ymax = std::max(ymax, v);
        }
        table->AddColumn(ys);
    }
    if (ymax <= ymin) ymax = ymin + 1.0;
    const double pad = 0.05 * (ymax - ymin);
    const double xmin = *std::min_element(x.begin(), x.end()), xmax = std::max(*std::max_element(x.begin(), x.end()), xmin + 1e-12);

    vtkNew<vtkContextView> view;
    view->GetRenderWindow()->SetOffScreenRendering(1);
    view->GetRenderWindow()->SetSize(width, height);
    view->GetRenderer()->SetBackground(1.0, 1.0, 1.0);
    vtkNew<vtkChartXY> chart;
    view->GetScene()->AddItem(chart);
    chart->SetTitle(title);
    chart->SetShowLegend(true);
    chart->GetLegend()->SetInline(false);  // beside the plot area, never over a curve
    chart->GetLegend()->SetHorizontalAlignment(vtkChartLegend::RIGHT);
    chart->GetLegend()->SetVerticalAlignment(vtkChartLegend::TOP);
    chart->GetAxis(vtkAxis::BOTTOM)->SetTitle(xlabel);
    chart->GetAxis(vtkAxis::LEFT)->SetTitle(ylabel);
    chart->GetAxis(vtkAxis::BOTTOM)->SetBehavior(vtkAxis::FIXED);
    chart->GetAxis(vtkAxis::BOTTOM)->SetRange(xmin, xmax);
    chart->GetAxis(vtkAxis::LEFT)->SetBehavior(vtkAxis::FIXED);
    chart->GetAxis(vtkAxis::LEFT)->SetRange(ymin - pad, ymax + pad);
    static const unsigned char colours[][3] = {{228, 26, 28}, {55, 126, 184}, {77, 175, 74}, {152, 78, 163},
                                               {255, 127, 0}, {166, 86, 40}, {247, 129, 191}, {80, 80, 80}, {0, 0, 0}};
    for (std::size_t s = 0; s < series.size(); ++s) {
        vtkPlot* line = chart->AddPlot(vtkChart::LINE);
        line->SetInputData(table, 0, static_cast<vtkIdType>(s + 1));
        const auto* c = colours[s % 9];
        line->SetColor(c[0], c[1], c[2], 255);
        line->SetWidth(2.0);
    }
    viz::write_png(view->GetRenderWindow(), path);
    // The plot area (pixels from the bottom-left) and the axis ranges.
    const auto p1 = chart->GetPoint1(), p2 = chart->GetPoint2();
    micromacro::io::write_whole_file(path.string() + ".json", std::ios::out, [&](std::ofstream& side) {
        side.precision(17);
        side << "{\"width\": " << width << ", \"height\": " << height << ", \"plot_area\": [" << p1[0] << ", " << p1[1]
             << ", " << p2[0] << ", " << p2[1] << "], \"x_range\": [" << xmin << ", " << xmax << "], \"y_range\": ["
             << ymin - pad << ", " << ymax + pad << "]}\n";
    });
}
}  // namespace

int main(int argc, char** argv) {
    std::string input, out = "plots", size = "900x600";
    double k = 1e5, kt_ratio = 0.2;
    CLI::App app{"Plots like the paper's Fig. 4 and 5 from a biaxial or element_test timeseries.csv (PNG, off-screen). Needs an X "
                 "server: run under xvfb-run -a -s \"-screen 0 1280x1024x24\" on a machine without a display."};
    app.add_option("timeseries", input, "timeseries.csv of a biaxial or element_test run")->required();
    app.add_option("--out", out, "directory for the PNG files (created)")->capture_default_str();
    app.add_option("--size", size, "image size WIDTHxHEIGHT")->capture_default_str();
    app.add_option("--k", k, "normal stiffness k (N/m) to scale C^n")->check(micromacro::cli::positive())->capture_default_str();
    app.add_option("--kt-ratio", kt_ratio, "k_t / k to scale C^t")->check(micromacro::cli::positive())->capture_default_str();
    MICROMACRO_PARSE_COMMAND_LINE(app, argc, argv);
    try {
        const auto [width, height] = viz::parse_size(size);
        if (!fs::is_regular_file(input)) fail("cannot read " + input + (fs::exists(input) ? ": not a regular file" : ": no such file"));
        const auto col = biaxial::read_timeseries(input);
        if (col.empty() || !col.count("time")) fail(input + " is not a biaxial time series (no time column)");
        viz::require_display("plot_timeseries");  // after the input: a bad file is said first
        const bool three = col.count("strain_33") > 0;
        const std::string z = three ? "3" : "2";
        const std::string zz = z + z;
        auto get = [&](const std::string& name) {
            const auto it = col.find(name);
            if (it == col.end()) fail(input + " has no column " + name);
            return it->second;
        };
        auto scaled = [](std::vector<double> v, double f) {
            for (auto& x : v) x *= f;
            return v;
        };
        // Every chart's columns are gathered before any file is written: a missing column
        // leaves no partial set of plots behind.
        struct Chart {
            std::string file, title, ylabel;
            std::vector<Series> series;
        };
        std::vector<Chart> charts;
        // An element test's series (element_test: a periodic cell, no walls) is drawn against the
        // strain its preset drives (loading_strain), a biaxial one against eps_zz.
        const bool cell = col.count("loading_strain") > 0;
        const auto eps = get(cell ? "loading_strain" : "strain_" + zz);
        const std::string x = cell ? "loading strain (1): eps_zz, shear gamma_1z or volumetric, by preset" : "eps_zz (1)";
        std::vector<double> nuC = get("volume_fraction");
        const auto C = get("coordination");
        for (std::size_t i = 0; i < nuC.size(); ++i) nuC[i] *= C[i];
        std::vector<Series> fabric{{"tr F", get("trF")}, {"nu C", nuC}};
        if (!cell) fabric.insert(fabric.begin() + 1, Series{"tr F / g2", get("trF_over_g2")});
        charts.push_back({"fabric.png", "Fabric (Fig. 4)", "contact number density (1)", fabric});
        std::vector<Series> dev{{"deviatoric fabric", get("deviatoric_fabric")}};
        if (!three) dev.push_back({"phi_F (rad)", get("phi_F")});
        charts.push_back({"fabric_deviator.png", "Fabric anisotropy (Fig. 4)", "deviator (1), angle (rad)", dev});
        const std::vector<std::string> normal = three ? std::vector<std::string>{"1111", "2222", "3333", "1133", "1313"}
                                                      : std::vector<std::string>{"1111", "2222", "1122", "1212", "1112", "1222"};
        std::vector<Series> cn, ct;
        for (const auto& e : normal) cn.push_back({"C_n_" + e, scaled(get("C_n_" + e), 1.0 / k)});
        const std::vector<std::string> tang = three ? std::vector<std::string>{"1111", "3333", "1313", "3131", "1133"}
                                                    : std::vector<std::string>{"1111", "2222", "1122", "1212", "2121", "1112", "1222", "1121", "2122"};
        for (const auto& e : tang) ct.push_back({"C_t_" + e, scaled(get("C_t_" + e), 1.0 / (kt_ratio * k))});
        charts.push_back({"stiffness_normal.png", "Normal stiffness (Fig. 5 left)", "C^n / k (1)", cn});
        charts.push_back({"stiffness_tangential.png", "Tangential stiffness (Fig. 5 right)", "C^t / k_t (1)", ct});
        const std::string unit = three ? "Pa" : "N/m";
        if (cell) {
            charts.push_back({"stress.png", "Stress (whole cell)", "stress (" + unit + ")",
                              {{"sigma_11", get("sigma_11")}, {"sigma_" + zz, get("sigma_" + zz)}, {"sigma_1" + z, get("sigma_1" + z)},
                               {"pressure", get("pressure")}}});
            charts.push_back({"stress_ratio.png", "Stress ratio", "ratio (1)",
                              {{"deviatoric stress / p", get("stress_ratio")}, {"-sigma_1" + z + " / sigma_" + zz, get("shear_stress_ratio")}}});
        } else {
            charts.push_back({"stress.png", "Stress", "stress (" + unit + ")",
                              {{"sigma_11 (inner)", get("sigma_11")}, {"sigma_" + zz + " (inner)", get("sigma_" + zz)},
                               {"sigma_11 (walls)", get("sigma_wall_11")}, {"sigma_" + zz + " (walls)", get("sigma_wall_" + zz)}}});
        }
        charts.push_back({"volumetric.png", "Volumetric strain", "volumetric strain (1, compaction > 0)",
                          {{"volumetric strain", get("volumetric_strain")}}});
        if (eps.size() < 2) fail(input + " has " + std::to_string(eps.size()) + " rows; a plot needs at least 2");
        for (const auto& c : charts)
            for (const fs::path& file : {fs::path(out) / c.file, fs::path(out) / (c.file + ".json")})
                micromacro::cli::refuse_writing_over_inputs(file, "--out", {{"the input", input}});
        std::error_code ec;
        fs::create_directories(out, ec);
        if (!fs::is_directory(out)) fail("cannot create the directory " + out);
        for (const auto& c : charts) plot(fs::path(out) / c.file, c.title, x, c.ylabel, eps, c.series, width, height);
        std::printf("plot_timeseries: %zu plots in %s\n", charts.size(), out.c_str());
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "plot_timeseries: %s\n", e.what());
        return 1;
    }
}
