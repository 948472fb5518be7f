// render_snapshot: a picture like the paper's Fig. 3 from a particles .vtp (or one step of a
// .pvd): filled disks at their true radius (spheres in 3D) coloured by potential energy (red and
// green high, through blue to black low), a colour bar, the walls, optionally the force network
// as tubes whose radius follows the normal force. The colour scale is the frame's own extent, or
// one for a whole series (--range MIN MAX, or --range-from SERIES.pvd: up to its 99th
// percentile), so that frames compare by colour; --log. A 3D box is seen from outside, or cut
// (--slice AXIS POSITION THICKNESS) to show its interior. The frame's own numbers (the biaxial
// program's eps_zz) are printed on the picture.
//
//   xvfb-run -a -s "-screen 0 1280x1024x24" render_snapshot vtk/particles.pvd --step -1
//       --walls vtk/walls_10.vtp --contacts vtk/contacts_10.vtp -o snapshot.png   (one line)
//
// VTK 9.1 from Debian renders only through an X server: on a machine without a display run it
// under xvfb-run as above (Mesa software rendering, well under a second a frame).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkColorTransferFunction.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkFieldData.h>
#include <vtkGlyph3DMapper.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRegularPolygonSource.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkSphereSource.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkTubeFilter.h>
#include <vtkWindowToImageFilter.h>
#include <vtkXMLPPolyDataReader.h>
#include <vtkXMLPolyDataReader.h>

#include "../examples/command_line.hpp"
#include "../examples/installed.hpp"
#include "../examples/output_paths.hpp"
#include "offscreen.hpp"
#include "slice.hpp"
#include "snapshot_view.hpp"

namespace fs = std::filesystem;

namespace {
using viz::fail;

/// One data set of a .pvd collection: its file (a path next to the collection) and time.
struct Entry {
    fs::path file;
    double time;
};

/// The data sets a .pvd collection lists, in order.
std::vector<Entry> collection(const fs::path& pvd) {
    std::ifstream in(pvd);
    if (!in) fail("cannot open " + pvd.string());
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    std::vector<Entry> entries;
    const std::regex data_set("<DataSet[^>]*timestep=\"([^\"]*)\"[^>]*file=\"([^\"]+)\"");
    for (auto it = std::sregex_iterator(text.begin(), text.end(), data_set); it != std::sregex_iterator(); ++it)
        entries.push_back({pvd.parent_path() / std::string((*it)[2]), std::strtod(std::string((*it)[1]).c_str(), nullptr)});
    if (text.find("</VTKFile>") == std::string::npos) fail(pvd.string() + " is truncated (no closing </VTKFile>)");
    if (entries.empty()) fail(pvd.string() + " lists no data sets");
    return entries;
}

/// The file of step `step` (negative: from the end) of a .pvd collection, or the file itself.
fs::path resolve(const fs::path& input, int step) {
    if (input.extension() != ".pvd") return input;
    const std::vector<Entry> files = collection(input);
    const int n = static_cast<int>(files.size());
    const int index = step < 0 ? n + step : step;
    if (index < 0 || index >= n) fail("--step " + std::to_string(step) + " is outside the " + std::to_string(n) + " steps of " + input.string());
    return files[static_cast<std::size_t>(index)].file;
}

/// Refuses a picture (`png`, unless empty) or a movie (`movie` and its folder of frames, unless
/// empty) that would replace a file this run reads: the input and the frames a .pvd lists, the
/// walls, the contacts, the series of --range-from and its frames.
void refuse_outputs_over_inputs(const fs::path& input, const fs::path& walls, const fs::path& contacts, const fs::path& range_from,
                                const fs::path& png, const fs::path& movie) {
    std::vector<micromacro::cli::Input> inputs = {{"the input", input}, {"--walls", walls}, {"--contacts", contacts},
                                                  {"--range-from", range_from}};
    for (const auto& [given_as, series] : {std::pair<std::string, fs::path>{"a frame of the input", input}, {"a frame of --range-from", range_from}})
        if (series.extension() == ".pvd" && fs::is_regular_file(series))
            for (const Entry& frame : collection(series)) inputs.push_back({given_as, frame.file});
    micromacro::cli::refuse_writing_over_inputs(png, "-o", inputs);
    if (movie.empty()) return;
    micromacro::cli::refuse_writing_over_inputs(movie, "--movie", inputs);
    const fs::path frames = movie.parent_path() / (movie.stem().string() + "_frames");
    for (const auto& in : inputs)
        if (!in.path.empty() && micromacro::cli::same_file(in.path.parent_path(), frames))
            fail("--movie " + movie.string() + " would write its frames into " + frames.string() + ", which holds " + in.given_as +
                 " " + in.path.string() + "; give another --movie");
}

/// A .vtp file, or a .pvtp summary with its pieces (a run over MPI ranks) as one data set;
/// `need_points`: refuse one without points (a particles file must have some).
vtkSmartPointer<vtkPolyData> read(const fs::path& p, bool need_points = true) {
    if (!fs::is_regular_file(p)) fail("cannot read " + p.string() + (fs::exists(p) ? ": not a regular file" : ": no such file"));
    vtkSmartPointer<vtkXMLReader> reader;
    if (p.extension() == ".pvtp")
        reader = vtkSmartPointer<vtkXMLPPolyDataReader>::New();
    else
        reader = vtkSmartPointer<vtkXMLPolyDataReader>::New();
    // A damaged or truncated file makes the reader raise error events and return what it read
    // so far; any error refuses the file instead of drawing part of it.
    const micromacro::io::VtkMessages vtk_said(reader);
    reader->SetFileName(p.string().c_str());
    reader->Update();
    if (vtk_said.any_error() || reader->GetErrorCode() != vtkErrorCode::NoError)
        fail(p.string() + " is damaged or truncated (VTK could not read it whole" +
             (vtk_said.text().empty() ? "" : ": " + vtk_said.text()) + ")");
    vtkSmartPointer<vtkPolyData> data = vtkPolyData::SafeDownCast(reader->GetOutputDataObject(0));
    if (!data || (need_points && data->GetNumberOfPoints() == 0)) fail(p.string() + " holds no points (not a particles .vtp?)");
    return data;
}

/// Draws `data` (walls, contact lines) in one flat colour and returns its actor.
vtkSmartPointer<vtkActor> overlay(vtkRenderer* renderer, vtkPolyData* data, double grey, double line_width) {
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(data);
    mapper->ScalarVisibilityOff();
    auto actor = vtkSmartPointer<vtkActor>::New();
    actor->SetMapper(mapper);
    actor->GetProperty()->SetColor(grey, grey, grey);
    actor->GetProperty()->SetLineWidth(line_width);
    actor->GetProperty()->LightingOff();
    renderer->AddActor(actor);
    return actor;
}

/// The frame's own numbers (field data, e.g. eps_zz = 0.1), as "name = value" joined by spaces.
std::string frame_values(vtkPolyData* frame) {
    std::string text;
    auto* fields = frame->GetFieldData();
    for (int k = 0; fields && k < fields->GetNumberOfArrays(); ++k) {
        auto* a = fields->GetArray(k);
        if (!a || !a->GetName() || a->GetNumberOfTuples() != 1 || a->GetNumberOfComponents() != 1) continue;
        char item[96];
        std::snprintf(item, sizeof item, "%s%s = %.4g", text.empty() ? "" : "   ", a->GetName(), a->GetTuple1(0));
        text += item;
    }
    return text;
}
}  // namespace

int main(int argc, char** argv) {
    std::string input, walls, contacts, output = "snapshot.png", size = "1000x800", range_from;
    std::string movie;
    std::vector<double> fixed_range;
    std::vector<std::string> slice_words;
    int step = -1, frames_per_second = 8;
    bool three_d = false, log_scale = false;
    CLI::App app{"Render particles coloured by potential energy (the paper's Fig. 3) to a PNG, off-screen. "
                 "Needs an X server: run under xvfb-run -a -s \"-screen 0 1280x1024x24\" on a machine without a display."};
    app.add_option("input", input, "particles .vtp, or a .pvd collection (see --step)")->required();
    app.add_option("--step", step, "which step of a .pvd (negative counts from the end)")->capture_default_str();
    app.add_option("--walls", walls, "walls .vtp to draw");
    app.add_option("--contacts", contacts, "contacts .vtp: overlay the force network (a line per contact)");
    app.add_option("-o,--output", output, "PNG file to write")->capture_default_str();
    app.add_option("--size", size, "image size WIDTHxHEIGHT in pixels")->capture_default_str();
    app.add_flag("--3d", three_d, "draw spheres with lighting (default: flat disks in the plane z = 0)");
    app.add_option("--slice", slice_words,
                   "3D: draw only the particles whose centres lie in the slab |x_AXIS - POSITION| <= THICKNESS/2 (m; "
                   "POSITION 'mid': the middle of each frame's particles), seen along AXIS (x, y or z), with the "
                   "force network of --contacts in the slab; e.g. --slice y mid 0.004")
        ->expected(3);
    auto* range_option = app.add_option("--range", fixed_range, "colour scale MIN MAX in J (default: this frame's extent)")->expected(2);
    app.add_option("--range-from", range_from,
                   "one colour scale for every frame of this .pvd series: its smallest value (with --log the 1st percentile "
                   "of the positive ones) to its 99th percentile; values beyond take the end colours, and the colour bar "
                   "says how many")
        ->excludes(range_option);
    app.add_flag("--log", log_scale, "logarithmic colour scale");
    app.add_option("--movie", movie,
                   "render every frame of the .pvd input on one colour scale (the series', unless --range or --range-from), "
                   "its time printed on each, and make this .mp4 of them with ffmpeg if installed; else the numbered "
                   "PNGs stay in MOVIE_frames/ and the ffmpeg command is printed");
    app.add_option("--fps", frames_per_second, "frames per second of the movie")->check(CLI::Range(1, 120))->capture_default_str();
    MICROMACRO_PARSE_COMMAND_LINE(app, argc, argv);
    try {
        const auto [width, height] = viz::parse_size(size);
        const viz::Slice slice = viz::parse_slice(slice_words);
        if (slice.active() && !three_d) fail("--slice cuts a 3D box: give --3d too (a 2D frame is a slice already)");
        const auto axes = viz::image_axes(slice);
        if (!fixed_range.empty() && !(std::isfinite(fixed_range[0]) && std::isfinite(fixed_range[1]) && fixed_range[1] > fixed_range[0]))
            fail("--range " + std::to_string(fixed_range[0]) + " " + std::to_string(fixed_range[1]) + ": give MIN < MAX, both finite");
        const auto out_dir = fs::path(output).has_parent_path() ? fs::path(output).parent_path() : fs::path(".");
        if (!fs::is_directory(out_dir)) fail("cannot write " + output + ": the directory " + out_dir.string() + " does not exist");

        refuse_outputs_over_inputs(input, walls, contacts, range_from, movie.empty() ? output : "", movie);
        if (!movie.empty()) {
            if (fs::path(input).extension() != ".pvd") fail("--movie needs a .pvd series as input, not " + input);
            if (fs::exists(movie)) fail("--movie " + movie + " exists; remove it or give another name");
            const auto dir = fs::path(movie).has_parent_path() ? fs::path(movie).parent_path() : fs::path(".");
            if (!fs::is_directory(dir)) fail("cannot write " + movie + ": the directory " + dir.string() + " does not exist");
            if (fixed_range.empty() && range_from.empty()) range_from = input;  // one scale for the movie
        }
        const auto particles = read(resolve(input, step));
        auto* energy = particles->GetPointData()->GetArray("potential_energy");
        auto* radius = particles->GetPointData()->GetArray("radius");
        if (!energy || !radius) fail(input + " has no potential_energy or radius array");
        viz::require_display("render_snapshot");  // after the input: a bad file is said first
        // The colour scale: given, from a series, or this frame's own extent.
        std::array<double, 2> range;
        std::string scale_source = "this frame";
        double largest_force = 0.0;  // of the force network drawn last
        std::string last_label;      // the caption of the picture drawn last
        if (!fixed_range.empty()) {
            range = {fixed_range[0], fixed_range[1]};
            scale_source = "--range";
        } else if (!range_from.empty()) {
            std::vector<double> all;
            const auto frames = collection(range_from);
            for (const auto& [file, time] : frames) {
                const auto frame = read(file);
                auto* values = frame->GetPointData()->GetArray("potential_energy");
                if (!values) fail(file.string() + " has no potential_energy array");
                for (vtkIdType i = 0; i < values->GetNumberOfTuples(); ++i) all.push_back(values->GetTuple1(i));
            }
            range = viz::colour_scale(std::move(all), log_scale, true);
            scale_source = std::to_string(frames.size()) + " frames of " + range_from;
        } else {
            std::vector<double> own(static_cast<std::size_t>(energy->GetNumberOfTuples()));
            for (vtkIdType i = 0; i < energy->GetNumberOfTuples(); ++i) own[static_cast<std::size_t>(i)] = energy->GetTuple1(i);
            range = viz::colour_scale(std::move(own), log_scale, false);
        }
        if (log_scale && !(range[0] > 0.0))
            fail("--log needs a scale above zero, and " + scale_source + " gives " + std::to_string(range[0]) +
                 "; give --range with MIN > 0 or drop --log");
        if (!(range[1] > range[0])) range[1] = log_scale ? range[0] * (1.0 + 1e-9) : range[0] + std::max(1e-300, 1e-9 * std::abs(range[0]));
        // One window for every picture: VTK's X connection does not survive a second window.
        vtkNew<vtkRenderWindow> window;
        window->SetOffScreenRendering(1);
        window->SetSize(width, height);
        // One picture: `frame`'s particles (with the walls and contacts files if not empty) on the
        // colour scale, `caption` at the top left, written to `png`. Returns the share of the
        // particles above and below the scale.
        auto draw = [&](vtkPolyData* frame, const fs::path& walls_file, const fs::path& contacts_file, const std::string& caption,
                        const fs::path& png) -> std::array<double, 2> {
            auto* radius = frame->GetPointData()->GetArray("radius");
            if (!frame->GetPointData()->GetArray("potential_energy") || !radius) fail("a frame has no potential_energy or radius array");
            // The slab of this frame (its middle, for 'mid'), in picture coordinates.
            viz::Slice cut = slice;
            double bounds[6];
            frame->GetBounds(bounds);
            if (cut.middle) cut.position = 0.5 * (bounds[2 * cut.axis] + bounds[2 * cut.axis + 1]);
            const auto shown = viz::particles_in_view(frame, cut);
            auto* energy = shown->GetPointData()->GetArray("potential_energy");
            // Values beyond the scale take its end colours; how many of those drawn, the colour bar says.
            std::size_t above = 0, below = 0;
            for (vtkIdType i = 0; i < energy->GetNumberOfTuples(); ++i) {
                const double e = energy->GetTuple1(i);
                above += e > range[1];
                below += e < range[0];
            }
            const double n_values = std::max<double>(1.0, static_cast<double>(energy->GetNumberOfTuples()));

            vtkNew<vtkColorTransferFunction> colours;
            if (log_scale) colours->SetScaleToLog10();
            for (double u : {0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0}) {
                const auto c = viz::energy_colour(u);
                const double at = log_scale ? range[0] * std::pow(range[1] / range[0], u) : range[0] + u * (range[1] - range[0]);
                colours->AddRGBPoint(at, c[0], c[1], c[2]);
            }
            colours->ClampingOn();
            vtkNew<vtkGlyph3DMapper> glyphs;
            glyphs->SetInputData(shown);
            vtkNew<vtkRegularPolygonSource> disk;
            disk->SetNumberOfSides(48);
            disk->SetRadius(1.0);
            vtkNew<vtkSphereSource> sphere;
            sphere->SetRadius(1.0);
            sphere->SetThetaResolution(24);
            sphere->SetPhiResolution(16);
            if (three_d) glyphs->SetSourceConnection(sphere->GetOutputPort());
            else glyphs->SetSourceConnection(disk->GetOutputPort());
            glyphs->SetScaleArray("radius");
            glyphs->SetScaleModeToScaleByMagnitude();
            glyphs->SetScalarModeToUsePointFieldData();
            glyphs->SelectColorArray("potential_energy");
            glyphs->SetLookupTable(colours);
            glyphs->SetScalarRange(range.data());
            glyphs->ScalarVisibilityOn();
            vtkNew<vtkActor> actor;
            actor->SetMapper(glyphs);
            if (!three_d) actor->GetProperty()->LightingOff();  // exact colour-map colours on flat disks
            // In 3D the tubes of the force network run through the spheres: these are drawn see-through.
            if (three_d && !contacts_file.empty()) actor->GetProperty()->SetOpacity(0.35);

            vtkNew<vtkRenderer> renderer;
            renderer->SetBackground(viz::background[0], viz::background[1], viz::background[2]);
            renderer->AddActor(actor);

            // The picture spans the whole frame (or its walls), slab or not, so that slices and
            // frames line up.
            const double rmax = radius->GetRange()[1];
            double xlo = bounds[2 * axes[0]] - rmax, xhi = bounds[2 * axes[0] + 1] + rmax;
            double ylo = bounds[2 * axes[1]] - rmax, yhi = bounds[2 * axes[1] + 1] + rmax;
            if (!walls_file.empty()) {
                const auto wall_data = read(walls_file, false);
                double wb[6];
                wall_data->GetBounds(wb);
                xlo = wb[2 * axes[0]], xhi = wb[2 * axes[0] + 1], ylo = wb[2 * axes[1]], yhi = wb[2 * axes[1] + 1];
                const auto actor = overlay(renderer, viz::walls_in_view(wall_data, cut), 0.3, 3.0);
                if (cut.active()) actor->GetProperty()->SetRepresentationToWireframe();  // the walls seen edge-on, as lines
                else if (three_d) actor->GetProperty()->SetOpacity(0.15);
            }
            if (!contacts_file.empty()) {
                // Tubes through the contacts, the largest normal force of the frame as wide as
                // 0.3 of the mean radius, the others in proportion.
                auto* r = shown->GetPointData()->GetArray("radius");
                double mean_radius = 0.0;
                for (vtkIdType i = 0; r && i < r->GetNumberOfTuples(); ++i) mean_radius += r->GetTuple1(i) / r->GetNumberOfTuples();
                if (!(mean_radius > 0.0)) mean_radius = rmax;
                double largest = 0.0;
                const auto network = viz::network_in_view(read(contacts_file, false), cut, 0.3 * mean_radius, largest);
                vtkNew<vtkTubeFilter> tubes;
                tubes->SetInputData(network);
                tubes->SetVaryRadiusToVaryRadiusByAbsoluteScalar();
                tubes->SetNumberOfSides(12);  // seen from any side about 2 r wide (within 4%)
                tubes->CappingOn();
                tubes->Update();
                const auto actor = overlay(renderer, tubes->GetOutput(), three_d ? 0.1 : 1.0, 1.0);
                if (three_d) actor->GetProperty()->LightingOn();
                else actor->SetPosition(0, 0, 0.5 * (yhi - ylo));  // above the disks
                largest_force = largest;
            }

            // A logarithmic scale's bar shows log10 of the energy on a linear axis (VTK's bar samples a
            // log colour function linearly).
            vtkNew<vtkColorTransferFunction> bar_colours;
            for (double u : {0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0}) {
                const auto c = viz::energy_colour(u);
                const double lo = log_scale ? std::log10(range[0]) : range[0], hi = log_scale ? std::log10(range[1]) : range[1];
                bar_colours->AddRGBPoint(lo + u * (hi - lo), c[0], c[1], c[2]);
            }
            vtkNew<vtkScalarBarActor> bar;
            bar->SetLookupTable(bar_colours);
            std::string title = log_scale ? "log10 potential energy (J)" : "potential energy (J)";
            char share[64];
            if (above > 0) {
                std::snprintf(share, sizeof share, "\n%.1f%% above: red", 100.0 * above / n_values);
                title += share;
            }
            if (below > 0) {
                std::snprintf(share, sizeof share, "\n%.1f%% below: black", 100.0 * below / n_values);
                title += share;
            }
            bar->SetTitle(title.c_str());
            bar->SetNumberOfLabels(5);
            bar->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
            bar->GetPositionCoordinate()->SetValue(0.87, 0.1);
            bar->SetWidth(0.11);
            bar->SetHeight(0.8);
            for (auto* t : {bar->GetTitleTextProperty(), bar->GetLabelTextProperty()}) t->SetColor(0, 0, 0);
            renderer->AddActor2D(bar);

            std::string label = caption;
            if (const std::string values = frame_values(frame); !values.empty()) label += (label.empty() ? "" : "   ") + values;
            if (cut.active()) {
                char where[96];
                std::snprintf(where, sizeof where, "%sslice %c = %.4g +- %.3g", label.empty() ? "" : "   ", "xyz"[cut.axis], cut.position,
                              0.5 * cut.thickness);
                label += where;
            }
            last_label = label;
            const auto view = viz::View::fit(xlo, xhi, ylo, yhi, width, height, label.empty() ? 0 : 40);
            auto* camera = renderer->GetActiveCamera();
            camera->ParallelProjectionOn();
            const double nearest = bounds[2 * axes[2] + 1] + rmax;  // the frame's side towards the camera
            camera->SetFocalPoint(view.camera_x(), view.cy, nearest);
            camera->SetPosition(view.camera_x(), view.cy, nearest + 10.0 * (yhi - ylo + xhi - xlo));
            camera->SetViewUp(0, 1, 0);
            camera->SetParallelScale(view.half_height);
            renderer->ResetCameraClippingRange();

            if (!label.empty()) {
                vtkNew<vtkTextActor> text;
                text->SetInput(label.c_str());
                text->GetTextProperty()->SetColor(0, 0, 0);
                text->GetTextProperty()->SetFontSize(18);
                text->SetDisplayPosition(10, height - 30);
                renderer->AddActor2D(text);
            }
            window->AddRenderer(renderer);
            viz::write_png(window, png);
            window->RemoveRenderer(renderer);
            return {100.0 * above / n_values, 100.0 * below / n_values};
        };

        if (!movie.empty()) {
            const auto frames = collection(input);
            const fs::path folder = fs::path(movie).parent_path() / (fs::path(movie).stem().string() + "_frames");
            // Walls drawn from the series' walls.pvd when it lists as many frames.
            std::vector<Entry> wall_frames;
            if (const auto w = fs::path(input).parent_path() / "walls.pvd"; fs::exists(w)) wall_frames = collection(w);
            if (wall_frames.size() != frames.size()) wall_frames.clear();
            fs::create_directories(folder);
            for (std::size_t k = 0; k < frames.size(); ++k) {
                char name[32], caption[64];
                std::snprintf(name, sizeof name, "frame_%04zu.png", k);
                std::snprintf(caption, sizeof caption, "t = %.4g s", frames[k].time);
                draw(read(frames[k].file), wall_frames.empty() ? fs::path() : wall_frames[k].file, {}, caption, folder / name);
            }
            auto quoted = [](const std::string& text) { return "'" + text + "'"; };
            const std::string encode = "ffmpeg -loglevel error -y -framerate " + std::to_string(frames_per_second) + " -i " +
                                       quoted((folder / "frame_%04d.png").string()) +
                                       " -c:v libx264 -pix_fmt yuv420p -vf 'pad=ceil(iw/2)*2:ceil(ih/2)*2' " + quoted(movie);
            if (installed("ffmpeg")) {
                if (std::system(encode.c_str()) != 0) fail("ffmpeg could not make " + movie + " from " + folder.string() + "; the frames stay there");
                fs::remove_all(folder);
                std::printf("render_snapshot: %s (%zu frames at %d per second, colour scale %g..%g J from %s)\n", movie.c_str(),
                            frames.size(), frames_per_second, range[0], range[1], scale_source.c_str());
            } else {
                std::printf("render_snapshot: %zu frames in %s (colour scale %g..%g J from %s); no ffmpeg (Debian's ffmpeg) to "
                            "make the movie: %s\n",
                            frames.size(), folder.string().c_str(), range[0], range[1], scale_source.c_str(), encode.c_str());
            }
            return 0;
        }
        const auto [above, below] = draw(particles, walls, contacts, "", output);
        char network[96] = "";
        if (!contacts.empty()) std::snprintf(network, sizeof network, "; force network: the widest tube %g N", largest_force);
        std::printf("render_snapshot: %s (%dx%d, %lld particles, colour scale %g..%g J%s from %s; %.1f%% of this frame above it, "
                    "%.1f%% below%s)%s%s\n",
                    output.c_str(), width, height, static_cast<long long>(particles->GetNumberOfPoints()), range[0], range[1],
                    log_scale ? ", logarithmic," : "", scale_source.c_str(), above, below, network, last_label.empty() ? "" : ": ",
                    last_label.c_str());
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "render_snapshot: %s\n", e.what());
        return 1;
    }
}
