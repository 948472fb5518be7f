#pragma once
// What an element test is: its preset (the path the periodic cell follows after the isotropic
// preparation), the packing and its contact law, the rate, and every parameter written once in a
// table that makes the command line, run.json and the saved states.
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "../parameter_table.hpp"

#include <micromacro/micromacro.hpp>

namespace element_test {

namespace mm = micromacro;

/// The presets: what the cell does after the isotropic preparation to the pressure p.
inline const std::vector<std::pair<std::string, std::string>>& presets() {
    static const std::vector<std::pair<std::string, std::string>> list{
        {"isotropic", "every axis compressed at the strain rate until the pressure reaches --target-pressure (or the volume "
                      "fraction --target-volume-fraction), then held there by the servo until the packing rests"},
        {"oedometric", "the last axis compressed at the strain rate to --strain, the other axes' lengths held (uniaxial strain)"},
        {"triaxial", "the last axis compressed at the strain rate to --strain, the other normal stresses held at p by the servo "
                     "(the paper's biaxial test in 2D without walls)"},
        {"shear-p", "simple shear (axis 1 moving along the last axis) at the strain rate to the shear strain --strain, the normal "
                    "stress across the shear plane held at p, the other lengths held"},
        {"shear-v", "simple shear as shear-p at constant volume: every length held"},
        {"probes", "small strain increments (--probe-strain) in several directions from the prepared state, each relaxed at "
                   "fixed strain: the incremental stiffness against the averaged C^n + C^t (Eq. 9) and the frozen affine probe"},
    };
    return list;
}

struct Config {
    int dim = 2;
    std::string preset = "shear-p";
    std::size_t particles = 400;
    double radius_min = 0.5e-3, radius_max = 1.5e-3;  // m
    double density = 2000.0;                           // kg/m^3 (sphere masses, also in 2D)
    double k = 1e5, gamma0 = 0.1;                      // N/m, kg/s (the linear law of Eq. 20-29)
    double mu = 0.5, kt_ratio = 0.2, gammat_ratio = 0.2;
    double mu_prepare = 0.0;          // friction while preparing: 0 gives the densest random packing
    double pressure = 1000.0;         // p: N/m in 2D, Pa in 3D
    double inertial_number = 1e-3;    // of the loading: sets the strain rate
    double strain = 1.0;              // the preset's final strain
    double target_pressure = 0.0;     // isotropic: 0 = 2 p
    double target_volume_fraction = 0.0;  // isotropic: stop at this volume fraction instead (0: by pressure)
    double probe_strain = 1e-4;       // size of each probe's strain increment
    double servo_time = 1.0;          // the servo corrects a stress error in this many contact durations
    double max_rate_factor = 10.0;    // the servo's largest rate over the loading's rate
    double gamma_b = 5e-2;            // kg/s: damping against the cell's flow (AffineDamping)
    double gamma_b_prepare = 5e-2;    // kg/s: the same while preparing (rattlers come to rest only by it)
    double dt_fraction = 50.0;        // dt = t_c / dt_fraction, t_c of two mean particles
    double start_volume_fraction = 0.3;  // the fresh packing's gas before the preparation
    double prepare_inertial_number = 1e-2;  // the preparation's largest compression rate, as an inertial number
    double rest_ratio = 1e-6;         // rest: kinetic energy below this fraction of the elastic energy
    double rows = 200;                // rows of the time series over the loading
    unsigned long long seed = 1;

    double mean_radius() const { return 0.5 * (radius_min + radius_max); }
    double mean_mass() const { return mm::sphere_mass(density, mean_radius()); }
    double contact_duration() const { return mm::contact_duration(k, gamma0, 0.5 * mean_mass()); }
    double time_step() const { return contact_duration() / dt_fraction; }
    /// The density the inertial number takes: in 2D the sphere mass per disk area, 4/3 rho a.
    double inertial_density() const { return dim == 2 ? 4.0 / 3.0 * density * mean_radius() : density; }
    /// The strain rate of inertial number I at the pressure `at`: I = rate d sqrt(rho / p), d the mean diameter.
    double rate_of(double I, double at) const { return I / (2.0 * mean_radius() * std::sqrt(inertial_density() / at)); }
    double rate() const { return rate_of(inertial_number, pressure); }
    double target_p() const { return target_pressure > 0 ? target_pressure : 2.0 * pressure; }
    /// The servos close a stress error in servo_time contact durations: their gain follows the
    /// packing's averaged stiffness (CellControl::following_stiffness). The steady lag of a
    /// component, its rate times that time times its stiffness C, is (rate t_c) (C/p) servo_time
    /// of p: docs/element-tests.md measures it.
    double servo_relaxation() const { return servo_time * contact_duration(); }
    /// The largest rate a servo asks for (1/s).
    double max_rate() const { return max_rate_factor * rate(); }
};

/// The defaults that depend on the dimension and the preset.
inline void apply_preset(Config& c, const std::string& preset) {
    c.preset = preset;
    c.particles = c.dim == 2 ? 400 : 1000;
    c.pressure = c.dim == 2 ? 1000.0 : 5e5;  // p / k = 1e-2 in 2D, p d / k = 1e-2 in 3D
    c.strain = preset == "oedometric" ? 0.02 : preset == "triaxial" ? 0.2 : preset == "isotropic" ? 0.05 : 1.0;
}

/// In run.json's order. --dim and --preset choose the defaults and are handled apart.
inline const micromacro::cli::ParameterTable<Config>& parameter_table() {
    using C = Config;
    static const micromacro::cli::ParameterTable<Config> table{
        {nullptr, "dim", "", &C::dim},
        {nullptr, "preset", "", &C::preset},
        {"--particles", "particles", "number of particles of a fresh packing (default 400 in 2D, 1000 in 3D)", &C::particles, true},
        {"--radius-min", "radius_min_m", "smallest radius of a fresh packing in m, radii uniform (default 0.5e-3)", &C::radius_min, true},
        {"--radius-max", "radius_max_m", "largest radius in m (default 1.5e-3)", &C::radius_max, true},
        {"--density", "density_kg_m3", "particle density in kg/m^3, sphere masses also in 2D (default 2000)", &C::density, true},
        {"--k", "k_N_m", "normal stiffness k of the linear law in N/m (default 1e5)", &C::k},
        {"--gamma0", "gamma0_kg_s", "normal damping gamma_0 of the linear law in kg/s (default 0.1)", &C::gamma0},
        {"--mu", "mu", "friction coefficient of the loading (default 0.5)", &C::mu},
        {"--kt-ratio", "kt_ratio", "k_t / k (default 0.2)", &C::kt_ratio},
        {nullptr, "gammat_ratio", "", &C::gammat_ratio},
        {"--mu-prepare", "mu_prepare", "friction while preparing (default 0: the densest random packing)", &C::mu_prepare, true},
        {"--pressure", "pressure",
         "p of the preparation, held by the servos (N/m in 2D, Pa in 3D; default 1000 and 5e5: p / k = 1e-2, p d / k = 1e-2)",
         &C::pressure},
        {"--inertial-number", "inertial_number",
         "I = rate d sqrt(rho/p) of the loading, d the mean diameter (2D: rho = 4/3 density a); sets the strain rate "
         "(default 1e-3)",
         &C::inertial_number},
        {"--strain", "strain",
         "the preset's final strain: axial for oedometric and triaxial, shear for shear-p and shear-v (default 0.02, 0.2, 1); "
         "isotropic: the largest volumetric strain before the target, refused beyond (default 0.05)",
         &C::strain},
        {"--target-pressure", "target_pressure", "isotropic: the pressure to compress to (default 2 p)", &C::target_pressure},
        {"--target-volume-fraction", "target_volume_fraction",
         "isotropic: compress to this volume fraction instead of a pressure (default 0: by pressure)", &C::target_volume_fraction},
        {"--probe-strain", "probe_strain", "probes: the size of each strain increment (default 1e-4)", &C::probe_strain},
        {"--servo-time", "servo_time",
         "the stress servos close an error in this many contact durations, their gain following the packing's averaged "
         "stiffness (default 1)",
         &C::servo_time},
        {"--max-rate-factor", "max_rate_factor", "the servo's largest strain rate over the loading's (default 10)",
         &C::max_rate_factor},
        {"--gamma-b", "gamma_b_kg_s", "damping against the cell's flow in kg/s during the loading (default 5e-2, the biaxial test's)",
         &C::gamma_b},
        {"--gamma-b-prepare", "gamma_b_prepare_kg_s",
         "damping against the cell's flow in kg/s while preparing, above 0: rattlers rest only by it (default 5e-2)",
         &C::gamma_b_prepare, true, nullptr, true},
        {"--dt-fraction", "dt_fraction", "dt = t_c / this, t_c of two mean particles (default 50)", &C::dt_fraction},
        {"--start-volume-fraction", "start_volume_fraction",
         "a fresh packing's gas before the preparation (default 0.3)", &C::start_volume_fraction, true},
        {"--prepare-inertial-number", "prepare_inertial_number",
         "the preparation's largest compression rate as an inertial number at p (default 1e-2)", &C::prepare_inertial_number, true},
        {"--rest-ratio", "rest_ratio", "at rest: kinetic energy below this fraction of the elastic energy (default 1e-6)",
         &C::rest_ratio},
        {"--rows", "rows", "rows of timeseries.csv over the loading (default 200)", &C::rows},
        {"--seed", "seed", "random seed of a fresh packing's placement (default 1)", &C::seed, true},
    };
    return table;
}

/// run.json's "parameters": the table, then the figures derived from it.
inline nlohmann::ordered_json parameters_json(const Config& c) {
    nlohmann::ordered_json j = micromacro::cli::parameters_json(parameter_table(), c);
    j["pressure_unit"] = c.dim == 2 ? "N/m" : "Pa";
    j["strain_rate_1_s"] = c.rate();
    j["time_step_s"] = c.time_step();
    j["contact_duration_s"] = c.contact_duration();
    return j;
}

/// The configuration saved in run.json or a state (`j` holds "parameters"). A file written before
/// --gamma-b-prepare existed was prepared with its --gamma-b.
inline Config config_from_json(const nlohmann::ordered_json& j) {
    const auto& saved = j.at("parameters");
    Config c = micromacro::cli::config_from_json(parameter_table(), saved, Config{});
    if (!saved.contains("gamma_b_prepare_kg_s")) c.gamma_b_prepare = c.gamma_b;
    return c;
}

/// Refuses what cannot run, naming the value, the limit and the fix.
inline void validate(const Config& c) {
    using mm::throw_input_error;
    bool known = false;
    for (const auto& p : presets()) known = known || p.first == c.preset;
    if (!known) throw_input_error("--preset '", c.preset, "' is not one of isotropic, oedometric, triaxial, shear-p, shear-v, probes");
    if (c.particles < 2) throw_input_error("--particles ", c.particles, " is too few; give at least 2");
    if (c.particles > 2000000) throw_input_error("--particles ", c.particles, " is more than 2e6, the most one core runs in a day");
    if (!(c.radius_min > 0 && c.radius_max >= c.radius_min))
        throw_input_error("radii [", c.radius_min, ", ", c.radius_max, "] m are invalid; need 0 < --radius-min <= --radius-max");
    auto positive = [](double v, const char* option, const char* fix) {
        if (!(v > 0) || !std::isfinite(v)) throw_input_error(option, " ", v, " must be a finite number above 0; ", fix);
    };
    positive(c.density, "--density", "give kg/m^3");
    positive(c.k, "--k", "give N/m");
    positive(c.pressure, "--pressure", "give N/m in 2D, Pa in 3D");
    positive(c.inertial_number, "--inertial-number", "1e-3 is quasi-static");
    positive(c.prepare_inertial_number, "--prepare-inertial-number", "1e-2 prepares in seconds");
    positive(c.dt_fraction, "--dt-fraction", "50 is the default");
    positive(c.servo_time, "--servo-time", "1 is the default");
    positive(c.max_rate_factor, "--max-rate-factor", "10 is the default");
    positive(c.rest_ratio, "--rest-ratio", "1e-6 is the default");
    positive(c.probe_strain, "--probe-strain", "1e-4 is the default");
    positive(c.gamma_b_prepare, "--gamma-b-prepare", "5e-2 is the default");
    for (const auto& [v, option] : {std::pair{c.gamma0, "--gamma0"}, {c.gamma_b, "--gamma-b"}, {c.mu, "--mu"},
                                    {c.mu_prepare, "--mu-prepare"}, {c.kt_ratio, "--kt-ratio"}})
        if (!(v >= 0) || !std::isfinite(v)) throw_input_error(option, " ", v, " must be a finite number of 0 or more");
    if (!(c.strain > 0 && c.strain < (c.preset == "oedometric" || c.preset == "triaxial" ? 0.9 : 100.0)))
        throw_input_error("--strain ", c.strain, " is out of range; give a strain above 0 (below 0.9 for an axial compression)");
    // Random sequential addition jams near 0.55 (disks) and 0.38 (spheres): the gas stays below.
    if (!(c.start_volume_fraction > 0 && c.start_volume_fraction <= (c.dim == 2 ? 0.5 : 0.35)))
        throw_input_error("--start-volume-fraction ", c.start_volume_fraction, " must lie in (0, ", c.dim == 2 ? 0.5 : 0.35,
                          "]: the gas is placed at random without overlaps, which jams near ", c.dim == 2 ? 0.55 : 0.38);
    if (c.target_volume_fraction != 0 && !(c.target_volume_fraction > 0 && c.target_volume_fraction < 1))
        throw_input_error("--target-volume-fraction ", c.target_volume_fraction, " must lie in (0, 1), or 0 to compress by pressure");
    if (c.target_pressure != 0 && !(c.target_pressure > c.pressure))
        throw_input_error("--target-pressure ", c.target_pressure, " must exceed --pressure ", c.pressure, " (or be 0: 2 p)");
    if (!(c.rows >= 1 && c.rows <= 1e6 && c.rows == std::floor(c.rows)))
        throw_input_error("--rows ", c.rows, " must be a whole number from 1 to 1e6");
    c.contact_duration();  // throws for an overdamped contact
}

}  // namespace element_test
