// biaxial: the paper's biaxial test (Sec. 4) with one command.
//
//   biaxial --preset quick --out runs/quick        # under a minute on one core
//   biaxial --preset paper --out runs/paper        # N = 1950, T = 1 s, as in the paper
//   biaxial --dim 3 --preset quick --out runs/tri  # the same experiment as a triaxial box (N = 8000)
//
// Writes run.json (every parameter, derived figures, timing) and timeseries.csv (one row per
// output interval of the loading) into --out. Run with --help for every option and its unit.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>

#include <CLI/CLI.hpp>
#include <micromacro/io/checksum.hpp>
#include <micromacro/io/whole_file.hpp>
#include <nlohmann/json.hpp>

#include "../command_line.hpp"
#include "../installed.hpp"
#include "biaxial.hpp"
#include "cost.hpp"
#include "parameters.hpp"
#include "processes.hpp"
#include "quality.hpp"
#include "../run_folder.hpp"
#include "scene.hpp"
#ifdef MICROMACRO_HAVE_VTK
#include <micromacro/io/vtk.hpp>
#endif
#ifdef MICROMACRO_HAVE_MPI
#include "distributed_scene.hpp"
#ifdef MICROMACRO_HAVE_VTK
#include <micromacro/mpi/vtk_output.hpp>
#endif
#endif

namespace fs = std::filesystem;
using biaxial::Config;
using biaxial::config_from_json;

namespace {

/// Snapshots (like Fig. 3) of a few VTK frames, all on the colour scale of the whole series, with
/// the force network (in 3D a slab through the middle of the box, two mean diameters thick, seen
/// across y, so that the chains inside show), the plots of Fig. 4-5 and, with ffmpeg, a movie of
/// every frame: through the X display, or through Xvfb (xvfb-run) when there is none; without
/// either, the commands that make them later. `pieces` is the particles' and contacts' extension
/// (.vtp, or .pvtp for the pieces of a run over MPI ranks).
void make_pictures(const fs::path& out, std::size_t frames, int dim, double mean_radius, const std::string& pieces) {
    const fs::path render = micromacro::cli::sibling_program("render_snapshot"), plot = micromacro::cli::sibling_program("plot_timeseries");
    const std::string xvfb = "xvfb-run -a -s \"-screen 0 1280x1024x24\" ";
    std::vector<std::string> commands;
    char slice[64];
    std::snprintf(slice, sizeof slice, " --3d --slice y mid %.6g", 4.0 * mean_radius);
    if (!plot.empty())
        commands.push_back(plot.string() + " " + (out / "timeseries.csv").string() + " --out " + (out / "plots").string());
    if (!render.empty() && frames > 0) {
        std::vector<std::size_t> picked;
        for (std::size_t q = 0; q < 5; ++q) {
            const std::size_t f = q * (frames - 1) / 4;
            if (picked.empty() || picked.back() != f) picked.push_back(f);
        }
        for (const std::size_t f : picked) {
            const std::string k = std::to_string(f);
            commands.push_back(render.string() + " " + (out / "vtk" / ("particles_" + k + pieces)).string() + " --range-from " +
                               (out / "vtk" / "particles.pvd").string() + " --walls " + (out / "vtk" / ("walls_" + k + ".vtp")).string() +
                               " --contacts " + (out / "vtk" / ("contacts_" + k + pieces)).string() + (dim == 3 ? slice : "") +
                               " -o " + (out / "snapshots" / ("snapshot_" + k + ".png")).string());
        }
    }
    // A movie of every frame on the series' scale, where Debian's ffmpeg is installed to encode it.
    const bool has_ffmpeg = installed("ffmpeg");
    if (!render.empty() && frames > 1 && has_ffmpeg && !fs::exists(out / "movie.mp4"))
        commands.push_back(render.string() + " " + (out / "vtk" / "particles.pvd").string() + (dim == 3 ? " --3d" : "") + " --movie " +
                           (out / "movie.mp4").string());
    if (commands.empty()) return;
    const char* display = std::getenv("DISPLAY");
    const bool has_display = display && *display;
    const bool has_xvfb = !has_display && installed("xvfb-run");
    if (!has_display && !has_xvfb) {
        std::printf("no display and no xvfb-run (Debian's xvfb): make the snapshots and plots later with\n");
        for (const auto& c : commands) std::printf("  %s%s\n", xvfb.c_str(), c.c_str());
        return;
    }
    fs::create_directories(out / "snapshots");
    int failed = 0;
    for (const auto& c : commands) failed += std::system(((has_display ? "" : xvfb) + c + " > /dev/null").c_str()) != 0;
    const std::string movie = fs::exists(out / "movie.mp4") ? ", " + (out / "movie.mp4").string() : "";
    std::printf("pictures%s: %s/plots, %s/snapshots (one colour scale for all)%s%s\n", has_display ? "" : " (through Xvfb)",
                out.string().c_str(), out.string().c_str(), movie.c_str(), failed ? "; some failed: run the commands by hand to see why" : "");
}

/// What a run needs besides its configuration: where to start from and how often to save.
struct Plan {
    fs::path out;
    std::string from_prepared;     // a prepared.state to start the loading from
    bool resume = false;           // continue out/checkpoint.state
    double checkpoint_every = 0;   // simulated seconds between checkpoints (0: none)
    std::size_t stop_after_rows = 0;  // testing: die abruptly after this many rows, like a kill
    std::size_t vtk_every_rows = 20;  // a VTK frame every this many rows (0: none)
    bool pictures = true;             // snapshots and plots at the end (if a display is there)
    bool quiet = false;
    int threads = 1;                  // bitwise identical results for a fixed count
    std::string run_id;               // see new_run_id
};

/// The settings of a plan that shape a run's output, saved in its checkpoint and restored by --resume.
nlohmann::ordered_json plan_json(const Plan& p) {
    return {{"run_id", p.run_id}, {"from_prepared", p.from_prepared}, {"checkpoint_every_s", p.checkpoint_every},
            {"vtk_every_rows", p.vtk_every_rows}, {"threads", p.threads}};
}

void plan_from_json(const nlohmann::ordered_json& j, Plan& p) {
    p.run_id = j.at("run_id");
    p.from_prepared = j.at("from_prepared");
    p.checkpoint_every = j.at("checkpoint_every_s");
    p.vtk_every_rows = j.at("vtk_every_rows");
    p.threads = j.at("threads");
}

template <int dim, class Law>
int run(const Config& c, const Plan& plan) {
    const bool writer = biaxial::first_process();  // of the files every process would write alike
    const bool report = writer && !plan.quiet;      // progress: a line kept up to date on a terminal,
    const bool terminal = report && isatty(STDOUT_FILENO);  // else a new line every half minute
    const auto wall_start = std::chrono::steady_clock::now();
    const std::string started = micromacro::cli::now_iso();
    const fs::path& out = plan.out;
    biaxial::Experiment<dim, micromacro::VelocityVerlet, double, Law> exp(c);
    using Sim = std::remove_reference_t<decltype(exp.simulation())>;
    auto& sim = exp.simulation();  // the whole scene: built, loaded, or gathered from the ranks
    sim.set_threads(plan.threads);
#ifdef MICROMACRO_HAVE_MPI
    using Scene = biaxial::DistributedScene<Sim>;
    const auto start_scene = [&](std::optional<Scene>& s) { s.emplace(MPI_COMM_WORLD, sim, plan.threads); };
#else
    using Scene = biaxial::SerialScene<Sim>;
    const auto start_scene = [&](std::optional<Scene>& s) { s.emplace(sim); };
#endif
    std::optional<Scene> scene;  // what the phases step: sim itself, or sim split over the ranks
    const double n = static_cast<double>(c.particles);

    auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count(); };
    double last_print = -1.0;
    std::size_t steps_before = 0;  // steps done in an earlier process (resume)
    auto progress = [&](const char* phase, double fraction, double strain) {
        if (!report || elapsed() - last_print < (terminal ? 0.5 : 30.0)) return;
        last_print = elapsed();
        const double rate = (scene->steps_done() - steps_before) * n / std::max(elapsed(), 1e-9);
        char left[48] = "";  // the preparation's end is not known ahead
        if (fraction > 0) std::snprintf(left, sizeof left, "  ~%s left", biaxial::duration_text(elapsed() * (1.0 - fraction) / fraction).c_str());
        std::printf("%s%-9s strain %.4f  t = %.5f s  %.2e particle-steps/s%s%s", terminal ? "\r" : "", phase, strain, scene->time(),
                    rate, left, terminal ? "   " : "\n");
        std::fflush(stdout);
    };
    // VTK frames (where VTK was found at build time): particles, contacts and walls every
    // vtk_every_rows rows, each series with its .pvd collection. Over MPI ranks the particles and
    // contacts are pieces, one per rank, which a .pvtp summary joins (ParaView opens it as one).
    const std::string pieces = Scene::distributed ? ".pvtp" : ".vtp";
    std::vector<double> vtk_times;
    auto write_vtk = [&] {
#ifdef MICROMACRO_HAVE_VTK
        if (plan.vtk_every_rows == 0) return;
        const fs::path dir = out / "vtk";
        biaxial::on_first([&] { fs::create_directories(dir); });
        const std::string k = std::to_string(vtk_times.size());
        const auto snapshot = scene->snapshot();
        const std::vector<std::pair<std::string, double>> values = {{"eps_zz", exp.eps_zz(scene->walls())}};
#ifdef MICROMACRO_HAVE_MPI
        micromacro::mpi::write_particles(scene->distributed_run(), dir / ("particles_" + k + pieces), values);
        micromacro::mpi::write_contacts(scene->distributed_run(), dir / ("contacts_" + k + pieces));
#else
        auto frame = micromacro::io::particle_frame(sim);
        frame.values = values;
        micromacro::io::write_particles(frame, dir / ("particles_" + k + pieces));
        micromacro::io::write_contacts(snapshot, dir / ("contacts_" + k + pieces));
#endif
        vtk_times.push_back(scene->time() - exp.load_start());
        biaxial::on_first([&] {
            micromacro::io::write_walls(snapshot, dir / ("walls_" + k + ".vtp"));
            for (const std::string series : {"particles", "contacts", "walls"}) {
                micromacro::io::PvdCollection pvd(dir / (series + ".pvd"));
                const std::string extension = series == "walls" ? ".vtp" : pieces;
                for (std::size_t f = 0; f < vtk_times.size(); ++f) pvd.add(vtk_times[f], series + "_" + std::to_string(f) + extension);
                pvd.write();
            }
        });
#endif
    };
    auto settings = [&](std::size_t rows, std::uintmax_t csv_bytes) {
        nlohmann::ordered_json j;
        j["program"] = "biaxial";  // so that element_test's --from-prepared can name it
        j["parameters"] = biaxial::parameters_json(c);
        j["plan"] = plan_json(plan);
        j["bookkeeping"] = exp.bookkeeping();
        j["rows"] = rows;
        j["csv_bytes"] = csv_bytes;
        // The time series as the checkpoint saw it, which a resumed run continues only if unchanged.
        j["csv_checksum"] = csv_bytes ? micromacro::io::checksum_of_file(out / "timeseries.csv.partial", csv_bytes) : 0;
        j["vtk_times"] = vtk_times;
        return j.dump();
    };

    const fs::path partial = out / "timeseries.csv.partial";
    std::size_t rows_done = 0;
    double prepare_seconds = 0.0;
    std::size_t prepare_steps = 0;
    std::ofstream csv;  // the first process's
    if (plan.resume) {
        const nlohmann::ordered_json saved = nlohmann::ordered_json::parse(micromacro::io::load_state(sim, out / "checkpoint.state", "checkpoint"));
        exp.restore_bookkeeping(saved.at("bookkeeping").get<std::vector<double>>());
        rows_done = saved.at("rows");
        vtk_times = saved.at("vtk_times").get<std::vector<double>>();
        steps_before = sim.steps_done();
        biaxial::on_first([&] {
            if (!fs::exists(partial) || fs::file_size(partial) < saved.at("csv_bytes").get<std::uintmax_t>())
                micromacro::throw_input_error(partial.string(), " is missing or shorter than the checkpoint says; cannot resume");
            if (const std::string series = micromacro::cli::run_id_of_series(partial); series != plan.run_id)
                micromacro::throw_input_error(partial.string(), " belongs to run '", series, "', the checkpoint to run '",
                                              plan.run_id, "'; the folder mixes two runs and cannot resume");
            const auto csv_bytes = saved.at("csv_bytes").get<std::uintmax_t>();
            if (!saved.contains("csv_checksum"))
                micromacro::throw_input_error(out.string(), "/checkpoint.state has no checksum of the time series (an older ",
                                              "biaxial wrote it); cannot resume");
            if (micromacro::io::checksum_of_file(partial, csv_bytes) != saved.at("csv_checksum").get<std::uint64_t>())
                micromacro::throw_input_error(partial.string(), " is not what the checkpoint saved: its first ", csv_bytes,
                                              " bytes were changed after the checkpoint; the run cannot resume from it (",
                                              "start it again, or restore the file)");
            fs::resize_file(partial, csv_bytes);  // drop rows written after the checkpoint
            csv.open(partial, std::ios::app);
        });
        start_scene(scene);
    } else {
        if (plan.from_prepared.empty()) {
            exp.build();
            start_scene(scene);
            exp.prepare(*scene, [&] { progress("prepare", 0.0, 0.0); });
            Sim& prepared = scene->whole();
            biaxial::on_first([&] { micromacro::io::save_state(prepared, out / "prepared.state", settings(0, 0), "prepared"); });
        } else {
            const nlohmann::ordered_json saved = nlohmann::ordered_json::parse(micromacro::io::load_state(sim, plan.from_prepared, "prepared"));
            if (saved.at("parameters").at("particles").get<std::size_t>() != c.particles)
                micromacro::throw_input_error(plan.from_prepared, " holds ",
                                                      saved.at("parameters").at("particles").get<std::size_t>(),
                                                      " particles, this run asks for ", c.particles, "; drop --particles");
            steps_before = sim.steps_done();
        }
        prepare_seconds = elapsed();
        prepare_steps = sim.steps_done();
        exp.start_loading();  // on the whole scene, which the phases continue from
        if (scene)
            scene->continue_from(sim);
        else
            start_scene(scene);
        biaxial::on_first([&] { csv.open(partial, std::ios::trunc); });
    }
    biaxial::on_first([&] {
        if (!csv) micromacro::throw_input_error("cannot write ", partial.string());
    });

    // Loading: one row per output interval, into a partial file renamed at the end.
    auto write_row = [&] {
        const auto r = exp.row(*scene);
        if (writer) {
            if (rows_done == 0) {
                csv << "# run " << plan.run_id << "\n";
                csv << "# units: time s, strains 1, walls m, stresses " << (dim == 2 ? "N/m" : "Pa") << ", stiffness "
                    << (dim == 2 ? "N/m" : "Pa") << ", fabric 1, energies J, phi_F rad\n";
                for (std::size_t i = 0; i < r.names.size(); ++i) csv << (i ? "," : "") << r.names[i];
                csv << "\n";
            }
            for (std::size_t i = 0; i < r.values.size(); ++i) csv << (i ? "," : "") << micromacro::cli::csv_number(r.values[i]);
            csv << "\n";
        }
        if (plan.vtk_every_rows && rows_done % plan.vtk_every_rows == 0) write_vtk();
        ++rows_done;
    };
    const double dt = sim.time_step();
    const auto steps_per_row = exp.steps_per_row();
    const auto total_rows = exp.loading_rows();
    if (rows_done == 0) write_row();
    double last_checkpoint = scene->time();
    while (rows_done < total_rows) {
        scene->run(steps_per_row);
        write_row();
        progress("load", double(rows_done) / total_rows, exp.eps_zz(scene->walls()));
        if (plan.checkpoint_every > 0 && scene->time() - last_checkpoint >= plan.checkpoint_every - 0.5 * dt) {
            Sim& now = scene->whole();
            biaxial::on_first([&] {
                csv.flush();
                micromacro::io::save_state(now, out / "checkpoint.state", settings(rows_done, fs::file_size(partial)), "checkpoint");
            });
            last_checkpoint = scene->time();
        }
        if (plan.stop_after_rows && rows_done >= plan.stop_after_rows) {
            if (writer) csv.flush();
            std::_Exit(3);  // no clean-up, as if killed
        }
    }
    biaxial::on_first([&] {
        csv.close();
        if (!csv) micromacro::throw_input_error("cannot finish ", partial.string());
        fs::rename(partial, out / "timeseries.csv");
    });
    const double final_eps_zz = exp.eps_zz(scene->walls());
    const std::size_t steps = scene->steps_done();
    if (!writer) return 0;

    const double seconds = elapsed();
    const double pps = (steps - steps_before) * n / seconds;
    const double tc = c.contact_duration();
    // Inertial number I = (d eps/dt) d sqrt(rho / p) at the peak rate of Eq. 17, eps_f pi / T, with
    // the mean diameter d; in 2D rho is the sphere mass per disk area, 4/3 rho a.
    const double peak_rate = c.final_strain * M_PI / c.period;
    const double inertial = c.inertial_number();
    // Drag of the background damping on the column moved by the top wall, against the side
    // pressure times the box side: the mean particle moves at half the top wall's peak speed.
    const auto box = exp.reference_box();
    const double peak_wall_speed = peak_rate * box[dim - 1];
    double side = 1.0;
    for (int k = 0; k < dim - 1; ++k) side *= box[k];
    // Affine and local damping put no drag on the mean flow.
    const double background_drag = c.damping == "lab" ? c.gamma_b * n * 0.5 * peak_wall_speed / (c.pressure * side) : 0.0;
    nlohmann::ordered_json j;
    j["program"] = "micromacro biaxial";
    j["version"] = "0.1.0";
    j["run_id"] = plan.run_id;
    j["parameters"] = biaxial::parameters_json(c);
    j["derived"] = {{"contact_duration_s", tc},
                    {"time_step_s", sim.time_step()},
                    {"stable_time_step_s", sim.stable_time_step()},
                    {"restitution", c.restitution_coefficient()},
                    {"reference_overlap_m", c.reference_overlap()},
                    {"peak_strain_rate_1_s", peak_rate},
                    {"inertial_number_at_peak_rate", inertial},
                    {"background_drag_over_pL_at_peak_rate", background_drag},
                    {"wall_oscillation_time_s", 2.0 * M_PI * std::sqrt(c.wall_mass / c.contact_springs().normal_stiffness)},
                    {"wall_damping_time_s", c.wall_damping > 0 ? 2.0 * c.wall_mass / c.wall_damping : 0.0},
                    {"box_after_preparation_m", box},
                    {"final_eps_zz", final_eps_zz}};
    const auto q = biaxial::loading_quality(biaxial::read_timeseries((out / "timeseries.csv").string()), dim, c.pressure,
                                            c.final_strain);
    // Figures that cannot be taken (too few rows) are NaN, which nlohmann::json writes as null.
    j["quality"] = {{"roughness_sigma_zz", q.roughness_sigma_zz},
                    {"roughness_sigma_wall_zz", q.roughness_sigma_wall_zz},
                    {"fixed_side_wall_mean", q.fixed_side_wall},
                    {"controlled_side_wall_mean", q.controlled_side_wall},
                    {"controlled_side_wall_rms_deviation_over_p", q.controlled_rms_deviation},
                    {"inner_minus_wall_stress_over_wall_stress_median", q.inner_over_wall},
                    {"inner_minus_wall_stress_over_wall_stress_at_rest", q.inner_over_wall_at_rest},
                    {"damping_energy_over_wall_work", q.damping_over_wall_work}};
    j["timing"] = {{"started", started},
                   {"finished", micromacro::cli::now_iso()},
                   {"resumed", plan.resume},
                   {"from_prepared", plan.from_prepared},
                   {"wall_seconds", seconds},
                   {"prepare_wall_seconds", prepare_seconds},
                   {"steps", steps},
                   {"prepare_steps", prepare_steps},
                   {"particle_steps_per_second", pps},
                   {"threads", plan.threads},
                   {"ranks", biaxial::process_count()}};
    micromacro::io::write_whole_file(out / "run.json", j.dump(2) + "\n");
    // The run is complete: its checkpoint would only let a later run in this folder resume into it.
    fs::remove(out / "checkpoint.state");
    if (terminal) std::printf("\n");
    if (plan.pictures) make_pictures(out, vtk_times.size(), dim, c.mean_radius(), pieces);
    std::printf("biaxial %dD: %zu particles, %zu steps in %.1f s (%.3g particle-steps/s); results in %s\n", dim,
                c.particles, steps - steps_before, seconds, pps, out.string().c_str());
    return 0;
}

/// Everything but the first process writes its standard output (the help, the progress, the
/// summary: the same on each) to /dev/null, and its standard error too until the run starts (the
/// command line's messages: the same on each); `speak` gives the latter back.
struct QuietOthers {
    int saved_error = -1;
    QuietOthers() {
        if (biaxial::first_process()) return;
        saved_error = dup(STDERR_FILENO);
        if (!std::freopen("/dev/null", "w", stdout) || !std::freopen("/dev/null", "w", stderr)) saved_error = -1;
    }
    void speak() {
        if (saved_error < 0) return;
        std::fflush(stderr);
        dup2(saved_error, STDERR_FILENO);
        close(saved_error);
        saved_error = -1;
    }
};

/// What the run will cost (memory, the loading's time, the VTK frames' space), said before it
/// starts; with --quiet only for a large run (a gigabyte of memory or frames, an hour of loading).
void tell_cost(const Config& c, const biaxial::Cost& cost, const Plan& plan) {
    if (!biaxial::first_process()) return;
    if (plan.quiet && !biaxial::is_large(cost)) return;
    std::printf("%s\n", biaxial::describe_cost(c, cost, plan.threads).c_str());
    std::fflush(stdout);
}

/// The run in the configuration's dimension and with its contact law.
int run(const Config& c, const Plan& plan) {
    if (c.hertz()) return c.dim == 2 ? run<2, micromacro::HertzMindlin>(c, plan) : run<3, micromacro::HertzMindlin>(c, plan);
    return c.dim == 2 ? run<2, micromacro::FrictionalLinear>(c, plan) : run<3, micromacro::FrictionalLinear>(c, plan);
}

/// The run, and what stops it told once. Over MPI ranks a refused input or file (InputError)
/// stops every rank alike (the files are checked on the first, which tells the others), and the
/// first tells it; anything else may have stopped one rank alone, which tells it with its rank and
/// aborts the others, which would wait for it.
int run_scene(const Config& c, const Plan& plan, QuietOthers& others) {
    others.speak();
    const int ranks = biaxial::process_count();
    try {
        return run(c, plan);
    } catch (const micromacro::InputError& e) {
        if (biaxial::first_process()) {
            std::fprintf(stderr, "biaxial: %s\n", e.what());
            micromacro::cli::discard_unresumable_series(plan.out);
        }
        return 1;
    } catch (const std::exception& e) {
        if (ranks == 1) {
            std::fprintf(stderr, "biaxial: %s\n", e.what());
            micromacro::cli::discard_unresumable_series(plan.out);
            return 1;
        }
        std::fprintf(stderr, "biaxial (rank %d of %d): %s\n", biaxial::process_rank(), ranks, e.what());
#ifdef MICROMACRO_HAVE_MPI
        MPI_Abort(MPI_COMM_WORLD, 1);
#endif
        return 1;
    }
}

}  // namespace

int main(int argc, char** argv) {
#ifdef MICROMACRO_HAVE_MPI
    const micromacro::mpi::Runtime mpi(argc, argv);  // biaxial_mpi, under mpirun
#endif
    QuietOthers others;
    Config c;
    std::string preset = "quick", out;
    bool quiet = false;
    CLI::App app{"The paper's biaxial test: preparation, strain-controlled loading (Eq. 17) against a "
                 "stress-controlled side wall (Eq. 18), relaxation; averages in the inner box."};
    app.add_option("--dim", c.dim, "2 (biaxial) or 3 (triaxial box)")->capture_default_str();
    app.add_option("--preset", preset, "paper (N = 1950, in 3D 12 500; T = 1 s) or quick (N = 300, in 3D 8000; T = 0.1 s)")->capture_default_str();
    Plan plan;
    std::string resume;
    auto* out_option = app.add_option("--out", out, "output directory (created); one that holds an earlier run is refused");
    bool overwrite = false;
    app.add_flag("--overwrite", overwrite, "replace the earlier run in --out (its files only)");
    app.add_option("--from-prepared", plan.from_prepared, "start the loading from a prepared.state of an earlier run")
        ->check(CLI::ExistingFile);
    app.add_option("--checkpoint-every", plan.checkpoint_every,
                   "write DIR/checkpoint.state every this many simulated seconds of the loading (0: never)")
        ->capture_default_str();
    app.add_option("--threads", plan.threads, "threads (OpenMP); the same count gives the same bits")->capture_default_str();
    auto* vtk_every = app.add_option("--vtk-every", plan.vtk_every_rows, "write VTK frames (vtk/*.vtp, *.pvd) every this many rows (0: none)")
        ->capture_default_str();
    app.add_option("--stop-after-rows", plan.stop_after_rows, "testing restarts: die after this many rows, as a kill would")
        ->group("");  // hidden
    app.add_option("--resume", resume, "continue the killed run in this directory from its checkpoint.state")
        ->excludes(out_option)
        ->check(CLI::ExistingDirectory);
    // Options that override the preset: collected first, applied after it.
    const std::vector<CLI::Option*> given = micromacro::cli::add_options(app, biaxial::parameter_table());
    bool no_pictures = false;
    app.add_flag("--no-pictures", no_pictures, "skip the snapshots and plots at the end");
    app.add_flag("--quiet", quiet, "no progress line, only the final summary");
    MICROMACRO_PARSE_COMMAND_LINE(app, argc, argv);

    micromacro::cli::FolderLock folder_lock;  // the output folder's, held until the program ends
    try {
        if (out.empty() && resume.empty()) micromacro::throw_input_error("give --out DIR (or --resume DIR)");
        plan.quiet = quiet;
        plan.pictures = !no_pictures;
#ifndef MICROMACRO_HAVE_VTK  // a build without VTK writes no frames, and says so when asked for them
        if (resume.empty() && vtk_every->count() && plan.vtk_every_rows > 0)  // (with --resume: refused below as any option)
            micromacro::throw_input_error("--vtk-every ", plan.vtk_every_rows, " asks for VTK frames, but this biaxial was "
                                                  "built without VTK (install libvtk9-dev and build again); use --vtk-every 0");
        if (resume.empty()) plan.vtk_every_rows = 0;
#else
        (void)vtk_every;
#endif
        if (!resume.empty()) {  // everything comes from the checkpoint
            // Any setting given now would be ignored or would change the run half-way: refused.
            for (const CLI::Option* o : app.get_options())
                if (o->count() && o->get_name() != "--resume" && o->get_name() != "--quiet" && o->get_name() != "--no-pictures")
                    micromacro::throw_input_error(o->get_name(), " cannot be given with --resume: a resumed run keeps every "
                                                          "setting of the run it continues (saved in its checkpoint); drop ",
                                                          o->get_name());
            plan.out = resume;
            plan.resume = true;
            biaxial::on_first([&] { folder_lock.take(plan.out, "--resume", "biaxial"); });
            const fs::path checkpoint = plan.out / "checkpoint.state";
            if (!fs::exists(checkpoint))
                micromacro::throw_input_error(checkpoint.string(), " does not exist; was the run started with "
                                                      "--checkpoint-every, or did it complete?");
            // The settings are the text saved with the state (they say which dimension to restore).
            const auto saved = nlohmann::ordered_json::parse(micromacro::io::state_text(checkpoint, "checkpoint"));
            if (!saved.contains("plan"))
                micromacro::throw_input_error(checkpoint.string(), " has no run id (an older biaxial wrote it); cannot resume");
            c = config_from_json(saved, c);
            plan_from_json(saved.at("plan"), plan);
            tell_cost(c, biaxial::estimate_cost(c, plan.vtk_every_rows, plan.threads), plan);
            return run_scene(c, plan, others);
        }
        biaxial::apply_preset(c, preset);
        micromacro::cli::apply_options(biaxial::parameter_table(), given, c);
        // Eq. 30's weak damping unless --gamma-b says otherwise: strong lab damping drags the flow.
        if (c.damping == "lab" && !app.get_option("--gamma-b")->count()) c.gamma_b = 1e-4;
        if (!plan.from_prepared.empty()) {
            // The packing, and so everything that made it, comes from the prepared state: options
            // of the preparation would be recorded in run.json without having acted.
            for (const std::string& name : micromacro::cli::preparation_options_given(biaxial::parameter_table(), given))
                micromacro::throw_input_error(name, " cannot be given with --from-prepared: the prepared state "
                                                    "holds the packing it made (run.json records its value); drop ", name);
            const auto prepared = config_from_json(
                nlohmann::ordered_json::parse(micromacro::io::state_text(plan.from_prepared, "prepared")), c);
            if (prepared.dim != c.dim)
                micromacro::throw_input_error(plan.from_prepared, " holds a different scene (dim=", prepared.dim,
                                                      "), this run asks for --dim ", c.dim);
            micromacro::cli::take_preparation(biaxial::parameter_table(), prepared, c);
        }
        for (const std::string& name : biaxial::options_of_other_law(given, c))
            micromacro::throw_input_error(name, " does not apply to --law ", c.law,
                                          c.hertz() ? " (Mindlin's k_t follows from --young and --poisson)"
                                                    : " (it sets Hertz-Mindlin's material; add --law hertz-mindlin)",
                                          "; drop ", name);
        biaxial::validate(c);
        micromacro::require_non_negative(plan.checkpoint_every, "--checkpoint-every", "give simulated seconds, 0 for none");
        micromacro::check_thread_count(plan.threads);  // before the output folder is made
        const auto cost = biaxial::estimate_cost(c, plan.vtk_every_rows, plan.threads);
        biaxial::on_first([&] { biaxial::refuse_unaffordable(c, cost, plan.vtk_every_rows, out); });
        biaxial::on_first([&] { micromacro::cli::claim_output_folder(out, overwrite, plan.from_prepared, folder_lock, "biaxial"); });
        plan.out = out;
        plan.run_id = biaxial::as_on_first(biaxial::first_process() ? micromacro::cli::new_run_id() : "");
        tell_cost(c, cost, plan);
        return run_scene(c, plan, others);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "biaxial: %s\n", e.what());
        return 1;
    }
}
