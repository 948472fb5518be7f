// element_test: element tests in a deforming periodic cell, 2D and 3D, with one command.
//
//   element_test --preset shear-p --out runs/shear          # simple shear to 1 at constant p (400 disks)
//   element_test --dim 3 --preset triaxial --out runs/tri   # the triaxial test without walls
//   element_test --preset probes --from-prepared runs/shear/prepared.state --out runs/probes
//
// A run prepares a packing (a fresh gas, or a CSV or LAMMPS packing file) by compressing it
// isotropically to p until it rests, saves it as prepared.state, and drives the cell along the
// preset's path, writing run.json and timeseries.csv (the biaxial program's column names where
// they mean the same), VTK frames with the cell drawn, and plots and snapshots. The probes preset
// writes probes.csv instead of a time series. Run with --help for every option and its unit.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>
#include <micromacro/io/checksum.hpp>
#include <micromacro/io/state.hpp>
#include <micromacro/io/whole_file.hpp>
#include <nlohmann/json.hpp>

#include "../command_line.hpp"
#include "../installed.hpp"
#include "../output_paths.hpp"
#include "../run_folder.hpp"
#include "../standard_output.hpp"
#include "config.hpp"
#include "experiment.hpp"
#include "probes.hpp"
#ifdef MICROMACRO_HAVE_VTK
#include <micromacro/io/vtk.hpp>
#endif

namespace fs = std::filesystem;
using namespace element_test;
using micromacro::cli::csv_number;

namespace {

/// What a run needs besides its configuration: where it starts from and what it writes.
struct Plan {
    fs::path out;
    std::string from_prepared;        // a prepared.state to start the loading from
    std::string packing;              // a CSV or LAMMPS packing file to prepare from
    std::vector<double> box;          // the packing file's cell (lo hi per axis), if the file has none
    bool resume = false;              // continue out/checkpoint.state
    double checkpoint_every = 0;      // simulated seconds between checkpoints (0: none)
    std::size_t stop_after_rows = 0;  // testing: die abruptly after this many rows, like a kill
    std::size_t vtk_every_rows = 20;  // a VTK frame every this many rows (0: none)
    bool pictures = true;
    bool quiet = false;
    int threads = 1;
    std::string run_id;
};

nlohmann::ordered_json plan_json(const Plan& p) {
    return {{"run_id", p.run_id},         {"from_prepared", p.from_prepared},   {"packing", p.packing},
            {"checkpoint_every_s", p.checkpoint_every}, {"vtk_every_rows", p.vtk_every_rows}, {"threads", p.threads}};
}

void plan_from_json(const nlohmann::ordered_json& j, Plan& p) {
    p.run_id = j.at("run_id");
    p.from_prepared = j.at("from_prepared");
    p.packing = j.at("packing");
    p.checkpoint_every = j.at("checkpoint_every_s");
    p.vtk_every_rows = j.at("vtk_every_rows");
    p.threads = j.at("threads");
}

/// The parameters a prepared.state of element_test was made with; another program's state (biaxial's
/// prepared.state, say) is refused by name, since its packing was made for other conditions.
Config prepared_config(const std::string& path) {
    const auto saved = nlohmann::ordered_json::parse(mm::io::state_text(path, "prepared"));
    const std::string program = saved.value("program", "");
    const auto refuse = [&](const std::string& what) {
        mm::throw_input_error("--from-prepared ", path, " is ", what, ", not a prepared.state of element_test; start from a packing file "
                              "with --packing (CSV or LAMMPS dump), or from a prepared.state an element_test run wrote");
    };
    if (!program.empty() && program != "element_test") refuse("a state of " + program);
    try {
        return config_from_json(saved);
    } catch (const nlohmann::json::exception&) {
        refuse("a state of another program (its parameters lack element_test's)");
    }
    return {};
}

/// Plots of the time series and snapshots of the first and last frames, through the X display or
/// Xvfb; without either, the commands that make them later.
void make_pictures(const fs::path& out, std::size_t frames, int dim, double mean_radius) {
    const fs::path render = micromacro::cli::sibling_program("render_snapshot"), plot = micromacro::cli::sibling_program("plot_timeseries");
    const std::string xvfb = "xvfb-run -a -s \"-screen 0 1280x1024x24\" ";
    std::vector<std::string> commands;
    if (!plot.empty() && fs::exists(out / "timeseries.csv"))
        commands.push_back(plot.string() + " " + (out / "timeseries.csv").string() + " --out " + (out / "plots").string());
    char slice[64];
    std::snprintf(slice, sizeof slice, " --3d --slice y mid %.6g", 4.0 * mean_radius);
    std::vector<std::size_t> picked;  // the first frame and the last, on the series' colour scale
    if (frames > 0) picked.push_back(0);
    if (frames > 1) picked.push_back(frames - 1);
    for (const std::size_t f : render.empty() ? std::vector<std::size_t>{} : picked) {
        const std::string k = std::to_string(f);
        commands.push_back(render.string() + " " + (out / "vtk" / ("particles_" + k + ".vtp")).string() + " --range-from " +
                           (out / "vtk" / "particles.pvd").string() + " --contacts " + (out / "vtk" / ("contacts_" + k + ".vtp")).string() +
                           (dim == 3 ? slice : "") + " -o " + (out / "snapshots" / ("snapshot_" + k + ".png")).string());
    }
    if (commands.empty()) return;
    const char* display = std::getenv("DISPLAY");
    const bool has_display = display && *display;
    if (!has_display && !installed("xvfb-run")) {
        std::printf("no display and no xvfb-run (Debian's xvfb): make the plots and snapshots later with\n");
        for (const auto& c : commands) std::printf("  %s%s\n", xvfb.c_str(), c.c_str());
        return;
    }
    fs::create_directories(out / "snapshots");
    int failed = 0;
    for (const auto& c : commands) failed += std::system(((has_display ? "" : xvfb) + c + " > /dev/null").c_str()) != 0;
    std::printf("pictures: %s/plots, %s/snapshots%s\n", out.string().c_str(), out.string().c_str(),
                failed ? "; some failed: run the commands by hand to see why" : "");
}

template <int dim>
void write_probes(const std::vector<ProbeResult<dim>>& probes, const fs::path& path, const std::string& run_id) {
    micromacro::io::write_whole_file(path, std::ios::out, [&](std::ofstream& f) {
        f << "# run " << run_id << "\n# units: strains 1, stress changes " << (dim == 2 ? "N/m" : "Pa")
          << "; modulus_X = (dsigma_X : eps) / (eps : eps)\ndirection";
        const char* methods[] = {"cell", "relaxed", "affine", "predicted"};
        for (int a = 0; a < dim; ++a)
            for (int b = a; b < dim; ++b) f << ",eps_" << idx({a, b});
        for (const char* m : methods)
            for (int a = 0; a < dim; ++a)
                for (int b = a; b < dim; ++b) f << ",dsigma_" << m << "_" << idx({a, b});
        for (const char* m : methods) f << ",modulus_" << m;
        f << ",relaxation_steps\n";
        for (const auto& p : probes) {
            f << p.name;
            for (int a = 0; a < dim; ++a)
                for (int b = a; b < dim; ++b) f << "," << csv_number(p.eps(a, b));
            const mm::Tensor2<dim>* changes[] = {&p.cell, &p.relaxed, &p.affine, &p.predicted};
            for (const auto* d : changes)
                for (int a = 0; a < dim; ++a)
                    for (int b = a; b < dim; ++b) f << "," << csv_number((*d)(a, b));
            for (const auto* d : changes) f << "," << csv_number(d->cwiseProduct(p.eps).sum() / p.eps.squaredNorm());
            f << "," << p.relaxation_steps << "\n";
        }
    });
}

template <int dim>
int run(const Config& c, const Plan& plan) {
    const bool report = !plan.quiet, terminal = report && isatty(STDOUT_FILENO);
    const auto wall_start = std::chrono::steady_clock::now();
    const std::string started = micromacro::cli::now_iso();
    const fs::path& out = plan.out;
    auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count(); };

    Packing<dim> packing;  // empty for a run from a saved state
    if (!plan.resume && plan.from_prepared.empty()) {
        if (plan.packing.empty()) {
            packing = random_gas<dim>(c);
        } else {
            const auto file = mm::io::read_packing<dim>(plan.packing, mm::io::guess_format(plan.packing));
            packing.cell = mm::io::packing_domain(file, plan.box, dim == 2 ? "x,z" : "x,y,z");
            packing.position = file.position;
            packing.radius = file.radius;
            for (auto& x : packing.position) packing.cell.wrap(x);
        }
    }
    Experiment<dim> exp(c, packing);
    auto& sim = exp.simulation();
    sim.set_threads(plan.threads);
    double last_print = -1.0;
    std::size_t steps_before = 0;
    auto progress = [&](const char* phase, double strain, double pressure) {
        if (!report || elapsed() - last_print < (terminal ? 0.5 : 30.0)) return;
        last_print = elapsed();
        const double rate = double(sim.steps_done() - steps_before) * double(sim.particles().size()) / std::max(elapsed(), 1e-9);
        std::printf("%s%-9s strain %.4f  p = %.4g  t = %.5f s  %.2e particle-steps/s%s", terminal ? "\r" : "", phase, strain, pressure,
                    sim.time(), rate, terminal ? "   " : "\n");
        std::fflush(stdout);
    };

    std::vector<double> vtk_times;
    auto write_vtk = [&] {
#ifdef MICROMACRO_HAVE_VTK
        if (plan.vtk_every_rows == 0) return;
        const fs::path dir = out / "vtk";
        fs::create_directories(dir);
        const std::string k = std::to_string(vtk_times.size());
        auto frame = mm::io::particle_frame(sim);
        frame.values = {{"loading_strain", exp.loading_strain()}};
        mm::io::write_particles(frame, dir / ("particles_" + k + ".vtp"));
        mm::io::write_contacts(mm::take_snapshot(sim), dir / ("contacts_" + k + ".vtp"));
        mm::io::write_cell(sim.domain(), dir / ("cell_" + k + ".vtp"));
        vtk_times.push_back(sim.time() - exp.load_start());
        for (const std::string series : {"particles", "contacts", "cell"}) {
            mm::io::PvdCollection pvd(dir / (series + ".pvd"));
            for (std::size_t f = 0; f < vtk_times.size(); ++f) pvd.add(vtk_times[f], series + "_" + std::to_string(f) + ".vtp");
            pvd.write();
        }
#endif
    };
    const fs::path partial = out / "timeseries.csv.partial";
    auto settings = [&](std::size_t rows, std::uintmax_t csv_bytes) {
        nlohmann::ordered_json j;
        j["program"] = "element_test";  // --from-prepared refuses another program's state by this
        j["parameters"] = parameters_json(c);
        j["plan"] = plan_json(plan);
        j["bookkeeping"] = exp.bookkeeping();
        j["rows"] = rows;
        j["csv_bytes"] = csv_bytes;
        j["csv_checksum"] = csv_bytes ? mm::io::checksum_of_file(partial, csv_bytes) : 0;
        j["vtk_times"] = vtk_times;
        return j.dump();
    };

    std::size_t rows_done = 0;
    double prepare_seconds = 0.0;
    std::ofstream csv;
    if (plan.resume) {
        const nlohmann::ordered_json saved = nlohmann::ordered_json::parse(mm::io::load_state(sim, out / "checkpoint.state", "checkpoint"));
        exp.restore_bookkeeping(saved.at("bookkeeping"));
        rows_done = saved.at("rows");
        vtk_times = saved.at("vtk_times").get<std::vector<double>>();
        steps_before = sim.steps_done();
        const auto csv_bytes = saved.at("csv_bytes").get<std::uintmax_t>();
        if (!fs::exists(partial) || fs::file_size(partial) < csv_bytes)
            mm::throw_input_error(partial.string(), " is missing or shorter than the checkpoint says; cannot resume");
        if (const std::string series = micromacro::cli::run_id_of_series(partial); series != plan.run_id)
            mm::throw_input_error(partial.string(), " belongs to run '", series, "', the checkpoint to run '", plan.run_id,
                                  "'; the folder mixes two runs and cannot resume");
        if (mm::io::checksum_of_file(partial, csv_bytes) != saved.at("csv_checksum").get<std::uint64_t>())
            mm::throw_input_error(partial.string(), " is not what the checkpoint saved: its first ", csv_bytes,
                                  " bytes were changed after the checkpoint; start the run again, or restore the file");
        fs::resize_file(partial, csv_bytes);  // drop rows written after the checkpoint
        csv.open(partial, std::ios::app);
    } else {
        if (plan.from_prepared.empty()) {
            exp.prepare([&](const mm::MicroMacro<dim>& m) { progress("prepare", 0.0, m.pressure); });
            mm::io::save_state(sim, out / "prepared.state", settings(0, 0), "prepared");
        } else {
            // main() has checked that it is element_test's state of this dimension.
            (void)mm::io::load_state(sim, plan.from_prepared, "prepared");
            steps_before = sim.steps_done();
        }
        prepare_seconds = elapsed();
        exp.start_loading();
        if (c.preset != "probes") csv.open(partial, std::ios::trunc);
    }
    if (c.preset != "probes" && !csv) mm::throw_input_error("cannot write ", partial.string());

    nlohmann::ordered_json results;
    if (c.preset == "probes") {
        write_vtk();
        const auto probes = run_probes(exp);
        write_probes(probes, out / "probes.csv", plan.run_id);
        for (const auto& p : probes) {
            const double cell = p.cell.cwiseProduct(p.eps).sum(), predicted = p.predicted.cwiseProduct(p.eps).sum();
            results["modulus_ratio_cell_over_predicted"][p.name] = cell / predicted;
            if (report) std::printf("probe %-11s modulus (cell, relaxed, affine, predicted): %.5g %.5g %.5g %.5g\n", p.name.c_str(),
                                    cell / p.eps.squaredNorm(), p.relaxed.cwiseProduct(p.eps).sum() / p.eps.squaredNorm(),
                                    p.affine.cwiseProduct(p.eps).sum() / p.eps.squaredNorm(), predicted / p.eps.squaredNorm());
        }
    } else {
        double row_pressure = 0.0;  // the latest row's, for the progress line
        auto write_row = [&] {
            const Row r = exp.row();
            for (std::size_t i = 0; i < r.names.size(); ++i)
                if (r.names[i] == "pressure") row_pressure = r.values[i];
            if (rows_done == 0) {
                csv << "# run " << plan.run_id << "\n";
                csv << "# units: time s, strains 1, rates 1/s, stresses and stiffness " << (dim == 2 ? "N/m" : "Pa")
                    << ", fabric 1, energies J, phi_F rad; preset " << c.preset << "\n";
                for (std::size_t i = 0; i < r.names.size(); ++i) csv << (i ? "," : "") << r.names[i];
                csv << "\n";
            }
            for (std::size_t i = 0; i < r.values.size(); ++i) csv << (i ? "," : "") << csv_number(r.values[i]);
            csv << "\n";
            if (plan.vtk_every_rows && rows_done % plan.vtk_every_rows == 0) write_vtk();
            ++rows_done;
        };
        const double dt = sim.time_step();
        if (rows_done == 0) write_row();
        double last_checkpoint = sim.time();
        while (!exp.done()) {
            exp.run(exp.steps_per_row());
            write_row();
            progress("load", exp.loading_strain(), row_pressure);
            if (plan.checkpoint_every > 0 && sim.time() - last_checkpoint >= plan.checkpoint_every - 0.5 * dt) {
                csv.flush();
                mm::io::save_state(sim, out / "checkpoint.state", settings(rows_done, fs::file_size(partial)), "checkpoint");
                last_checkpoint = sim.time();
            }
            if (plan.stop_after_rows && rows_done >= plan.stop_after_rows) {
                csv.flush();
                std::_Exit(3);  // no clean-up, as if killed
            }
        }
        if (plan.vtk_every_rows && (rows_done - 1) % plan.vtk_every_rows != 0) write_vtk();  // the last state too
        csv.close();
        if (!csv) mm::throw_input_error("cannot write ", partial.string(), " (disk full?)");
        fs::rename(partial, out / "timeseries.csv");
        fs::remove(out / "checkpoint.state");
        const Row last = exp.row();
        for (std::size_t i = 0; i < last.names.size(); ++i) results["last_row"][last.names[i]] = last.values[i];
    }
    if (report && terminal) std::printf("\n");

    nlohmann::ordered_json j;
    j["program"] = "element_test";
    j["run_id"] = plan.run_id;
    j["started"] = started;
    j["finished"] = micromacro::cli::now_iso();
    j["parameters"] = parameters_json(c);
    j["plan"] = plan_json(plan);
    j["timing"] = {{"wall_seconds", elapsed()}, {"prepare_wall_seconds", prepare_seconds}, {"steps", sim.steps_done()},
                   {"particle_steps_per_second", double(sim.steps_done() - steps_before) * double(sim.particles().size()) / elapsed()}};
    j["results"] = results;
    mm::io::write_whole_file(out / "run.json", std::ios::out, [&](std::ofstream& f) { f << j.dump(2) << "\n"; });
    if (report) std::printf("element_test %s: %s/run.json, %s\n", c.preset.c_str(), out.string().c_str(),
                            c.preset == "probes" ? (out / "probes.csv").string().c_str() : (out / "timeseries.csv").string().c_str());
    if (plan.pictures && !vtk_times.empty()) make_pictures(out, vtk_times.size(), dim, c.mean_radius());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    Config c;
    Plan plan;
    std::string preset = "shear-p", resume, out;
    bool overwrite = false, no_pictures = false;
    std::string preset_help = "the path the cell follows after the isotropic preparation:";
    for (const auto& [name, what] : presets()) preset_help += "\n  " + name + ": " + what;
    CLI::App app{"Element tests in a deforming periodic cell (2D disks, 3D spheres): a packing compressed isotropically "
                 "to p until it rests, then driven along a preset path by strain rates and stress servos. Writes run.json, "
                 "timeseries.csv (probes.csv for the probes), prepared.state, VTK frames and pictures into --out."};
    app.add_option("--dim", c.dim, "2 (disks) or 3 (spheres)")->check(CLI::IsMember({2, 3}))->capture_default_str();
    app.add_option("--preset", preset, preset_help)->capture_default_str();
    const auto options = micromacro::cli::add_options(app, parameter_table());
    app.add_option("--out", out, "the run's folder (created); a folder holding a run is refused without --overwrite");
    app.add_flag("--overwrite", overwrite, "replace the run in --out (only the files a run writes are removed)");
    app.add_option("--from-prepared", plan.from_prepared, "start the loading from this prepared.state of an earlier element_test run");
    app.add_option("--packing", plan.packing, "prepare from this packing file (CSV with x,z,r in 2D or x,y,z,r in 3D, or a LAMMPS "
                                              "dump), its box made periodic; the particles' masses from --density");
    app.add_option("--box", plan.box, "the packing file's cell, lo hi per axis (m), for a file without a box")->expected(4, 6);
    app.add_option("--checkpoint-every", plan.checkpoint_every, "write checkpoint.state every this many simulated seconds of the "
                                                                "loading (0: never)")
        ->check(micromacro::cli::non_negative())->capture_default_str();
    app.add_option("--resume", resume, "continue the killed run in this folder from its checkpoint.state");
    app.add_option("--vtk-every-rows", plan.vtk_every_rows, "a VTK frame every this many rows (0: none)")->capture_default_str();
    app.add_flag("--no-pictures", no_pictures, "make no plots and snapshots at the end");
    app.add_flag("--quiet", plan.quiet, "print nothing but errors");
    app.add_option("--threads", plan.threads, "OpenMP threads (results are bitwise the same for a fixed count)")
        ->check(CLI::Range(1, 1024))->capture_default_str();
    app.add_option("--stop-after-rows", plan.stop_after_rows, "testing: stop abruptly after this many rows, as a kill would")
        ->group("");
    MICROMACRO_PARSE_COMMAND_LINE(app, argc, argv);
    micromacro::cli::FolderLock lock;
    try {
        plan.pictures = !no_pictures;
        if (!resume.empty()) {
            for (const CLI::Option* o : app.get_options())
                if (o->count() && o->get_name() != "--resume" && o->get_name() != "--quiet" && o->get_name() != "--no-pictures")
                    mm::throw_input_error(o->get_name(), " is a setting of the run --resume continues (saved in its checkpoint); drop it");
            plan.out = resume;
            lock.take(plan.out, "--resume", "element_test");
            const fs::path checkpoint = plan.out / "checkpoint.state";
            if (!fs::exists(checkpoint))
                mm::throw_input_error(checkpoint.string(), " does not exist; was the run started with --checkpoint-every, or did it complete?");
            const auto saved = nlohmann::ordered_json::parse(mm::io::state_text(checkpoint, "checkpoint"));
            c = config_from_json(saved);
            const bool quiet = plan.quiet;
            plan_from_json(saved.at("plan"), plan);
            plan.quiet = quiet;
            plan.resume = true;
        } else {
            if (out.empty()) mm::throw_input_error("--out is missing; give the folder for the run (or --resume a killed one)");
            if (!plan.from_prepared.empty() && !plan.packing.empty())
                mm::throw_input_error("--from-prepared and --packing both give the packing; give one");
            if (!plan.box.empty() && plan.packing.empty()) mm::throw_input_error("--box is the cell of a --packing file; give --packing");
            apply_preset(c, preset);
            micromacro::cli::apply_options(parameter_table(), options, c);
            if (!plan.from_prepared.empty()) {
                if (const auto given = micromacro::cli::preparation_options_given(parameter_table(), options); !given.empty())
                    mm::throw_input_error(given.front(), " made the packing; --from-prepared ", plan.from_prepared,
                                          " supplies it; drop ", given.front());
                const Config prepared = prepared_config(plan.from_prepared);
                if (prepared.dim != c.dim)
                    mm::throw_input_error("--from-prepared ", plan.from_prepared, " holds a ", prepared.dim, "D packing; give --dim ",
                                          prepared.dim);
                micromacro::cli::take_preparation(parameter_table(), prepared, c);
                // Unless given, the loading's p is the one the packing rests at.
                if (!micromacro::cli::given(parameter_table(), options, "pressure")) c.pressure = prepared.pressure;
            }
            validate(c);
            plan.out = out;
            micromacro::cli::refuse_writing_over_inputs(plan.out / "prepared.state", "--out", {{"--from-prepared", plan.from_prepared}});
            micromacro::cli::claim_output_folder(plan.out, overwrite, plan.from_prepared, lock, "element_test");
            plan.run_id = micromacro::cli::new_run_id();
        }
        const int status = c.dim == 2 ? run<2>(c, plan) : run<3>(c, plan);
        if (!standard_output_complete()) return 1;
        return status;
    } catch (const std::exception& e) {
        if (!plan.out.empty()) micromacro::cli::discard_unresumable_series(plan.out);
        std::fprintf(stderr, "element_test: %s\n", e.what());
        return 1;
    }
}
