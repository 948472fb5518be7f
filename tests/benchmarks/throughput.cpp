// throughput: particle-steps per second, nanoseconds per contact and peak memory per particle of
// the engine on a dense packing, static or under slow shear, or on a packing given as a file.
// Laws: frictionless, frictional-no-rotation (Cundall-Strack springs on particles that do not
// turn) and frictional (springs and rotation, the paper's law).
//
//   throughput --dim 2 --particles 20000 --law frictional --steps 2000
//   throughput --packing packing.csv --box 0 0.1 0 0.1 --periodic x,z --k 1e5 --kt 2e4 --mu 0.5 --json
//
// The generated packing is a square (2D) or simple cubic (3D) lattice of equal 1 mm particles
// in a periodic box, pressed together by 1e-4 of a diameter and jittered by 1e-5 of it, so every
// particle keeps its 4 (2D) or 6 (3D) contacts and the packing stays static: the cost of a
// dense packing at rest. (A 1% overlap, tried first, makes the square lattice buckle: the
// first thousands of steps then time a collapsing, hot packing.) With --shear the particles get
// a velocity profile of 1/s (slowly sheared). --precision float stores the particle state in
// float (arithmetic stays double; the coarse positions are accepted for the timing);
// --threads splits the pair loop and the particle passes (OpenMP).
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <algorithm>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include <micromacro/io/packing_files.hpp>
#include <micromacro/micromacro.hpp>

namespace mm = micromacro;

namespace {
struct Options {
    int dim = 2;
    std::size_t particles = 1950;
    std::string law = "frictional";
    std::size_t steps = 1000;
    bool shear = false, json = false;
    std::string packing, periodic;
    std::vector<double> box;
    double k = 1e5, kt = 2e4, mu = 0.5;
    int threads = 1;
    std::string precision = "double";
    bool track_energy = true;
    bool shuffle = false, sort = false;
};

double peak_rss_bytes() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return 1024.0 * static_cast<double>(u.ru_maxrss);  // Linux reports kilobytes
}

template <int dim>
void fill_lattice(std::vector<mm::Vec<dim>>& x, std::vector<double>& r, double& L, std::size_t n, unsigned seed) {
    const int per_side = static_cast<int>(std::ceil(std::pow(double(n), 1.0 / dim)));
    const double spacing = 2e-3;
    L = per_side * spacing;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    for (std::size_t i = 0; i < n; ++i) {
        mm::Vec<dim> p;
        for (int a = 0, t = static_cast<int>(i); a < dim; ++a, t /= per_side) p[a] = (t % per_side + 0.5) * spacing + 2e-8 * U(rng);
        x.push_back(p);
        r.push_back(0.5 * spacing * 1.0001);  // overlap 1e-4 of a diameter with the lattice neighbours
    }
}

template <int dim, class Real, class Law>
int run(const Options& o, const Law& law, const char* law_name) {
    std::vector<mm::Vec<dim>> x;
    std::vector<double> r;
    mm::Domain<dim> domain;
    if (o.packing.empty()) {
        double L = 0;
        fill_lattice<dim>(x, r, L, o.particles, 1);
        domain = mm::Domain<dim>::fully_periodic(mm::Vec<dim>::Zero(), mm::Vec<dim>::Constant(L));
    } else {
        const auto f = mm::io::read_csv<dim>(o.packing);
        x = f.position;
        r = f.radius;
        std::array<bool, dim> periodic{};
        const std::string names = dim == 2 ? "xz" : "xyz";
        for (char c : o.periodic)
            if (names.find(c) != std::string::npos) periodic[names.find(c)] = true;
        mm::Vec<dim> lo, hi;
        if (o.box.size() != 2 * dim) mm::detail::throw_input_error("--packing needs --box with ", 2 * dim, " numbers");
        for (int a = 0; a < dim; ++a) lo[a] = o.box[2 * a], hi[a] = o.box[2 * a + 1];
        domain = mm::Domain<dim>(lo, hi, periodic);
    }
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
    mm::BasicSimulation<dim, Real, Law> sim(law, domain);
    sim.set_threads(o.threads);
    sim.set_track_energy(o.track_energy);
    sim.allow_coarse_positions(true);  // float cannot resolve these overlaps; here only the time counts
    const double rho = 2000.0;
    sim.particles().reserve(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) sim.particles().add(x[i], r[i], mm::sphere_mass(rho, r[i]));
    std::vector<mm::Vec<dim>>().swap(x);  // the engine holds them now: peak memory is the engine's
    std::vector<double>().swap(r);
    if (o.shear) {
        const double rate = 1.0;  // 1/s: slow against 1/t_c ~ 5e4/s
        for (std::size_t i = 0; i < sim.particles().size(); ++i) sim.particles().velocity()[i][0] = rate * (sim.particles().position()[i][dim - 1] - domain.lo()[dim - 1]);
    }
    if (o.sort) sim.sort_spatially();
    const double mean_mass = mm::sphere_mass(rho, 1e-3);
    sim.set_time_step(mm::contact_duration(o.k, 0.1, 0.5 * mean_mass) / 50);
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
    const char* name = o.packing.empty() ? (o.shear ? "shear" : "static") : "file";
    if (o.json)
        std::printf("{\"name\": \"%s-%s\", \"dim\": %d, \"particles\": %zu, \"contacts\": %zu, \"steps\": %zu, "
                    "\"seconds\": %.6g, \"particle_steps_per_second\": %.6g, \"ns_per_contact\": %.4g, "
                    "\"bytes_per_particle\": %.1f, \"storage_bytes_per_particle\": %.1f, \"threads\": %d, "
                    "\"precision\": \"%s\"}\n",
                    name, law_name, dim, sim.particles().size(), contacts, o.steps, seconds, pps, ns_contact, bytes, storage, o.threads,
                    o.precision.c_str());
    else
        std::printf("%s %s %dD: %zu particles, %zu contacts (coordination %.2f), %zu steps in %.3f s: %.3g particle-steps/s, "
                    "%.1f ns per contact, peak memory %.0f bytes per particle (engine arrays %.0f) (%d threads, %s)\n",
                    name, law_name, dim, sim.particles().size(), contacts, 2.0 * contacts / n, o.steps, seconds, pps,
                    ns_contact, bytes, storage, o.threads, o.precision.c_str());
    return 0;
}

template <int dim, class Real>
int dispatch_law(const Options& o) {
    if (o.law == "frictionless") return run<dim, Real>(o, mm::FrictionlessLinear{mm::LinearSpringDashpot(o.k, 0.1)}, "frictionless");
    if (o.law == "frictional-no-rotation")
        return run<dim, Real>(o,
                              mm::FrictionalLinearWithoutRotation{mm::LinearSpringDashpot(o.k, 0.1),
                                                                  mm::CundallStrackWithoutRotation(o.kt, 0.02, o.mu)},
                              "frictional-no-rotation");
    if (o.law == "frictional")
        return run<dim, Real>(o, mm::FrictionalLinear{mm::LinearSpringDashpot(o.k, 0.1), mm::CundallStrack(o.kt, 0.02, o.mu)},
                              "frictional");
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
    app.add_option("--dim", o.dim, "2 or 3")->check(CLI::IsMember({2, 3}))->capture_default_str();
    app.add_option("--particles", o.particles, "particles of the generated packing")->capture_default_str();
    app.add_option("--law", o.law,
                   "frictionless, frictional-no-rotation (tangential springs, particles do not turn) or frictional "
                   "(tangential springs and rotation)")
        ->check(CLI::IsMember({"frictionless", "frictional-no-rotation", "frictional"}))
        ->capture_default_str();
    app.add_option("--steps", o.steps, "time steps to time")->capture_default_str();
    app.add_flag("--shear", o.shear, "start from a slow shear profile instead of rest");
    app.add_option("--packing", o.packing, "time this packing instead (CSV as analyze_packing reads)")->check(CLI::ExistingFile);
    app.add_option("--box", o.box, "bounds lo hi per axis (with --packing)");
    app.add_option("--periodic", o.periodic, "periodic axes (with --packing), e.g. x,z");
    app.add_option("--k", o.k, "normal stiffness (N/m)")->capture_default_str();
    app.add_option("--kt", o.kt, "tangential stiffness (N/m)")->capture_default_str();
    app.add_option("--mu", o.mu, "friction coefficient")->capture_default_str();
    app.add_option("--threads", o.threads, "threads (OpenMP)")->capture_default_str();
    app.add_flag("--shuffle", o.shuffle, "number the particles in random order first");
    app.add_flag("--sort", o.sort, "renumber the particles in row order (sort_spatially) before timing");
    app.add_flag("!--no-energy", o.track_energy, "switch the energy books off (on by default, as in the examples)");
    app.add_option("--precision", o.precision, "storage precision of the particle state: double or float")
        ->check(CLI::IsMember({"double", "float"}))
        ->capture_default_str();
    app.add_flag("--json", o.json, "one JSON line instead of text");
    CLI11_PARSE(app, argc, argv);
    try {
        return o.dim == 2 ? dispatch<2>(o) : dispatch<3>(o);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "throughput: %s\n", e.what());
        return 1;
    }
}
