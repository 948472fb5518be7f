// biaxial: the paper's biaxial test (Sec. 4) with one command.
//
//   biaxial --preset quick --out runs/quick        # under a minute on one core
//   biaxial --preset paper --out runs/paper        # N = 1950, T = 1 s, as in the paper
//   biaxial --dim 3 --preset quick --out runs/tri  # the same experiment as a triaxial box
//
// Writes run.json (every parameter, derived figures, timing) and timeseries.csv (one row per
// output interval of the loading) into --out. Run with --help for every option and its unit.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "biaxial.hpp"

namespace fs = std::filesystem;
using biaxial::Config;

namespace {

std::string now_iso() {
    const std::time_t t = std::time(nullptr);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
    return buf;
}

/// Writes `text` to `path` atomically: a temporary file in the same directory, then a rename.
void write_atomically(const fs::path& path, const std::string& text) {
    const fs::path partial = path.string() + ".partial";
    {
        std::ofstream out(partial);
        if (!(out << text) || !out.flush()) {
            std::error_code ignored;
            fs::remove(partial, ignored);
            micromacro::detail::throw_input_error("cannot write ", partial.string());
        }
    }
    fs::rename(partial, path);
}

std::string csv_number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

nlohmann::ordered_json parameters(const Config& c) {
    return {{"dim", c.dim},
            {"preset", c.preset},
            {"particles", c.particles},
            {"radius_min_m", c.radius_min},
            {"radius_max_m", c.radius_max},
            {"density_kg_m3", c.density},
            {"k_N_m", c.k},
            {"gamma0_kg_s", c.gamma0},
            {"mu", c.mu},
            {"mu_prepare", c.mu_prepare},
            {"kt_ratio", c.kt_ratio},
            {"gammat_ratio", c.gammat_ratio},
            {"pressure", c.pressure},
            {"pressure_unit", c.dim == 2 ? "N/m" : "Pa"},
            {"period_s", c.period},
            {"final_strain", c.final_strain},
            {"relax_s", c.relax},
            {"dt_fraction", c.dt_fraction},
            {"seed", c.seed},
            {"gamma_b_kg_s", c.gamma_b},
            {"gamma_b_prepare_kg_s", c.gamma_b_prepare},
            {"gamma_r_kg_m2_s", c.rotational_damping(c.gamma_b)},
            {"wall_mass_kg", c.wall_mass},
            {"wall_damping_kg_s", c.wall_damping},
            {"prepare_speed_m_s", c.prepare_speed},
            {"prepare_kinetic_ratio", c.prepare_kinetic_ratio},
            {"output_interval_s", c.output_interval},
            {"box_factor", c.box_factor},
            {"wall_friction", c.wall_friction}};
}

template <int dim>
int run(const Config& c, const fs::path& out, bool quiet) {
    const bool terminal = !quiet && isatty(STDOUT_FILENO);
    const auto wall_start = std::chrono::steady_clock::now();
    const std::string started = now_iso();
    biaxial::Experiment<dim> exp(c);
    exp.build();
    auto& sim = exp.simulation();
    const double n = static_cast<double>(c.particles);

    auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count(); };
    double last_print = -1.0;
    auto progress = [&](const char* phase, double fraction, double strain) {
        if (!terminal || elapsed() - last_print < 0.5) return;
        last_print = elapsed();
        const double rate = sim.steps_done() * n / std::max(elapsed(), 1e-9);
        const double left = fraction > 0 ? elapsed() * (1.0 - fraction) / fraction : 0.0;
        std::printf("\r%-9s strain %.4f  t = %.5f s  %.2e particle-steps/s  ~%.0f s left   ", phase, strain, sim.time(),
                    rate, left);
        std::fflush(stdout);
    };

    exp.prepare([&](const auto&) { progress("prepare", 0.0, 0.0); });
    const double prepare_seconds = elapsed();
    const std::size_t prepare_steps = sim.steps_done();
    exp.start_loading();

    // Loading: one row per output interval, into a partial file renamed at the end.
    const fs::path series = out / "timeseries.csv";
    const fs::path partial = out / "timeseries.csv.partial";
    std::ofstream csv(partial);
    if (!csv) micromacro::detail::throw_input_error("cannot write ", partial.string());
    bool header = false;
    auto write_row = [&] {
        const auto r = exp.row();
        if (!header) {
            csv << "# units: time s, strains 1, walls m, stresses " << (dim == 2 ? "N/m" : "Pa") << ", stiffness "
                << (dim == 2 ? "N/m" : "Pa") << ", fabric 1, energies J, phi_F rad\n";
            for (std::size_t i = 0; i < r.names.size(); ++i) csv << (i ? "," : "") << r.names[i];
            csv << "\n";
            header = true;
        }
        for (std::size_t i = 0; i < r.values.size(); ++i) csv << (i ? "," : "") << csv_number(r.values[i]);
        csv << "\n";
    };
    const double dt = sim.time_step();
    const auto steps_per_row = std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(c.output_interval / dt)));
    const auto total_rows = static_cast<std::size_t>(std::ceil((exp.load_end() - exp.load_start()) / (steps_per_row * dt)));
    write_row();
    for (std::size_t row = 0; row < total_rows; ++row) {
        sim.run(steps_per_row);
        write_row();
        progress("load", double(row + 1) / total_rows, exp.eps_zz());
    }
    csv.close();
    if (!csv) micromacro::detail::throw_input_error("cannot finish ", partial.string());
    fs::rename(partial, series);

    const double seconds = elapsed();
    const double pps = sim.steps_done() * n / seconds;
    const double tc = c.contact_duration();
    // Inertial number I = (d eps/dt) d sqrt(rho / p) at the peak rate of Eq. 17, eps_f pi / T, with
    // the mean diameter d; in 2D rho is the sphere mass per disk area, 4/3 rho a.
    const double peak_rate = c.final_strain * M_PI / c.period;
    const double rho_2d = 4.0 / 3.0 * c.density * c.mean_radius();
    const double inertial = peak_rate * 2.0 * c.mean_radius() * std::sqrt((dim == 2 ? rho_2d : c.density) / c.pressure);
    // Drag of the background damping on the column moved by the top wall, against the side
    // pressure times the box side: the mean particle moves at half the top wall's peak speed.
    const auto box = exp.reference_box();
    const double peak_wall_speed = peak_rate * box[dim - 1];
    double side = 1.0;
    for (int k = 0; k < dim - 1; ++k) side *= box[k];
    const double background_drag = c.gamma_b * n * 0.5 * peak_wall_speed / (c.pressure * side);
    nlohmann::ordered_json j;
    j["program"] = "micromacro biaxial";
    j["version"] = "0.1.0";
    j["parameters"] = parameters(c);
    j["derived"] = {{"contact_duration_s", tc},
                    {"time_step_s", sim.time_step()},
                    {"stable_time_step_s", sim.stable_time_step()},
                    {"restitution", micromacro::restitution(c.k, c.gamma0, 0.5 * c.mean_mass())},
                    {"peak_strain_rate_1_s", peak_rate},
                    {"inertial_number_at_peak_rate", inertial},
                    {"background_drag_over_pL_at_peak_rate", background_drag},
                    {"wall_oscillation_time_s", 2.0 * M_PI * std::sqrt(c.wall_mass / c.k)},
                    {"wall_damping_time_s", c.wall_damping > 0 ? 2.0 * c.wall_mass / c.wall_damping : 0.0},
                    {"box_after_preparation_m", exp.reference_box()},
                    {"final_eps_zz", exp.eps_zz()}};
    j["timing"] = {{"started", started},
                   {"finished", now_iso()},
                   {"wall_seconds", seconds},
                   {"prepare_wall_seconds", prepare_seconds},
                   {"steps", sim.steps_done()},
                   {"prepare_steps", prepare_steps},
                   {"particle_steps_per_second", pps}};
    write_atomically(out / "run.json", j.dump(2) + "\n");
    if (terminal) std::printf("\n");
    std::printf("biaxial %dD: %zu particles, %zu steps in %.1f s (%.3g particle-steps/s); results in %s\n", dim,
                c.particles, sim.steps_done(), seconds, pps, out.string().c_str());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    Config c;
    std::string preset = "quick", out;
    bool quiet = false;
    CLI::App app{"The paper's biaxial test: preparation, strain-controlled loading (Eq. 17) against a "
                 "stress-controlled side wall (Eq. 18), relaxation; averages in the inner box."};
    app.add_option("--dim", c.dim, "2 (biaxial) or 3 (triaxial box)")->capture_default_str();
    app.add_option("--preset", preset, "paper (N = 1950, T = 1 s) or quick (N = 300, T = 0.1 s)")->capture_default_str();
    app.add_option("--out", out, "output directory (created)")->required();
    // Options that override the preset: collected first, applied after it.
    auto* particles = app.add_option("--particles", "number of particles");
    auto* pressure = app.add_option("--pressure", "side pressure p (N/m in 2D, Pa in 3D; default 20 and 1e4)");
    auto* mu = app.add_option("--mu", "friction coefficient mu_s = mu_d (default 0.5)");
    auto* mup = app.add_option("--mu-prepare", "friction while preparing (default: --mu; lower gives denser packings)");
    auto* kt = app.add_option("--kt-ratio", "k_t / k (default 0.2)");
    auto* period = app.add_option("--period", "T of Eq. 17 in s (loading lasts T/2)");
    auto* strain = app.add_option("--final-strain", "eps_zz at the end of the motion (default 0.2)");
    auto* relax = app.add_option("--relax", "relaxation after T/2 in s");
    auto* dtf = app.add_option("--dt-fraction", "dt = t_c / this, t_c of two mean particles (default 50)");
    auto* seed = app.add_option("--seed", "random seed of the initial placement (default 1)");
    auto* gb = app.add_option("--gamma-b", "background damping while loading in kg/s (default 1e-4)");
    auto* gbp = app.add_option("--gamma-b-prepare", "background damping while preparing in kg/s (default 1e-2)");
    auto* mw = app.add_option("--wall-mass", "m_w of Eq. 18 in kg (default 1e-4)");
    auto* gw = app.add_option("--wall-damping", "gamma_w of Eq. 18 in kg/s while loading (default 0.63)");
    auto* interval = app.add_option("--output-interval", "time between rows of timeseries.csv in s");
    app.add_flag("--wall-friction", c.wall_friction, "walls use the particles' friction (default: smooth walls)");
    app.add_flag("--quiet", quiet, "no progress line, only the final summary");
    CLI11_PARSE(app, argc, argv);

    try {
        biaxial::apply_preset(c, preset);
        auto set = [](CLI::Option* o, auto& field) {
            if (o->count()) field = o->as<std::decay_t<decltype(field)>>();
        };
        set(particles, c.particles);
        set(pressure, c.pressure);
        set(mu, c.mu);
        c.mu_prepare = c.mu;
        set(mup, c.mu_prepare);
        set(kt, c.kt_ratio);
        set(period, c.period);
        set(strain, c.final_strain);
        set(relax, c.relax);
        set(dtf, c.dt_fraction);
        set(seed, c.seed);
        set(gb, c.gamma_b);
        set(gbp, c.gamma_b_prepare);
        set(mw, c.wall_mass);
        set(gw, c.wall_damping);
        set(interval, c.output_interval);
        biaxial::validate(c);
        std::error_code ec;
        fs::create_directories(out, ec);
        const fs::path probe = fs::path(out) / ".write_test";
        if (ec || !std::ofstream(probe))
            micromacro::detail::throw_input_error("--out ", out, " is not a writable directory");
        fs::remove(probe, ec);
        return c.dim == 2 ? run<2>(c, out, quiet) : run<3>(c, out, quiet);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "biaxial: %s\n", e.what());
        return 1;
    }
}
