// throughput: particle-steps per second, nanoseconds per contact and peak memory per particle of
// the engine on a dense packing, static or under slow shear, or on a packing given as a file.
// Laws: frictionless, frictional-no-rotation (Cundall-Strack springs on particles that do not
// turn) and frictional (springs and rotation, the paper's law).
//
//   throughput --dim 2 --particles 20000 --law frictional --steps 2000
//   throughput --packing packing.csv --box 0 0.1 0 0.1 --periodic x,z --k 1e5 --kt 2e4 --mu 0.5 --json
//   throughput --packing dump.lammps --sort --dt 1e-7 --gamma-n 0.01   # box and pp axes from the dump
//
// The generated packing is a square (2D) or simple cubic (3D) lattice of equal 1 mm particles
// in a periodic box, pressed together by 1e-4 of a diameter and jittered by 1e-5 of it, so every
// particle keeps its 4 (2D) or 6 (3D) contacts and the packing stays static: the cost of a
// dense packing at rest. (A 1% overlap, tried first, makes the square lattice buckle: the
// first thousands of steps then time a collapsing, hot packing.) With --shear the particles get
// a velocity profile of 1/s (slowly sheared); with --cell-shear RATE the periodic cell itself is
// sheared at RATE (Lees-Edwards images, the particles moving with it: the cost of an element
// test's simple shear against the still box). --precision float stores the particle state in
// float (arithmetic stays double; the coarse positions are accepted for the timing);
// --threads splits the pair loop and the particle passes (OpenMP).
//
// A packing file (CSV as analyze_packing reads it, or a LAMMPS dump) is read, and its box and
// periodic axes settled, as analyze_packing does (io::read_packing, io::packing_domain); the
// dimension is the file's unless --dim says otherwise. The time step is t_c/50 of two particles
// of the packing's mean radius at --density (Eq. 22, the paper's choice), or --dt. Everything that
// sets the work is printed with the result (the JSON line's keys after "precision").
#include <sys/resource.h>

#include <chrono>
#include <filesystem>
#include <cmath>
#include <cstdio>
#include <algorithm>
#include <numeric>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <micromacro/io/packing_files.hpp>
#include <micromacro/io/packing_writer.hpp>
#include <micromacro/micromacro.hpp>

#include "../../examples/command_line.hpp"
#include "../../examples/standard_output.hpp"
#include "timed_particles.hpp"

namespace mm = micromacro;

namespace {
struct Options {
    int dim = 2;
    std::size_t particles = 1950;
    std::string law = "frictional";
    std::size_t steps = 1000;
    bool shear = false, json = false;
    double cell_shear = 0.0;
    std::string packing, periodic;
    mm::io::PackingFormat format = mm::io::PackingFormat::csv;  // of the packing file, from its first line
    std::vector<double> box;
    double k = 1e5, kt = 2e4, mu = 0.5;
    double gamma_n = 0.1, gamma_t = 0.02;  // kg/s, the paper's
    double density = 2000.0;               // kg/m^3
    double dt_fraction = 50.0, dt = 0.0;   // dt = t_c / dt_fraction unless dt > 0
    double skin = 0.0;                     // 0: the engine's default (a fifth of the mean radius)
    int threads = 1;
    std::string precision = "double";
    bool track_energy = true;
    bool shuffle = false, sort = false, auto_sort = true;
    std::string write_packing;  // a LAMMPS dump of the packing as timed (scripts/vs_lammps.sh hands it to LAMMPS)
};

double peak_rss_bytes() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return 1024.0 * static_cast<double>(u.ru_maxrss);  // Linux reports kilobytes
}

// A file name as a JSON string, quotes included (the program prints its JSON line by hand; bytes
// that are not UTF-8 become U+FFFD instead of an exception).
std::string json_string(const std::string& text) {
    return nlohmann::json(text).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

// Whether the engine's arithmetic here fuses multiplies and adds (built with MICROMACRO_FMA, for a
// CPU with FMA instructions): part of the configuration, it changes the speed and the last bits.
#if defined(MICROMACRO_FP_CONTRACT) && defined(__FP_FAST_FMA)
constexpr bool fused_multiply_add = true;
#else
constexpr bool fused_multiply_add = false;
#endif

template <int dim, class Real, class Law>
int run(const Options& o, const Law& law, const char* law_name) {
    auto [x, r, domain] = benchmark::timed_particles<dim>(o.packing, o.format, o.box, o.periodic, o.particles);
    if (o.shuffle) {  // the particles in random order, as random placement or a long flow leaves them
        std::vector<std::size_t> perm(x.size());
        std::iota(perm.begin(), perm.end(), std::size_t{0});
        std::shuffle(perm.begin(), perm.end(), std::mt19937_64(2));
        std::vector<mm::Vec<dim>> xs(x.size());
        std::vector<double> rs(r.size());
        for (std::size_t i = 0; i < perm.size(); ++i) xs[i] = x[perm[i]], rs[i] = r[perm[i]];
        x.swap(xs);
        r.swap(rs);
    }
    if (!o.write_packing.empty()) mm::io::write_lammps_dump<dim>(o.write_packing, x, r, domain);
    const double tc = benchmark::mean_contact_duration(r, o.density, o.k, o.gamma_n);
    const double dt = o.dt > 0.0 ? o.dt : tc / o.dt_fraction;
    if (!(std::isfinite(tc) && tc > 0.0 && std::isfinite(dt) && dt > 0.0))
        mm::detail::throw_input_error("--k ", o.k, " N/m with --density ", o.density, " kg/m^3 gives a contact duration t_c = ", tc,
                                      " s and dt = ", dt, " s (", o.dt > 0.0 ? "--dt" : "t_c / --dt-fraction",
                                      "), not finite and > 0; give values of a real material (k = 1e5 N/m, density 2000 kg/m^3)");
    mm::BasicSimulation<dim, Real, Law> sim(law, domain);
    sim.set_threads(o.threads);
    sim.set_track_energy(o.track_energy);
    sim.allow_coarse_positions(true);  // float cannot resolve these overlaps; here only the time counts
    if (o.skin > 0.0) sim.set_skin(o.skin);
    sim.particles().reserve(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) sim.particles().add(x[i], r[i], mm::sphere_mass(o.density, r[i]));
    std::vector<mm::Vec<dim>>().swap(x);  // the engine holds them now: peak memory is the engine's
    std::vector<double>().swap(r);
    if (o.shear) {
        const double rate = 1.0;  // 1/s: slow against 1/t_c ~ 5e4/s
        for (std::size_t i = 0; i < sim.particles().size(); ++i) sim.particles().velocity()[i][0] = rate * (sim.particles().position()[i][dim - 1] - domain.lo()[dim - 1]);
    }
    if (o.cell_shear != 0.0) {  // Lees-Edwards: the cell sheared, x moving with the last axis, the particles with it
        Eigen::Matrix<double, dim, dim> L = Eigen::Matrix<double, dim, dim>::Zero();
        L(0, dim - 1) = o.cell_shear;
        sim.set_velocity_gradient(L);
        for (std::size_t i = 0; i < sim.particles().size(); ++i)
            sim.particles().velocity()[i] = mm::convert<Real>(mm::Vec<dim>(L * (mm::convert<double>(sim.particles().position()[i]) - sim.domain().centre())));
    }
    if (o.sort) sim.sort_spatially();
    sim.set_auto_sort(o.auto_sort);
    sim.set_time_step(dt);
    if (const double limit = sim.stable_time_step(); dt > limit)  // said in the program's terms, not the engine's
        mm::detail::throw_input_error("time step dt = ", dt, " s (", o.dt > 0.0 ? "--dt" : "t_c / --dt-fraction",
                                      ") exceeds the stability limit ", limit,
                                      " s of the lightest particles' contact (set by --k, --kt, their dampings and the "
                                      "masses); give --dt below it, a larger --dt-fraction or a softer --kt");
    sim.prepare();
    const std::size_t contacts = sim.contact_count();
    const auto start = std::chrono::steady_clock::now();
    sim.run(o.steps);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double n = static_cast<double>(sim.particles().size());
    const double pps = n * o.steps / seconds;
    const double ns_contact = contacts ? 1e9 * seconds / (double(o.steps) * contacts) : 0.0;
    const double bytes = peak_rss_bytes() / n;  // whole process: includes its fixed baseline
    const double storage = static_cast<double>(sim.storage_bytes()) / n;
    const char* name = o.packing.empty() ? (o.cell_shear != 0.0 ? "sheared-cell" : o.shear ? "shear" : "static") : "file";
    // The configuration: everything that sets the work of a step.
    std::string periodic;
    for (int a = 0; a < dim; ++a)
        if (domain.periodic(a)) periodic += mm::io::csv_coordinates<dim>()[a];
    const bool engine_sorted = sim.spatial_sorts() > (o.sort ? 1u : 0u);
    const std::string order = std::string(o.shuffle ? "shuffled" : "as given") + (o.sort ? ", then sorted" : "") +
                              (engine_sorted ? ", sorted by the engine" : "");
    const bool friction = std::string_view(law_name) != "frictionless";
    if (o.json)
        std::printf("{\"name\": \"%s-%s\", \"dim\": %d, \"particles\": %zu, \"contacts\": %zu, \"steps\": %zu, "
                    "\"seconds\": %.6g, \"particle_steps_per_second\": %.6g, \"ns_per_contact\": %.4g, "
                    "\"bytes_per_particle\": %.1f, \"storage_bytes_per_particle\": %.1f, \"threads\": %d, "
                    "\"precision\": \"%s\", \"law\": \"%s\", \"packing\": %s, \"order\": \"%s\", \"periodic\": \"%s\", "
                    "\"k\": %.6g, \"gamma_n\": %.6g, \"kt\": %.6g, \"gamma_t\": %.6g, \"mu\": %.6g, \"density\": %.6g, "
                    "\"contact_duration\": %.6g, \"dt\": %.6g, \"skin\": %.6g, \"energy_books\": %s, \"shear\": %s, \"cell_shear\": %.6g, \"fma\": %s}\n",
                    name, law_name, dim, sim.particles().size(), contacts, o.steps, seconds, pps, ns_contact, bytes, storage, o.threads,
                    o.precision.c_str(), law_name, json_string(o.packing.empty() ? "lattice" : o.packing).c_str(), order.c_str(), periodic.c_str(), o.k,
                    o.gamma_n, friction ? o.kt : 0.0, friction ? o.gamma_t : 0.0, friction ? o.mu : 0.0, o.density, tc, dt,
                    sim.skin(), o.track_energy ? "true" : "false", o.shear ? "true" : "false", o.cell_shear, fused_multiply_add ? "true" : "false");
    else {
        std::printf("%s %s %dD: %zu particles, %zu contacts (coordination %.2f), %zu steps in %.3f s: %.3g particle-steps/s, "
                    "%.1f ns per contact, peak memory %.0f bytes per particle (engine arrays %.0f) (%d threads, %s)\n",
                    name, law_name, dim, sim.particles().size(), contacts, 2.0 * contacts / n, o.steps, seconds, pps,
                    ns_contact, bytes, storage, o.threads, o.precision.c_str());
        std::printf("  packing %s (order %s, periodic axes '%s'); k %.6g N/m, gamma_n %.6g kg/s", o.packing.empty() ? "lattice" : o.packing.c_str(),
                    order.c_str(), periodic.c_str(), o.k, o.gamma_n);
        if (friction) std::printf(", k_t %.6g N/m, gamma_t %.6g kg/s, mu %.6g", o.kt, o.gamma_t, o.mu);
        std::printf("; density %.6g kg/m^3, t_c %.6g s, dt %.6g s (t_c/%.4g), skin %.6g m; energy books %s; fused multiply-adds %s",
                    o.density, tc, dt, tc / dt, sim.skin(), o.track_energy ? "on" : "off", fused_multiply_add ? "on" : "off");
        if (o.cell_shear != 0.0) std::printf("; cell sheared at %.6g /s", o.cell_shear);
        std::printf("\n");
    }
    if (!standard_output_complete())
        mm::detail::throw_input_error("cannot write the result to standard output (is the disk full?)");
    return 0;
}

template <int dim, class Real>
int dispatch_law(const Options& o) {
    const mm::LinearSpringDashpot normal(o.k, o.gamma_n);
    if (o.law == "frictionless") return run<dim, Real>(o, mm::FrictionlessLinear{normal}, "frictionless");
    if (o.law == "frictional-no-rotation")
        return run<dim, Real>(o, mm::FrictionalLinearWithoutRotation{normal, mm::CundallStrackWithoutRotation(o.kt, o.gamma_t, o.mu)},
                              "frictional-no-rotation");
    if (o.law == "frictional")
        return run<dim, Real>(o, mm::FrictionalLinear{normal, mm::CundallStrack(o.kt, o.gamma_t, o.mu)}, "frictional");
    mm::detail::throw_input_error("--law '", o.law, "' is unknown; use frictionless, frictional-no-rotation or frictional");
}

template <int dim>
int dispatch(const Options& o) {
    return o.precision == "float" ? dispatch_law<dim, float>(o) : dispatch_law<dim, double>(o);
}
}  // namespace

int main(int argc, char** argv) {
    Options o;
    CLI::App app{"Engine throughput: particle-steps per second, ns per contact, peak memory per particle"};
    auto* dim = app.add_option("--dim", o.dim, "2 or 3 (with --packing: the file's, a CSV 3 if it has a y column)")
                    ->check(CLI::IsMember({2, 3}))
                    ->capture_default_str();
    auto* particles = app.add_option("--particles", o.particles, "particles of the generated lattice (at least 9 in 2D, 27 in 3D)")
                          ->capture_default_str();
    app.add_option("--law", o.law,
                   "frictionless, frictional-no-rotation (tangential springs, particles do not turn) or frictional "
                   "(tangential springs and rotation)")
        ->check(CLI::IsMember({"frictionless", "frictional-no-rotation", "frictional"}))
        ->capture_default_str();
    app.add_option("--steps", o.steps, "time steps to time")->check(CLI::Range(std::size_t{1}, std::size_t{1} << 40))->capture_default_str();
    app.add_flag("--shear", o.shear, "start from a slow shear profile (1/s) instead of rest");
    app.add_option("--cell-shear", o.cell_shear,
                   "shear the periodic cell at this rate (1/s; x moving with the last axis, Lees-Edwards images), the "
                   "particles moving with it; 0: a still box")
        ->capture_default_str()->excludes("--shear");
    auto* packing = app.add_option("--packing", o.packing,
                                   "time this packing instead: CSV as analyze_packing reads it (x,z,r in 2D, x,y,z,r in 3D) "
                                   "or a LAMMPS dump (format from the first line)")
                        ->check(CLI::ExistingFile)
                        ->excludes(particles);
    app.add_option("--box", o.box, "bounds lo hi per axis (m; default: the dump's box, else the particles' extent)")
        ->expected(4, 6)
        ->needs(packing);
    app.add_option("--periodic", o.periodic, "periodic axes, e.g. x,z (default: the dump's pp axes, else none)")->needs(packing);
    app.add_option("--k", o.k, "normal stiffness (N/m)")->capture_default_str();
    app.add_option("--gamma-n", o.gamma_n, "normal damping gamma_0 (kg/s)")->capture_default_str();
    app.add_option("--kt", o.kt, "tangential stiffness (N/m)")->capture_default_str();
    app.add_option("--gamma-t", o.gamma_t, "tangential damping (kg/s)")->capture_default_str();
    app.add_option("--mu", o.mu, "friction coefficient")->capture_default_str();
    app.add_option("--density", o.density, "particle density (kg/m^3): masses, and t_c")->capture_default_str();
    auto* fraction = app.add_option("--dt-fraction", o.dt_fraction, "dt = t_c / this, t_c of two particles of the mean radius")
                         ->check(micromacro::cli::positive())
                         ->capture_default_str();
    app.add_option("--dt", o.dt, "the time step in s instead")->check(micromacro::cli::positive())->excludes(fraction);
    app.add_option("--skin", o.skin, "neighbour-list skin in m (default: a fifth of the mean radius)")->check(micromacro::cli::positive());
    app.add_option("--threads", o.threads, "threads (OpenMP)")->capture_default_str();
    app.add_flag("--shuffle", o.shuffle, "number the particles in random order first");
    app.add_flag("--sort", o.sort, "renumber the particles in row order (sort_spatially) before timing; "
                                   "a file's own order may be slow (see docs/performance.md)");
    app.add_flag("!--no-auto-sort", o.auto_sort,
                 "keep the particles in the order given: the engine sorts scenes of 2048 or more spatially on its own "
                 "(BasicSimulation::set_auto_sort)");
    app.add_flag("!--no-energy", o.track_energy, "switch the energy books off (on by default, as in the examples)");
    app.add_option("--precision", o.precision, "storage precision of the particle state: double or float")
        ->check(CLI::IsMember({"double", "float"}))
        ->capture_default_str();
    app.add_option("--write-packing", o.write_packing,
                   "also write the packing as timed (after --shuffle) as a LAMMPS dump to this new file, e.g. for LAMMPS");
    app.add_flag("--json", o.json, "one JSON line instead of text");
    MICROMACRO_PARSE_COMMAND_LINE(app, argc, argv);
    try {
        if (!o.write_packing.empty() && std::filesystem::exists(o.write_packing))
            mm::detail::throw_input_error("--write-packing ", o.write_packing, " exists; give a new file name");
        if (!o.packing.empty()) {
            o.format = mm::io::guess_format(o.packing);
            if (dim->count() == 0) o.dim = mm::io::guess_dimension(o.packing, o.format);
        }
        return o.dim == 2 ? dispatch<2>(o) : dispatch<3>(o);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "throughput: %s\n", e.what());
        return 1;
    }
}
