// speed_accuracy: what each speed setting costs and what it buys, measured, written as
// docs/speed-accuracy.md and docs/speed-accuracy.svg.
//
//   speed_accuracy --seeds 12 --jobs 2 --out-dir docs   (about 20 minutes on two cores)
//   speed_accuracy --tiny --out-dir /tmp/x (seconds: CI runs this so the program cannot rot)
//
// Two sweeps. The two-particle collision against Eq. 22 (exact): time step t_c/10 ... t_c/200
// with t_c of the mean pair or of the smallest pair, and both integrators. The biaxial quick
// preset (2D, 300 particles) against a converged reference run (the smallest time step, the
// slowest loading, double precision): time step, integrator, loading period T, the loading's damping;
// and the coarse-graining kernel width on the reference's relaxed state. Every number in the
// output comes from the runs of this program; nothing is stored.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <future>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <micromacro/io/whole_file.hpp>

#include "../biaxial/biaxial.hpp"
#include "../command_line.hpp"

namespace mm = micromacro;
namespace fs = std::filesystem;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string format(const char* fmt, double v) {
    char b[64];
    std::snprintf(b, sizeof b, fmt, v);
    return b;
}
std::string percent(double relative) { return std::isfinite(relative) ? format("%.2f%%", 100 * relative) : "-"; }

// ---- the collision --------------------------------------------------------------------------

struct CollisionRow {
    std::string base;        // "mean pair" or "smallest pair"
    double fraction;         // dt = t_c(base) / fraction
    std::string integrator;
    double steps_per_contact;  // of the smallest pair
    double e_error_mean, tc_error_mean, e_error_small, tc_error_small;
};

template <class Integrator, class Real = double>
CollisionRow collision_row(const biaxial::Config& c, const std::string& base, double fraction) {
    const mm::LinearSpringDashpot law(c.k, c.gamma0);
    const double m_mean = c.mean_mass(), m_small = mm::sphere_mass(c.density, c.radius_min);
    const double tc_mean = mm::contact_duration(c.k, c.gamma0, m_mean / 2);
    const double tc_small = mm::contact_duration(c.k, c.gamma0, m_small / 2);
    const double dt = (base == "mean pair" ? tc_mean : tc_small) / fraction;
    // The worst over 16 entry phases (where in a step the contact begins): at coarse steps the
    // phase decides much of the error, and a packing samples all phases.
    auto error = [&](double m, double a) {
        const double e = mm::restitution(c.k, c.gamma0, m / 2), tc = mm::contact_duration(c.k, c.gamma0, m / 2);
        std::pair<double, double> worst{0.0, 0.0};
        for (int phase = 1; phase <= 16; ++phase) {
            const auto measured = mm::measure_normal_collision<2, Integrator, Real>(law, m, a, m, a, 0.1, dt, phase / 16.0);
            worst.first = std::max(worst.first, std::abs(measured.restitution / e - 1));
            worst.second = std::max(worst.second, std::abs(measured.contact_duration / tc - 1));
        }
        return worst;
    };
    const auto [em, tm] = error(m_mean, c.mean_radius());
    const auto [es, ts] = error(m_small, c.radius_min);
    return {base, fraction, std::string(Integrator::name) + (std::is_same_v<Real, float> ? ", float" : ""), tc_small / dt,
            em, tm, es, ts};
}

// ---- the biaxial test -----------------------------------------------------------------------

struct Outcome {
    std::string failure;  // the error message of a run that stopped; empty if it completed
    double seconds = 0, particle_steps = 0, steps = 0;
    double peak_ratio = 0, strain_at_peak = 0, max_fabric = 0, Cn_at_peak = 0, wall_gap = 0, residual = 0;
    double box_stress = 0;  // for the kernel rows: the relaxed state's inner-box sigma_22
    mm::PackingSnapshot<2> relaxed;
};

struct Variant {
    std::string group, label;
    biaxial::Config config;
    bool symplectic_euler = false;
    unsigned long long first_seed = 1;
    bool single_precision = false;  // float storage (arithmetic stays double)
};

// Runs the preparation and the loading; the peak quantities are taken from rows smoothed over
// five output intervals (one row of a few hundred particles fluctuates by several percent).
template <class Integrator, class Real = double>
Outcome run_biaxial(const biaxial::Config& c) {
    const auto t0 = std::chrono::steady_clock::now();
    biaxial::Experiment<2, Integrator, Real> exp(c);
    exp.build();
    exp.prepare();
    exp.start_loading();
    auto& sim = exp.simulation();
    std::map<std::string, std::vector<double>> col;
    const std::size_t rows = exp.loading_rows(), steps_per_row = exp.steps_per_row();
    for (std::size_t r = 0; r < rows; ++r) {
        if (r) sim.run(steps_per_row);
        const auto row = exp.row();
        for (std::size_t i = 0; i < row.names.size(); ++i) col[row.names[i]].push_back(row.values[i]);
    }
    Outcome o;
    o.seconds = seconds_since(t0);
    o.steps = static_cast<double>(sim.steps_done());
    o.particle_steps = o.steps * static_cast<double>(sim.particles().size());
    o.residual = sim.energy_residual();
    auto smooth = [&](const std::string& key, std::size_t r) {
        const auto& v = col.at(key);
        const std::size_t lo = r >= 2 ? r - 2 : 0, hi = std::min(v.size() - 1, r + 2);
        double sum = 0;
        for (std::size_t i = lo; i <= hi; ++i) sum += v[i];
        return sum / static_cast<double>(hi - lo + 1);
    };
    const auto& ezz = col.at("strain_22");
    std::size_t peak = 0, motion_rows = 0;
    double best = -1e300, gap = 0;
    for (std::size_t r = 0; r < ezz.size() && ezz[r] < c.final_strain - 1e-12; ++r, ++motion_rows) {
        const double ratio = (smooth("sigma_22", r) - smooth("sigma_11", r)) / (smooth("sigma_22", r) + smooth("sigma_11", r));
        if (ratio > best) best = ratio, peak = r;
        o.max_fabric = std::max(o.max_fabric, smooth("deviatoric_fabric", r));
        gap += std::abs(col.at("sigma_wall_22")[r] / col.at("sigma_22")[r] - 1);
    }
    o.peak_ratio = best;
    o.strain_at_peak = ezz[peak];
    o.Cn_at_peak = smooth("C_n_2222", peak);
    o.wall_gap = motion_rows ? gap / static_cast<double>(motion_rows) : NAN;
    o.relaxed = mm::take_snapshot(sim);
    o.box_stress = col.at("sigma_22").back();
    return o;
}

// One run per packing (seeds first_seed, first_seed + 1, ...): a packing of a few hundred
// particles is chaotic enough that a change of dt by 1e-6 moves its peak by 10-20%, so only
// ensemble statistics can show what a setting does. `jobs` packings run at a time. A setting the
// engine or the preparation refuses is a result too: its failure says why.
struct VariantResult {
    std::string failure;
    std::vector<Outcome> runs;
    double mean(double Outcome::*field) const {
        double sum = 0;
        for (const auto& o : runs) sum += o.*field;
        return runs.empty() ? NAN : sum / static_cast<double>(runs.size());
    }
};

Outcome run_one(const Variant& v, unsigned long long seed) {
    biaxial::Config c = v.config;
    c.seed = seed;
    try {
        return v.single_precision   ? run_biaxial<mm::VelocityVerlet, float>(c)
               : v.symplectic_euler ? run_biaxial<mm::SymplecticEuler>(c)
                                    : run_biaxial<mm::VelocityVerlet>(c);
    } catch (const std::exception& e) {
        Outcome o;
        o.failure = "seed " + std::to_string(seed) + ": " + e.what();
        return o;
    }
}

VariantResult run_variant(const Variant& v, int seeds, int jobs) {
    VariantResult result;
    for (int k0 = 0; k0 < seeds; k0 += jobs) {
        std::vector<std::future<Outcome>> batch;
        for (int k = k0; k < std::min(seeds, k0 + jobs); ++k)
            batch.push_back(std::async(std::launch::async, run_one, std::cref(v), v.first_seed + static_cast<unsigned long long>(k)));
        for (auto& f : batch) {
            Outcome o = f.get();
            if (!o.failure.empty() && result.failure.empty()) result.failure = o.failure;
            result.runs.push_back(std::move(o));
        }
        if (!result.failure.empty()) break;
    }
    return result;
}

// The difference of a setting's mean from the reference's with its 95% confidence interval
// (Welch: the packings of two settings are independent samples, the variances unequal), both
// relative to the reference's mean.
struct Difference {
    double relative = NAN, half_width = NAN;
    bool distinguishable() const { return std::abs(relative) > half_width; }
};

Difference difference(const VariantResult& a, const VariantResult& ref, double Outcome::*field) {
    const double na = static_cast<double>(a.runs.size()), nr = static_cast<double>(ref.runs.size());
    if (na < 2 || nr < 2) return {};
    auto variance = [&](const VariantResult& r, double mean) {
        double sum = 0;
        for (const auto& o : r.runs) sum += (o.*field - mean) * (o.*field - mean);
        return sum / static_cast<double>(r.runs.size() - 1);
    };
    const double ma = a.mean(field), mr = ref.mean(field);
    const double va = variance(a, ma) / na, vr = variance(ref, mr) / nr;
    const double freedom = (va + vr) * (va + vr) / (va * va / (na - 1) + vr * vr / (nr - 1));
    const double t = boost::math::quantile(boost::math::students_t(freedom), 0.975);
    return {(ma - mr) / std::abs(mr), t * std::sqrt(va + vr) / std::abs(mr)};
}

// ---- the kernel width ------------------------------------------------------------------------

struct KernelRow {
    double width_in_diameters, seconds, rms, bias;
};

// The relaxed reference state coarse-grained with a Gaussian of width w on a grid over the whole
// packing (spacing the smaller of w and half a mean diameter): over the grid points in the inner
// box, how far one point's sigma_22 typically lies from the inner-box average (rms), and how far
// their mean lies (bias).
KernelRow kernel_row(const mm::PackingSnapshot<2>& s, double box_sigma22, double width_in_diameters) {
    const double d = mm::mean_diameter(s);
    const mm::GaussianKernel kernel{width_in_diameters * d};
    const auto whole = mm::Region<2>::whole(s), inner = mm::Region<2>::inner(s, 0.1);
    const double spacing = std::min(kernel.width, 0.5 * d);
    std::array<int, 2> n;
    for (int a = 0; a < 2; ++a) n[a] = std::max(1, static_cast<int>(std::ceil((whole.hi[a] - whole.lo[a]) / spacing)));
    const auto grid = mm::Grid<2>::covering(whole.lo, whole.hi, n);
    const auto t0 = std::chrono::steady_clock::now();
    const auto f = mm::coarse_grain(s, grid, kernel);
    const double seconds = seconds_since(t0);
    double sum = 0, sum2 = 0, count = 0;
    for (std::size_t i = 0; i < grid.size(); ++i) {
        if (!inner.contains(grid.point(i))) continue;
        const double x = (f.stress_normal[i](1, 1) + f.stress_tangential[i](1, 1)) / box_sigma22 - 1;
        sum += x;
        sum2 += x * x;
        count += 1;
    }
    return {width_in_diameters, seconds, std::sqrt(sum2 / count), sum / count};
}

// ---- a small log-log SVG plot ----------------------------------------------------------------

struct Series {
    std::string name, colour;
    std::vector<std::pair<double, double>> points;
};

std::string svg_panel(double x0, double y0, double w, double h, const std::string& title, const std::string& xlabel,
                      const std::string& ylabel, const std::vector<Series>& series, double floor_value = NAN) {
    double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
    for (const auto& s : series)
        for (auto [x, y] : s.points)
            if (x > 0 && y > 0) xmin = std::min(xmin, x), xmax = std::max(xmax, x), ymin = std::min(ymin, y), ymax = std::max(ymax, y);
    if (floor_value > 0) ymin = std::min(ymin, floor_value), ymax = std::max(ymax, floor_value);
    if (!(xmax > 0)) return "";
    xmin = std::pow(10, std::floor(std::log10(xmin))), xmax = std::pow(10, std::ceil(std::log10(xmax)));
    ymin = std::pow(10, std::floor(std::log10(ymin))), ymax = std::pow(10, std::ceil(std::log10(ymax)));
    if (xmax <= xmin) xmax = 10 * xmin;
    if (ymax <= ymin) ymax = 10 * ymin;
    const double L = 70, R = 15, T = 30, B = 45;
    auto X = [&](double x) { return x0 + L + (w - L - R) * std::log10(x / xmin) / std::log10(xmax / xmin); };
    auto Y = [&](double y) { return y0 + h - B - (h - T - B) * std::log10(y / ymin) / std::log10(ymax / ymin); };
    std::ostringstream o;
    o << "<text x='" << x0 + w / 2 << "' y='" << y0 + 18 << "' text-anchor='middle' font-size='14'>" << title << "</text>\n";
    o << "<rect x='" << x0 + L << "' y='" << y0 + T << "' width='" << w - L - R << "' height='" << h - T - B
      << "' fill='none' stroke='black'/>\n";
    for (double x = xmin; x <= xmax * 1.0001; x *= 10)
        o << "<line x1='" << X(x) << "' x2='" << X(x) << "' y1='" << y0 + T << "' y2='" << y0 + h - B
          << "' stroke='#ddd'/><text x='" << X(x) << "' y='" << y0 + h - B + 15 << "' text-anchor='middle' font-size='11'>"
          << format("%g", x) << "</text>\n";
    for (double y = ymin; y <= ymax * 1.0001; y *= 10)
        o << "<line x1='" << x0 + L << "' x2='" << x0 + w - R << "' y1='" << Y(y) << "' y2='" << Y(y)
          << "' stroke='#ddd'/><text x='" << x0 + L - 5 << "' y='" << Y(y) + 4 << "' text-anchor='end' font-size='11'>"
          << format("%g", y) << "</text>\n";
    o << "<text x='" << x0 + L + (w - L - R) / 2 << "' y='" << y0 + h - 8 << "' text-anchor='middle' font-size='12'>" << xlabel
      << "</text>\n";
    o << "<text transform='translate(" << x0 + 14 << "," << y0 + T + (h - T - B) / 2
      << ") rotate(-90)' text-anchor='middle' font-size='12'>" << ylabel << "</text>\n";
    if (floor_value > 0)
        o << "<line x1='" << x0 + L << "' x2='" << x0 + w - R << "' y1='" << Y(floor_value) << "' y2='" << Y(floor_value)
          << "' stroke='gray' stroke-dasharray='6,4'/><text x='" << x0 + w - R - 4 << "' y='" << Y(floor_value) - 4
          << "' text-anchor='end' font-size='11' fill='gray'>chaos floor</text>\n";
    int legend = 0;
    for (const auto& s : series) {
        std::ostringstream path;
        for (auto [x, y] : s.points)
            if (x > 0 && y > 0) path << X(x) << "," << Y(y) << " ";
        o << "<polyline points='" << path.str() << "' fill='none' stroke='" << s.colour << "' stroke-width='1.5'/>\n";
        for (auto [x, y] : s.points)
            if (x > 0 && y > 0) o << "<circle cx='" << X(x) << "' cy='" << Y(y) << "' r='3' fill='" << s.colour << "'/>\n";
        o << "<text x='" << x0 + L + 8 << "' y='" << y0 + T + 15 + 14 * legend++ << "' font-size='11' fill='" << s.colour << "'>"
          << s.name << "</text>\n";
    }
    return o.str();
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"speed_accuracy: the measured speed-accuracy trade (docs/speed-accuracy.md and .svg)"};
    std::string out_dir = "docs";
    bool tiny = false;
    std::size_t particles = 300;
    int seeds = 1, jobs = 1;
    app.add_option("--out-dir", out_dir, "where speed-accuracy.md and speed-accuracy.svg go")->capture_default_str();
    auto* particles_option =
        app.add_option("--particles", particles, "particles of the biaxial runs (the quick preset's 300)")->capture_default_str();
    app.add_option("--seeds", seeds, "packings per biaxial row; the row shows their mean (the docs use 4)")
        ->capture_default_str()
        ->check(CLI::Range(1, 100));
    app.add_option("--jobs", jobs, "packings run at a time (each on one thread); the seconds are each run's own")
        ->capture_default_str()
        ->check(CLI::Range(1, 64));
    app.add_flag("--tiny", tiny, "a few seconds: 40 particles, short loading, fewer rows (for CI; the numbers mean little)");
    MICROMACRO_PARSE_COMMAND_LINE(app, argc, argv);

    try {
        if (tiny && particles_option->count())
            mm::throw_input_error("--tiny runs 40 particles and would ignore --particles ", particles,
                                  "; drop --particles, or drop --tiny for a run of that size");
        std::error_code ec;
        fs::create_directories(out_dir, ec);
        if (ec || !fs::is_directory(out_dir)) mm::throw_input_error("--out-dir ", out_dir, " is not a writable directory");
        const auto started = std::chrono::steady_clock::now();
        auto say = [&](const std::string& what) {
            std::fprintf(stderr, "[%6.0f s] %s\n", seconds_since(started), what.c_str());
        };

        biaxial::Config base;
        base.dim = 2;
        biaxial::apply_preset(base, "quick");
        base.particles = tiny ? 40 : particles;
        if (tiny) base.period = 0.02, base.relax = 0.005, base.output_interval = 2.5e-4;
        biaxial::validate(base);
        const double tc_mean = base.contact_duration();
        const double tc_small = mm::contact_duration(base.k, base.gamma0, 0.5 * mm::sphere_mass(base.density, base.radius_min));
        const double small_over_mean = tc_small / tc_mean;

        // Collision sweep.
        std::vector<CollisionRow> collisions;
        const std::vector<double> fractions = tiny ? std::vector<double>{10, 50} : std::vector<double>{10, 20, 50, 100, 200};
        for (const std::string b : {"mean pair", "smallest pair"})
            for (double f : fractions) {
                collisions.push_back(collision_row<mm::VelocityVerlet>(base, b, f));
                collisions.push_back(collision_row<mm::SymplecticEuler>(base, b, f));
                collisions.push_back(collision_row<mm::VelocityVerlet, float>(base, b, f));
            }
        say("collisions done");

        // Biaxial variants; the reference first.
        auto with = [&](auto change) {
            biaxial::Config c = base;
            change(c);
            return c;
        };
        const double slowest = 4 * base.period;
        const double finest = 200 / small_over_mean;  // t_c(smallest pair) / 200 in units of the mean pair's t_c
        std::vector<Variant> variants;
        variants.push_back({"reference", format("t_c(smallest)/200, T = %g s", slowest),
                            with([&](auto& c) { c.dt_fraction = finest, c.period = slowest; })});
        variants.push_back({"default", "the paper's choice: t_c(mean)/50, T = " + format("%g s", base.period), base});
        for (double f : fractions)
            if (f != 50) variants.push_back({"time step", format("t_c(mean)/%g", f), with([&](auto& c) { c.dt_fraction = f; })});
        for (double f : fractions)
            if (!(tiny && f > 50))
                variants.push_back({"time step", format("t_c(smallest)/%g", f) + format(" = t_c(mean)/%.0f", f / small_over_mean),
                                    with([&](auto& c) { c.dt_fraction = f / small_over_mean; })});
        variants.push_back({"integrator", "symplectic Euler, t_c(mean)/50", base, true});
        if (!tiny) variants.push_back({"integrator", "symplectic Euler, t_c(mean)/100", with([&](auto& c) { c.dt_fraction = 100; }), true});
        variants.push_back({"precision", "float storage, t_c(mean)/50", base, false, 1, true});
        if (!tiny)
            variants.push_back({"precision", "float storage, t_c(mean)/200", with([&](auto& c) { c.dt_fraction = 200; }), false, 1, true});
        for (double factor : {0.5, 2.0, 4.0, 8.0})
            if (!(tiny && factor > 2))
                variants.push_back({"loading period", format("T = %g s", factor * base.period),
                                    with([&](auto& c) { c.period = factor * base.period; })});
        // The loading's damping (the default: affine, 5e-2 kg/s, examples/biaxial/README.md, "Damping during the loading").
        for (double g : {0.0, 1e-2, 2e-1})
            variants.push_back({"damping", format("affine, gamma_b = %g kg/s", g), with([&](auto& c) { c.gamma_b = g; })});
        variants.push_back({"damping", "Eq. 30 (lab) 1e-4 kg/s, Eq. 18 gamma_w = 0.63 kg/s (the paper's)", with([&](auto& c) {
                                c.damping = "lab";
                                c.gamma_b = 1e-4;
                                c.wall_damping = 0.63;
                            })});
        // The floor: a change of dt by one part in a million gives other trajectories of the same
        // packings (the dynamics are chaotic); other seeds give other packings.
        variants.push_back({"floor", "default, dt x (1 + 1e-6)", with([&](auto& c) { c.dt_fraction = 50 / (1 + 1e-6); })});
        variants.push_back({"floor", "default, other packings", base, false, static_cast<unsigned long long>(seeds) + 1});

        std::vector<VariantResult> results;
        for (const auto& v : variants) {
            results.push_back(run_variant(v, seeds, jobs));
            say(v.group + ": " + v.label + format(" (%.1f s per run)", results.back().mean(&Outcome::seconds)) + results.back().failure);
        }
        const VariantResult& ref = results.front();
        if (!ref.failure.empty()) mm::throw_input_error("the reference run failed: ", ref.failure);

        std::vector<KernelRow> kernels;
        for (double w : {0.25, 0.5, 1.0, 2.0})
            kernels.push_back(kernel_row(ref.runs.front().relaxed, ref.runs.front().box_stress, w));
        say("kernels done");

        // ---- the Markdown ------------------------------------------------------------------
        auto rel = [](double x, double r) { return std::abs(x / r - 1); };
        std::ostringstream md;
        md << "# The speed-accuracy trade, measured\n\n"
           << "Generated by `build/examples/speed_accuracy " << (tiny ? "--tiny " : "") << "--seeds " << seeds
           << (jobs > 1 ? " --jobs " + std::to_string(jobs) : std::string()) << " --out-dir docs` (`examples/speed_accuracy/main.cpp`, "
           << format("%.0f", seconds_since(started)) << " s, " << jobs << (jobs > 1 ? " runs at a time" : " run at a time")
           << (tiny ? "; **--tiny run: 40 particles, numbers meaningless**" : "")
           << "). Every number below comes from that run; rerun it to regenerate this page and `speed-accuracy.svg`.\n\n"
           << "Parameters: the biaxial quick preset (the paper's parameters, Sec. 4: k = 1e5 N/m, gamma_0 = 0.1 kg/s, radii 0.5-1.5 mm, "
           << "rho = 2000 kg/m^3, mu = 0.5, p = 20 N/m), 2D, " << base.particles << " particles. t_c(mean) = "
           << format("%.3g s", tc_mean) << " (two mean particles), t_c(smallest) = " << format("%.3g s", tc_small) << " = "
           << format("%.3f", small_over_mean) << " t_c(mean): the paper's t_c/50 of the mean pair is t_c/"
           << format("%.1f", 50 * small_over_mean) << " of the smallest pair.\n\n";

        md << "## Two-particle collision against Eq. 22\n\n"
           << "Head-on, approach speed 0.1 m/s. Error of the measured restitution e and contact duration t_c against the "
           << "closed form (exact), the worst over 16 entry phases (where in a step the contact begins; at coarse steps "
           << "the phase decides much of the error). Cost: steps per contact of the smallest pair (the stiffest contact, "
           << "which the time step must resolve).\n\n"
           << "| dt | integrator | steps per t_c(smallest) | e error, mean pair | t_c error, mean pair | e error, smallest pair | t_c error, smallest pair |\n"
           << "|---|---|---|---|---|---|---|\n";
        for (const auto& r : collisions)
            md << "| t_c(" << (r.base == "mean pair" ? "mean" : "smallest") << ")/" << r.fraction << " | " << r.integrator << " | "
               << format("%.1f", r.steps_per_contact) << " | " << percent(r.e_error_mean) << " | " << percent(r.tc_error_mean) << " | "
               << percent(r.e_error_small) << " | " << percent(r.tc_error_small) << " |\n";
        md << "\nOblique frictional impacts, the tangential spring's error against dt: `oblique-impacts.md` "
           << "(`build/examples/oblique_impacts --out docs/oblique-impacts.md`).\n";

        md << "\n## Biaxial quick preset against a converged reference\n\n"
           << "Each row is " << seeds << " packing" << (seeds > 1 ? "s" : "") << " (seeds 1.." << seeds
           << "; the floor's other packings: seeds " << seeds + 1 << ".." << 2 * seeds << "), each a complete run (random "
           << "placement, preparation, loading to eps_zz = "
           << base.final_strain << " and relaxation) with one setting changed from the default. Reference: "
           << variants.front().label << ", velocity Verlet, double. Peak quantities come from rows smoothed over five "
           << "output intervals, during the motion. Each cell is the mean over the packings and, in brackets, its "
           << "difference from the reference's mean with the 95% confidence interval of that difference (Welch's t, "
           << "relative to the reference's mean; for the strain at the peak, absolute); **bold** where the interval "
           << "excludes zero, i.e. the setting is distinguishable from the reference. Wall gap: mean over the motion of "
           << "|sigma_wall_22 / sigma_22 - 1| (wall stress "
           << "against the inner box's contact stress). Residual: the energy books' residual at the end (relative to the "
           << "work put in). Seconds: one run's wall time (" << jobs << " run" << (jobs > 1 ? "s" : "")
           << " at a time). Float: the particle state stored in float, every force computed and summed in double "
           << "(`BasicSimulation<dim, float, ...>`); positions of a 3.5 cm box then resolve 2e-9 m against overlaps of ~4e-7 m, "
           << "and a particle moves only once its step takes it half that far, at about resolution / (2 dt): far "
           << "faster than the preparation's rest allows, so the float rows stop, and their message gives the numbers.\n\n"
           << "| group | setting | seconds | particle-steps | peak stress ratio | eps_zz at peak | max deviatoric fabric | "
              "C_n_2222 at peak (N/m) | wall gap | residual |\n"
           << "|---|---|---|---|---|---|---|---|---|---|\n";
        // The three peak quantities a setting is judged by.
        const std::vector<std::pair<const char*, double Outcome::*>> judged{
            {"peak stress ratio", &Outcome::peak_ratio}, {"deviatoric fabric", &Outcome::max_fabric}, {"C_n_2222", &Outcome::Cn_at_peak}};
        for (std::size_t i = 0; i < variants.size(); ++i) {
            const auto& r = results[i];
            const bool is_ref = i == 0;
            if (!r.failure.empty()) {
                md << "| " << variants[i].group << " | " << variants[i].label << " | stopped: " << r.failure << " |||||||\n";
                continue;
            }
            auto cell = [&](double Outcome::*field, const char* fmt) {
                std::string text = format(fmt, r.mean(field));
                if (is_ref) return text;
                const Difference d = difference(r, ref, field);
                const std::string diff = format("%+.1f%%", 100 * d.relative) + format(" +- %.1f%%", 100 * d.half_width);
                return text + " (" + (d.distinguishable() ? "**" + diff + "**" : diff) + ")";
            };
            std::string at_peak = format("%.4f", r.mean(&Outcome::strain_at_peak));
            if (!is_ref) {
                const Difference d = difference(r, ref, &Outcome::strain_at_peak);
                const double scale = std::abs(ref.mean(&Outcome::strain_at_peak));  // back to absolute strain
                const std::string diff = format("%+.4f", d.relative * scale) + format(" +- %.4f", d.half_width * scale);
                at_peak += " (" + (d.distinguishable() ? "**" + diff + "**" : diff) + ")";
            }
            md << "| " << variants[i].group << " | " << variants[i].label << " | " << format("%.1f", r.mean(&Outcome::seconds)) << " | "
               << format("%.3g", r.mean(&Outcome::particle_steps)) << " | " << cell(&Outcome::peak_ratio, "%.4f") << " | " << at_peak
               << " | " << cell(&Outcome::max_fabric, "%.4f") << " | " << cell(&Outcome::Cn_at_peak, "%.4g") << " | "
               << percent(r.mean(&Outcome::wall_gap)) << " | " << format("%.2e", r.mean(&Outcome::residual)) << " |\n";
        }
        // A sentence per group: which settings the packings tell apart from the reference, and
        // from the default (the reference differs from it in dt and T at once; a setting that
        // changes one of them is told apart from the default by that change alone).
        md << "\nAt " << seeds << " packings per setting, by group: distinguishable (the 95% interval of the difference of "
           << "the means excludes zero for the peak stress ratio, the deviatoric fabric or C_n_2222) from the reference, "
           << "and from the default:\n\n";
        const VariantResult& fallback = results[1];  // the default
        auto which = [&](const VariantResult& r, const VariantResult& against) {
            std::string names;
            for (const auto& [name, field] : judged)
                if (difference(r, against, field).distinguishable()) names += (names.empty() ? "" : ", ") + std::string(name);
            return names;
        };
        auto list = [](const std::vector<std::string>& v) {
            std::string t;
            for (std::size_t k = 0; k < v.size(); ++k) t += (k ? "; " : "") + v[k];
            return t.empty() ? std::string("none") : t;
        };
        for (std::size_t i = 1; i < variants.size();) {
            const std::string group = variants[i].group;
            std::vector<std::string> from_ref, from_default, stopped;
            bool any_ran = false;
            for (; i < variants.size() && variants[i].group == group; ++i) {
                if (!results[i].failure.empty()) {
                    stopped.push_back(variants[i].label);
                    continue;
                }
                any_ran = true;
                if (const auto w = which(results[i], ref); !w.empty()) from_ref.push_back(variants[i].label + " (" + w + ")");
                if (i == 1) continue;
                if (const auto w = which(results[i], fallback); !w.empty()) from_default.push_back(variants[i].label + " (" + w + ")");
            }
            md << "- **" << group << "**: ";
            if (!stopped.empty()) md << "Stopped: " << list(stopped) << ".";
            if (any_ran) {
                md << (stopped.empty() ? "" : " ") << "From the reference: " << list(from_ref) << ".";
                if (group != "default") md << " From the default: " << list(from_default) << ".";
            }
            md << "\n";
        }
        md << "\n## Loading rate on the paper preset\n\n"
           << "The rate as a trade of its own, on the paper preset (1950 particles): one prepared packing loaded at T = 1, "
           << "2, 4 and 8 s, the roughness and the gaps of the smoothed curves to the slowest run, with the cost of each: "
           << "[loading-rate.md](loading-rate.md) (`scripts/rate_convergence.sh`). The quick preset's rates with "
           << "confidence intervals are the loading period group above.\n";

        md << "\n## Coarse-graining kernel width\n\n"
           << "The reference run's relaxed end state, coarse-grained (Gaussian, `coarse_graining.hpp`) on a grid over the "
           << "packing (spacing the smaller of the width and half a mean diameter); statistics over the grid points in the inner box. rms: how far one grid point's sigma_22 typically lies from the inner-box "
           << "average; bias: how far the mean over the points lies. A wider kernel averages more particles (smaller rms) "
           << "but reaches into the wall zone and costs more.\n\n"
           << "| width (mean diameters) | seconds | rms | bias |\n|---|---|---|---|\n";
        for (const auto& k : kernels)
            md << "| " << k.width_in_diameters << " | " << format("%.3f", k.seconds) << " | " << percent(k.rms) << " | "
               << percent(k.bias) << " |\n";
        mm::io::write_whole_file(fs::path(out_dir) / "speed-accuracy.md", md.str());

        // ---- the plot ----------------------------------------------------------------------
        std::vector<Series> left{{"velocity Verlet", "#1f77b4", {}}, {"symplectic Euler", "#d62728", {}},
                                 {"velocity Verlet, float storage", "#9467bd", {}}};
        for (const auto& r : collisions) {
            if (r.base != "smallest pair") continue;
            const std::size_t series = r.integrator.find("float") != std::string::npos ? 2
                                       : r.integrator == mm::SymplecticEuler::name  ? 1
                                                                                    : 0;
            left[series].points.emplace_back(r.steps_per_contact, r.e_error_small);
        }
        std::vector<Series> right{{"time step, velocity Verlet", "#1f77b4", {}}, {"loading period T", "#2ca02c", {}}};
        double floor_error = 0;
        for (std::size_t i = 1; i < variants.size(); ++i) {
            if (!results[i].failure.empty()) continue;
            const double err = rel(results[i].mean(&Outcome::peak_ratio), ref.mean(&Outcome::peak_ratio));
            const double seconds = results[i].mean(&Outcome::seconds);
            if (variants[i].group == "time step" || variants[i].group == "default") right[0].points.emplace_back(seconds, err);
            if (variants[i].group == "loading period" || variants[i].group == "default") right[1].points.emplace_back(seconds, err);
            if (variants[i].group == "floor" && variants[i].label.find("dt x") != std::string::npos) floor_error = err;
        }
        for (auto& s : right) std::sort(s.points.begin(), s.points.end());
        // What converges despite the chaos: the energy books' residual against the time step.
        std::vector<Series> residual{{"velocity Verlet", "#1f77b4", {}}, {"symplectic Euler", "#d62728", {}}};
        for (std::size_t i = 0; i < variants.size(); ++i) {
            if (!results[i].failure.empty() || variants[i].single_precision) continue;
            const auto& g = variants[i].group;
            if (g == "time step" || g == "default" || g == "reference" || g == "integrator")
                residual[variants[i].symplectic_euler ? 1 : 0].points.emplace_back(variants[i].config.dt_fraction,
                                                                                  std::abs(results[i].mean(&Outcome::residual)));
        }
        for (auto& s : residual) std::sort(s.points.begin(), s.points.end());
        std::ostringstream svg;
        svg << "<svg xmlns='http://www.w3.org/2000/svg' width='1500' height='400' font-family='sans-serif'>\n"
            << "<rect width='1500' height='400' fill='white'/>\n"
            << svg_panel(0, 0, 500, 400, "Collision: restitution error (smallest pair)", "steps per contact", "|e / e_Eq22 - 1|", left)
            << svg_panel(500, 0, 500, 400, "Biaxial: error of the peak stress ratio", "seconds per run (one core)",
                         "relative error vs reference", right, floor_error)
            << svg_panel(1000, 0, 500, 400, "Biaxial: energy-balance residual", "t_c(mean) / dt", "|residual| / work in", residual)
            << "</svg>\n";
        mm::io::write_whole_file(fs::path(out_dir) / "speed-accuracy.svg", svg.str());
        say("wrote " + (fs::path(out_dir) / "speed-accuracy.md").string() + " and .svg");
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "speed_accuracy: %s\n", e.what());
        return 1;
    }
}
