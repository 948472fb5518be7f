// oblique_impacts: how accurately the tangential spring resolves an oblique frictional impact at
// each time step, measured and written as docs/oblique-impacts.md.
//
//   oblique_impacts --out docs/oblique-impacts.md   (seconds)
//
// Two equal spheres (a = 1 mm, rho = 2000 kg/m^3, k = 1e5 N/m, k_t = 2e4 N/m, no dashpots), one at
// rest, the other arriving at 0.5 m/s with impact parameter b (the cases of a side-by-side
// comparison with LAMMPS's gran/hooke/history). The spin and the tangential velocity they part
// with are compared with the same impact at t_c/12800, over entry phases spread evenly through
// a step (where in a step the surfaces meet decides much of the error at coarse steps). Two
// tangential updates: the library's (the spring advanced by the half-step velocity, a new contact
// started at the time of touch) and, for comparison, the common first-order one (Eq. 26 with
// xi + v_t dt/2, the spring advanced by the end-of-step velocity, put at the Coulomb limit after
// sliding, a new contact half a step in).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "../command_line.hpp"

#include <micromacro/io/whole_file.hpp>
#include <micromacro/micromacro.hpp>

namespace mm = micromacro;

namespace {

/// The first-order update, for comparison only: the library's law with its force() replaced.
class EndOfStepSpring : public mm::CundallStrack {
public:
    using CundallStrack::CundallStrack;
    template <int dim, bool track_energy>
    mm::TangentialForce<dim> force(const mm::Vec<dim>& n, const mm::Vec<dim>& relative_velocity, double normal_velocity,
                                   double normal_force, double /*overlap*/, double dt, History<dim>& h) const {
        using V = mm::Vec<dim>;
        mm::TangentialForce<dim> out;
        const V stored = present_spring<dim>(n, h);
        const V vt = relative_velocity - n * normal_velocity;
        const V trial = -stiffness() * V(stored + (0.5 * dt) * vt) - damping() * vt;
        const double fn = std::max(normal_force, 0.0), trial_sq = trial.squaredNorm();
        const double static_limit = mu_static() * fn, dynamic_limit = mu_dynamic() * fn;
        const bool sliding = trial_sq > static_limit * static_limit ||
                             (h.sliding && trial_sq >= dynamic_limit * dynamic_limit && vt.dot(stored) >= 0.0);
        if (!sliding) {
            out.force = trial;
            keep(n, V(stored + dt * vt), h);
        } else {
            const double magnitude = std::sqrt(trial_sq);
            const V t = magnitude > 0.0 ? V(trial / magnitude) : V(V::Zero());
            out.force = dynamic_limit * t;
            keep(n, V(-(dynamic_limit / stiffness()) * t), h);
        }
        h.sliding = sliding;
        h.touching = true;
        out.sliding = sliding;
        return out;
    }
    /// A spring in the tangent plane of n into the history (2D: its component along the tangent).
    template <int dim>
    static void keep(const mm::Vec<dim>& n, const mm::Vec<dim>& spring, History<dim>& h) {
        if constexpr (dim == 2)
            h.spring = mm::tangent_of(n).dot(spring);
        else
            h.spring = spring;
    }
    /// Nothing added when a contact is found open: the plain last sample stands.
    template <int dim>
    mm::Vec<dim> opening_correction(const mm::Vec<dim>&, const History<dim>&, double, double, double) const {
        return mm::Vec<dim>::Zero();
    }
};

constexpr double a = 1e-3, rho = 2000.0, k = 1e5, kt = 2e4, speed = 0.5;

template <int dim, class Tangential>
mm::ObliqueImpact impact(double b, double mu, double steps_per_tc, double phase) {
    using Law = mm::ContactLaw<mm::LinearSpringDashpot, Tangential>;
    const double m = mm::sphere_mass(rho, a);
    const Law law{mm::LinearSpringDashpot(k, 0.0), Tangential(kt, 0.0, mu)};
    const double dt = mm::contact_duration(k, 0.0, m / 2) / steps_per_tc;
    return mm::measure_oblique_impact<dim>(law, m, a, speed, b, dt, phase, 300.0);
}

struct Errors {
    double spin_max = 0, spin_rms = 0, across_max = 0, across_rms = 0;
};

template <int dim, class Tangential>
Errors errors(double b, double mu, double steps_per_tc, int phases) {
    Errors e;
    for (int p = 0; p < phases; ++p) {
        const double phase = (p + 0.5) / phases;
        const auto ref = impact<dim, mm::CundallStrack>(b, mu, 12800, phase);
        const auto got = impact<dim, Tangential>(b, mu, steps_per_tc, phase);
        const double s = (got.target_spin - ref.target_spin).norm() / ref.target_spin.norm();
        const double v = (got.across - ref.across).norm() / ref.across.norm();
        e.spin_max = std::max(e.spin_max, s);
        e.across_max = std::max(e.across_max, v);
        e.spin_rms += s * s / phases;
        e.across_rms += v * v / phases;
    }
    e.spin_rms = std::sqrt(e.spin_rms);
    e.across_rms = std::sqrt(e.across_rms);
    return e;
}

// The processor, for the page's provenance (the numbers do not depend on it beyond the last bits).
std::string cpu_model() {
    std::ifstream in("/proc/cpuinfo");
    for (std::string line; std::getline(in, line);)
        if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
    return "unknown processor";
}

std::string sci(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.1e", v);
    return b;
}

struct Case {
    double b, mu;
};

template <int dim>
void table(std::ostream& md, const std::vector<Case>& cases, const std::vector<double>& steps, int phases) {
    md << "| b (mm), mu | update | error | " ;
    for (double s : steps) md << "t_c/" << s << " | ";
    md << "order | order, finest | least gain |\n|---|---|---|";
    for (std::size_t i = 0; i <= steps.size() + 2; ++i) md << "---|";
    md << "\n";
    for (const Case& c : cases) {
        std::vector<Errors> ours, first;
        for (double s : steps) {
            ours.push_back(errors<dim, mm::CundallStrack>(c.b, c.mu, s, phases));
            first.push_back(errors<dim, EndOfStepSpring>(c.b, c.mu, s, phases));
        }
        auto slope = [&](auto pick, const std::vector<Errors>& e, std::size_t from, std::size_t to) {
            char o[16];
            std::snprintf(o, sizeof o, "%.1f", std::log(pick(e[from]) / pick(e[to])) / std::log(steps[to] / steps[from]));
            return std::string(o);
        };
        auto row = [&](const char* name, const std::vector<Errors>& e, const char* what, auto pick) {
            md << "| " << c.b * 1e3 << ", " << c.mu << " | " << name << " | " << what << " | ";
            for (const Errors& x : e) md << sci(pick(x)) << " | ";
            // The slope over every step, and over the finest three, where it tends to the order.
            const std::size_t last = steps.size() - 1;
            md << slope(pick, e, 0, last) << " | " << slope(pick, e, last - 2, last) << " | ";
            if (&e == &ours) {  // the smallest ratio of the end-of-step update's error to this one's
                double least = std::numeric_limits<double>::infinity();
                for (std::size_t k = 0; k < steps.size(); ++k) least = std::min(least, pick(first[k]) / pick(ours[k]));
                char g[16];
                std::snprintf(g, sizeof g, "%.1f", least);
                md << g;
            }
            md << " |\n";
        };
        row("half-step (library)", ours, "spin, worst", [](const Errors& x) { return x.spin_max; });
        row("half-step (library)", ours, "spin, rms", [](const Errors& x) { return x.spin_rms; });
        row("half-step (library)", ours, "v_t, worst", [](const Errors& x) { return x.across_max; });
        row("end-of-step", first, "spin, worst", [](const Errors& x) { return x.spin_max; });
        row("end-of-step", first, "spin, rms", [](const Errors& x) { return x.spin_rms; });
        row("end-of-step", first, "v_t, worst", [](const Errors& x) { return x.across_max; });
    }
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"oblique_impacts: the tangential spring's error against the time step, as a Markdown page"};
    std::string out;
    int phases = 16;
    app.add_option("--out", out, "the Markdown file to write (e.g. docs/oblique-impacts.md)")->required();
    app.add_option("--phases", phases, "entry phases per case, spread evenly through a step")->check(CLI::Range(1, 1000));
    MICROMACRO_PARSE_COMMAND_LINE(app, argc, argv);

    const std::vector<Case> cases{{0.3e-3, 0.5}, {0.8e-3, 0.5}, {1.5e-3, 0.5}, {1.9e-3, 0.5}, {0.3e-3, 5.0}, {0.8e-3, 0.05}};
    const std::vector<double> steps{20, 50, 100, 200, 400};
    std::ostringstream md;
    md << "# Oblique impacts: the tangential spring against the time step\n\n"
       << "Made by `build/examples/oblique_impacts --out docs/oblique-impacts.md --phases " << phases
       << "` (the default build, on " << cpu_model() << "; seconds on one core). Two equal spheres (a = 1 mm, rho = 2000 kg/m^3, k = 1e5 N/m, k_t = 2e4 N/m, "
       << "mu as given, no dashpots), one at rest, the other arriving at 0.5 m/s with impact parameter b; in 3D "
       << "it also spins at 300 rad/s about its direction of flight. The error is that of the target's spin "
       << "and of the relative velocity across the flight (v_t) after the spheres part, relative to the same "
       << "impact at t_c/12800, over " << phases << " entry phases spread through a step: the worst and the "
       << "root mean square. The order is the slope of the error on log-log axes from t_c/20 to t_c/400, the "
       << "finest order its slope from t_c/100 to t_c/400; the least gain is the smallest ratio, over the steps, "
       << "of the end-of-step update's error to the library's.\n\n"
       << "The library's update (`CundallStrack`, docs/model.md): the spring advances by the half-step "
       << "velocity of velocity Verlet, as the positions do, a new contact starts from the time of touch, and a "
       << "contact's last evaluation before it opens gets the impulse of the force until the opening. "
       << "The end-of-step update, for comparison: Eq. 26 with xi + v_t dt/2, the "
       << "spring advanced by the end-of-step velocity alone, put at the Coulomb limit after sliding, a new "
       << "contact half a step in; first order.\n\n"
       << "Near head-on (b = 0.3 mm) the spring still carries a force when the normal force fades, and the "
       << "Coulomb limit drops to zero within about a step at t_c/50; with mu = 5 the spring holds until the "
       << "surfaces part. The step that finds the contact open adds the rest of the last evaluation's impulse, "
       << "the force until the opening (CundallStrack::opening_correction); the errors fall at second order overall, but not monotonically while "
       << "the last step's sliding is shorter than a step.\n\n"
       << "LAMMPS's gran/hooke/history on the same impacts and phases: [oblique-impacts-lammps.md](oblique-impacts-lammps.md) "
       << "(`scripts/oblique_impacts_lammps.sh`); first order, like the end-of-step update here where the spring "
       << "carries the contact, and the same as the library's update where the contact slides throughout (mu = 0.05: the "
       << "same digits in 2D). There the tangential force is mu_d f_n from first touch to the end, and what error is "
       << "left is the normal force's, sampled by velocity Verlet where it rises from and falls to zero within a step.\n\n## 2D\n\n";
    table<2>(md, cases, steps, phases);
    md << "\n## 3D\n\n";
    table<3>(md, cases, steps, phases);

    try {
        micromacro::io::write_whole_file(out, md.str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "oblique_impacts: %s\n", e.what());
        return 1;
    }
    std::printf("wrote %s\n", out.c_str());
    return 0;
}
