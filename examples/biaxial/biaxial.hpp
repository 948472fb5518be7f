#pragma once
// The paper's biaxial test (Sec. 4), in 2D and as a triaxial box in 3D.
//
// Preparation (Sec. 4.3.1): random non-overlapping particles in a box about twice the final size
// per side; the lower walls are fixed, the upper walls are stress-controlled at the pressure p
// and compress the packing until its kinetic energy is below 1e-6 of its elastic energy.
// Loading (Sec. 4.1): the top wall follows Eq. 17 (strain-controlled), the other upper walls stay
// stress-controlled at p (Eq. 18), the lower walls stay fixed; after T/2 the top wall stops and
// the packing relaxes. Averages (Sec. 4.4) are taken in the inner box, 10% left out next to each
// wall, with the contact-point rule.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include <micromacro/micromacro.hpp>

#include "../timeseries_row.hpp"
#include "scene.hpp"

namespace biaxial {

namespace mm = micromacro;

struct Config {
    int dim = 2;
    std::string preset = "quick";
    std::size_t particles = 300;
    double radius_min = 0.5e-3, radius_max = 1.5e-3;  // m
    double density = 2000.0;                           // kg/m^3 (sphere masses, also in 2D)
    std::string law = "linear";                        // linear (Eq. 20-29) or hertz-mindlin
    double k = 1e5, gamma0 = 0.1;                      // N/m, kg/s (linear)
    double mu = 0.5, kt_ratio = 0.2, gammat_ratio = 0.2;
    // hertz-mindlin: E and nu of the particles (E = 1e10 Pa gives the linear law's overlap at the
    // presets' pressures), and the restitution (the linear law's is 0.78 between mean particles)
    double young = 1e10, poisson = 0.25, restitution = 0.8;
    double pressure = 20.0;        // N/m in 2D, Pa in 3D
    double period = 0.1;           // T of Eq. 17 (s)
    double final_strain = 0.2;     // eps_zz at the end of the motion
    double relax = 0.02;           // s of relaxation after T/2
    double dt_fraction = 50.0;     // dt = t_c / dt_fraction, t_c of two mean particles
    unsigned long long seed = 1;
    std::string damping = "affine"; // while loading: lab (Eq. 30), affine (against the walls' mean flow) or local (Cundall)
    double gamma_b = 5e-2;          // lab or affine damping while loading (kg/s); see docs/loading-damping.md for the measurements
    double local_damping = 0.2;    // alpha of the local damping while loading
    double gamma_b_prepare = 1e-3; // background damping while preparing (kg/s); more slows the walls down
    double wall_mass = 1e-4;       // kg
    double wall_damping = 0.0;     // kg/s while loading (Eq. 18's gamma_w; the affine damping calms the packing, and a
                                   // damper anchored to the lab biases the controlled wall's mean load)
    double wall_follow_time = 0.0; // s: damper anchor follows the wall (0 = Eq. 18's lab anchor)
    double prepare_speed = 0.0;    // m/s: wall damping while preparing is p A / this speed (0 = automatic)
    double prepare_kinetic_ratio = 1e-6;
    double output_interval = 1e-3; // s between rows of the time series
    double box_factor = 2.0;       // initial box side over the expected final side
    double inner_margin = 0.1;     // averaging box: this fraction of each side left out next to each wall (the paper's 10%)
    bool wall_friction = false;    // walls use the particles' friction (default: smooth walls, principal axes)
    double mu_prepare = 0.1;       // friction while preparing: low gives the paper's volume fraction 0.82-0.84
    std::string prepare_walls = "upper"; // walls that compress while preparing: upper (the others stay) or both of each axis
    double max_prepare_time = 0.0; // s; 0 = 50 x the time a wall needs to cross the box at prepare_speed

    // Derived.
    double mean_radius() const { return 0.5 * (radius_min + radius_max); }
    double mean_mass() const { return mm::sphere_mass(density, mean_radius()); }
    bool hertz() const { return law == "hertz-mindlin"; }
    /// The overlap of two mean particles pressed together by p d^(dim-1), d the mean diameter:
    /// the overlap the side pressure gives, up to a factor of order one.
    double reference_overlap() const {
        const double force = pressure * std::pow(2.0 * mean_radius(), dim - 1);
        if (!hertz()) return force / k;
        // The elastic force alone: restitution 1 spares the law its search for the damping.
        return mm::HertzMindlin(young, poisson, 1.0, 0.0).overlap_for_force(force, 0.5 * mean_radius());  // R* = a/2
    }
    /// Stiffnesses and dampings between two mean particles: the linear law's, or Hertz-Mindlin's
    /// tangent ones at the reference overlap (those of the packing's small oscillations).
    mm::StiffnessBound contact_springs() const {
        if (!hertz()) return {k, gamma0, kt_ratio * k, gammat_ratio * gamma0};
        const double R = 0.5 * mean_radius();
        return mm::HertzMindlin(young, poisson, restitution, 0.0, reference_overlap() / R).stiffness_bound(R, 0.5 * mean_mass());
    }
    /// t_c of Eq. 22 for two mean particles, with Hertz-Mindlin's tangent stiffness and damping
    /// at the reference overlap (its collisions there last about as long).
    double contact_duration() const {
        const mm::StiffnessBound s = contact_springs();
        return mm::contact_duration(s.normal_stiffness, s.normal_damping, 0.5 * mean_mass());
    }
    double restitution_coefficient() const {
        return hertz() ? restitution : mm::restitution(k, gamma0, 0.5 * mean_mass());
    }
    double time_step() const { return contact_duration() / dt_fraction; }
    double rotational_damping(double gamma) const { return 0.4 * gamma * mean_radius() * mean_radius(); }
    /// p / k in 2D (p in N/m), p d / k in 3D (p in Pa, d the mean diameter): the overlap over the
    /// radius, up to a factor. After preparation the largest overlap of 60 particles is 8-11 p/k of
    /// the smaller radius at p/k = 1e-2 and up to 36 p/k below (tests/tools/biaxial_pressures.cpp).
    /// With Hertz-Mindlin, the reference overlap over the mean diameter (which it is for the linear law).
    double pressure_over_stiffness() const {
        if (hertz()) return reference_overlap() / (2.0 * mean_radius());
        return dim == 2 ? pressure / k : pressure * 2 * mean_radius() / k;
    }
    /// The side of the prepared box, expected from the particles' volume at the dense packing's
    /// volume fraction (0.84 of disks, 0.64 of spheres).
    double expected_side() const {
        double v = 0.0;  // mean particle volume (per unit depth in 2D), radii uniform in [min, max]
        for (int b = 0; b < 1000; ++b) {
            const double a = radius_min + (radius_max - radius_min) * (b + 0.5) / 1000;
            v += (dim == 2 ? mm::DimTraits<2>::particle_volume(a) : mm::DimTraits<3>::particle_volume(a)) / 1000;
        }
        return std::pow(particles * v / (dim == 2 ? 0.84 : 0.64), 1.0 / dim);
    }
    /// The inertial number I = (d eps/dt) d sqrt(rho / p) at the peak rate of Eq. 17, eps_f pi / T, with
    /// the mean diameter d; in 2D rho is the sphere mass per disk area, 4/3 rho a.
    double inertial_number() const {
        const double rho = dim == 2 ? 4.0 / 3.0 * density * mean_radius() : density;
        return final_strain * M_PI / period * 2.0 * mean_radius() * std::sqrt(rho / pressure);
    }
    /// The walls' speed while preparing: 5 m/s, slower below p/k = 1e-5 in proportion to p/k,
    /// because the walls bring kinetic energy ~ v^2 into a packing whose elastic energy, against
    /// which rest is judged, falls as (p/k)^2.
    double wall_speed_prepare() const {
        return prepare_speed > 0 ? prepare_speed : 5.0 * std::min(1.0, pressure_over_stiffness() / 1e-5);
    }
    /// The preparing walls' damper, p A / wall_speed_prepare() with A the face of a box of side L:
    /// a terminal speed of wall_speed_prepare() at that area.
    double prepare_wall_damping(double L) const { return pressure * std::pow(L, dim - 1) / wall_speed_prepare(); }
};

/// The presets of the issue: the paper's N = 1950 at T = 1 s, and a quick run of the same physics.
inline void apply_preset(Config& c, const std::string& name) {
    c.preset = name;
    if (name == "paper") {
        c.particles = c.dim == 2 ? 1950 : 12500;
        c.period = 1.0;
        c.relax = 0.1;
        c.output_interval = 1e-3;
    } else if (name == "quick") {
        // A triaxial box about 20 mean diameters wide (the 2D quick box is 17): in boxes of 8-18
        // diameters the looser layers at the walls leave the inner box's stress of some packings
        // 3-14% off the walls' (docs/loading-damping.md).
        c.particles = c.dim == 2 ? 300 : 8000;
        c.period = 0.1;
        c.relax = 0.02;
        c.output_interval = 5e-4;
    } else {
        mm::throw_input_error("--preset '", name, "' is unknown; use paper or quick");
    }
    if (c.dim == 3) {
        c.pressure = 1e4;  // p d / k = 2e-4 as in the paper's 2D p / k
        // Opposite walls close in together: compressed from its upper walls only, a triaxial box
        // keeps a lateral gradient that biases the inner box against the walls by up to 5%.
        c.prepare_walls = "both";
    }
}

/// Refuses a configuration before any work starts.
/// Steps between two rows of the time series with time step `dt` (the output interval, rounded
/// to whole steps).
inline std::size_t steps_per_row(const Config& c, double dt) {
    return std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(c.output_interval / dt)));
}
/// Rows of the time series of a loading that lasts `loading` seconds, the first at its start.
inline std::size_t loading_rows(const Config& c, double dt, double loading) {
    return 1 + static_cast<std::size_t>(std::ceil(loading / (steps_per_row(c, dt) * dt)));
}

inline void validate(const Config& c) {
    using mm::throw_input_error;
    if (c.dim != 2 && c.dim != 3) throw_input_error("--dim ", c.dim, " is invalid; use 2 or 3");
    if (c.particles < 2) throw_input_error("--particles ", c.particles, " is too few; use at least 2");
    mm::require_positive(c.pressure, "--pressure", "the side pressure p must be > 0 (N/m in 2D, Pa in 3D)");
    if (c.law != "linear" && !c.hertz())
        throw_input_error("--law '", c.law, "' is unknown; use linear (Eq. 20-29) or hertz-mindlin");
    if (c.hertz()) {  // before anything derived from the law
        mm::require_positive(c.young, "--young", "give Young's modulus E of the particles in Pa");
        if (!(c.poisson > -1.0 && c.poisson < 0.5))
            throw_input_error("--poisson ", c.poisson, " is outside (-1, 0.5); e.g. 0.25 for glass");
        if (!(c.restitution > 0.0 && c.restitution <= 1.0))
            throw_input_error("--restitution ", c.restitution, " is outside (0, 1]; use 1 for elastic contacts");
    }
    if (c.pressure_over_stiffness() > 1e-2) {
        if (c.hertz())
            throw_input_error("--pressure ", c.pressure, " with --young ", c.young, " Pa presses two mean particles ",
                              c.pressure_over_stiffness(), " of their diameter into each other, above 1e-2: the largest "
                              "overlaps would exceed 10-20% of a radius, beyond the small overlaps of Hertz's law; use --pressure <= ",
                              c.pressure * std::pow(1e-2 / c.pressure_over_stiffness(), 1.5), " or --young >= ",
                              c.young * std::pow(c.pressure_over_stiffness() / 1e-2, 1.5));
        throw_input_error("--pressure ", c.pressure, " gives p/k = ", c.pressure_over_stiffness(), (c.dim == 3 ? " (p d / k in 3D)" : ""),
                          ", above 1e-2: the largest overlaps would exceed 10-20% of a radius (they reach 8-11 p/k "
                          "at 1e-2), beyond the small overlaps the linear contact law assumes; use --pressure <= ",
                          1e-2 * c.pressure / c.pressure_over_stiffness());
    }
    if (!(c.final_strain > 0.0 && c.final_strain < 1.0))
        throw_input_error("--final-strain ", c.final_strain, " is invalid; the strain eps_zz = 1 - z/z0 must be in (0, 1)");
    mm::require_positive(c.period, "--period", "give T of Eq. 17 in s");
    // The run's limits, each naming the option at fault and the value that would do.
    if (c.particles > 100'000'000)
        throw_input_error("--particles ", c.particles, " is beyond this program's 1e8 (about 1 kB each in memory); "
                          "use fewer, or the library directly");
    const double dt = c.time_step(), d_max = 2.0 * c.radius_max;
    if (c.inertial_number() > 1.0)
        throw_input_error("--period ", c.period, " s loads at an inertial number of ", c.inertial_number(),
                          " at the peak rate, above 1: the top wall outruns the packing (a quasi-static test needs "
                          "I << 1, the paper's T = 1 s gives 5e-4); use --period >= ", c.period * c.inertial_number());
    if (const double side = c.expected_side(); (1.0 - c.final_strain) * side < 2.0 * d_max) {
        // The side grows as particles^(1/dim); a strain bound below 0.01 is no way out.
        const double needed = std::ceil(c.particles * std::pow(2.0 * d_max / ((1.0 - c.final_strain) * side), c.dim));
        const double strain = std::floor(100 * (1.0 - 2.0 * d_max / side)) / 100;
        std::ostringstream fix;
        fix << "use --particles >= " << needed;
        if (strain >= 0.01) fix << " or --final-strain <= " << strain;
        throw_input_error("--final-strain ", c.final_strain, " leaves the box about ", (1.0 - c.final_strain) * side,
                          " m high, less than 2 of the largest particles (", d_max, " m each): no packing is left between "
                          "the walls; ", fix.str());
    }
    mm::require_non_negative(c.relax, "--relax", "give the relaxation time after T/2 in s");
    mm::require_non_negative(c.mu, "--mu", "use 0 for frictionless particles");
    mm::require_positive(c.kt_ratio, "--kt-ratio", "k_t / k must be > 0");
    if (!(c.dt_fraction >= 5.0)) throw_input_error("--dt-fraction ", c.dt_fraction, " is too small; dt = t_c / fraction needs fraction >= 5");
    if (c.damping != "lab" && c.damping != "affine" && c.damping != "local")
        throw_input_error("--damping '", c.damping, "' is unknown; use lab (Eq. 30), affine (against the walls' mean flow) or local (Cundall's)");
    mm::require_non_negative(c.gamma_b, "--gamma-b", "use 0 for no background damping");
    if (!(c.local_damping >= 0.0 && c.local_damping < 1.0))
        throw_input_error("--local-damping ", c.local_damping, " is outside [0, 1); it is the fraction of each force component "
                          "taken against the motion (0.2 in YADE's examples)");
    mm::require_non_negative(c.gamma_b_prepare, "--gamma-b-prepare", "use 0 for no background damping");
    mm::require_non_negative(c.mu_prepare, "--mu-prepare", "use 0 for frictionless particles while preparing");
    if (c.prepare_walls != "upper" && c.prepare_walls != "both")
        throw_input_error("--prepare-walls '", c.prepare_walls, "' is unknown; use upper (the lower walls stay) or both "
                          "(opposite walls close in together)");
    // A drag gamma on the lightest particle takes gamma dt / m of its velocity per step; at 1 or
    // more the explicit drag overshoots (the run would blow up and blame the time step).
    const double m_min = mm::sphere_mass(c.density, c.radius_min);
    for (const auto& [gamma, name] : {std::pair{c.gamma_b, "--gamma-b"}, std::pair{c.gamma_b_prepare, "--gamma-b-prepare"}})
        if (gamma * dt / m_min >= 1.0)
            throw_input_error(name, " ", gamma, " kg/s would take ", gamma * dt / m_min, " of the lightest particle's "
                              "velocity per time step (mass ", m_min, " kg, dt = ", dt, " s), 1 or more: the drag overshoots; use ",
                              name, " < ", 0.5 * m_min / dt, " (the defaults are 5e-2 and 1e-3)");
    mm::require_positive(c.wall_mass, "--wall-mass", "give m_w of Eq. 18 in kg");
    // The stiffnesses of the checks below: the linear law's, or Hertz-Mindlin's at the reference
    // overlap (the engine checks its own bound at the law's largest overlap when it prepares).
    const mm::StiffnessBound springs = c.contact_springs();
    {  // the controlled wall on one particle is an oscillator of sqrt(k (1/m_w + 1/m)) (see stable_time_step)
        const double k = springs.normal_stiffness, omega = std::sqrt(k * (1.0 / c.wall_mass + 1.0 / m_min));
        if (omega * dt >= 2.0)
            throw_input_error("--wall-mass ", c.wall_mass, " kg is too light for dt = ", dt, " s: the wall on a contact of "
                              "stiffness k oscillates at omega dt = ", omega * dt, ", above the stable 2; use --wall-mass >= ",
                              1.0 / (1.0 / (k * dt * dt) - 1.0 / m_min), " (the default is 1e-4)");
    }
    {  // while preparing, the walls' damper p A / v grows with the starting box's face A: a wall too
       // light for it overshoots at every step (the engine's stress_wall_time_step_limit refuses it)
        const double L = c.box_factor * c.expected_side(), speed = c.wall_speed_prepare(), gamma = c.prepare_wall_damping(L);
        auto limit = [&](double m) { return mm::stress_wall_time_step_limit(springs.normal_stiffness, m, gamma, 1.0 / m_min); };
        if (dt > limit(c.wall_mass)) {
            double light = c.wall_mass, heavy = 2.0 * c.wall_mass;  // the lightest stable mass, bracketed
            while (dt > limit(heavy)) light = heavy, heavy *= 2.0;
            for (int k = 0; k < 60; ++k) (dt > limit(0.5 * (light + heavy)) ? light : heavy) = 0.5 * (light + heavy);
            const double digit = std::pow(10.0, std::floor(std::log10(heavy)) - 2);
            heavy = std::ceil(heavy / digit) * digit;  // three digits, rounded up: stable as printed
            throw_input_error("--wall-mass ", c.wall_mass, " kg is too light for the preparation's wall damping of ", gamma,
                              " kg/s (p A / --prepare-speed ", speed, " m/s, A the starting box's face ", std::pow(L, c.dim - 1),
                              c.dim == 2 ? " m" : " m^2", "): the wall is stable up to dt = ", limit(c.wall_mass), " s, and dt = ", dt,
                              " s; use --wall-mass >= ", heavy, " (the default is 1e-4)");
        }
    }
    {  // the tangential spring between the two lightest particles, turning (as the engine's stable_time_step)
        const double mobility = 2.0 * 3.5 / m_min;  // 1/m + a^2/I per particle, I = 2/5 m a^2
        const double limit = mm::tangential_time_step_limit<mm::VelocityVerlet>(
            mm::CundallStrack(springs.tangential_stiffness, springs.tangential_damping, 0.0), mobility);
        if (dt > limit) {
            if (c.hertz())  // Mindlin's k_t / k_n is 2 (1 - nu) / (2 - nu): only a smaller step helps
                throw_input_error("--dt-fraction ", c.dt_fraction, " makes dt = ", dt, " s, above the tangential spring's "
                                  "stable ", limit, " s between the two lightest particles; use --dt-fraction >= ",
                                  c.dt_fraction * dt / limit);
            throw_input_error("--kt-ratio ", c.kt_ratio, " makes the tangential spring too stiff for dt = ", dt,
                              " s: between the two lightest particles it is stable up to dt = ", limit, " s; use --kt-ratio <= ",
                              c.kt_ratio * (limit / dt) * (limit / dt), " or --dt-fraction >= ", c.dt_fraction * dt / limit,
                              " (the paper's k_t / k is 0.2)");
        }
    }
    {  // a wall so heavy that p A cannot move it across the box within the preparation's time
        const double L = c.box_factor * c.expected_side(), area = std::pow(L, c.dim - 1);
        const double crossing = std::sqrt(2.0 * 0.5 * L * c.wall_mass / (c.pressure * area));  // from rest, no damping
        const double allowed = c.max_prepare_time > 0 ? c.max_prepare_time : 50.0 * L / c.wall_speed_prepare();
        if (crossing > allowed)
            throw_input_error("--wall-mass ", c.wall_mass, " kg is too heavy: pushed by p A alone it needs ", crossing,
                              " s to close the box, longer than the preparation's ", allowed, " s; use --wall-mass <= ",
                              c.wall_mass * (allowed / crossing) * (allowed / crossing) / 4, " (the default is 1e-4)");
    }
    if (const double steps = (0.5 * c.period + c.relax) / dt; steps > 1e9) {
        // A larger dt helps only down to --dt-fraction's minimum of 5; beyond, the loading must be shorter.
        const double fraction = c.dt_fraction * 1e9 / steps, longest = 1e9 * dt * c.dt_fraction / 5.0;
        std::ostringstream fix;
        if (fraction >= 5.0) {
            fix << "use --dt-fraction <= " << fraction << " (the paper's is 50)";
        } else {
            fix << "even the largest step (--dt-fraction 5) allows T/2 + --relax of at most " << longest << " s; use";
            if (c.relax < longest) fix << " --period <= " << 2.0 * (longest - c.relax);
            if (c.relax < longest && 0.5 * c.period < longest) fix << " or";
            if (0.5 * c.period < longest) fix << " --relax <= " << longest - 0.5 * c.period;
            if (c.relax >= longest && 0.5 * c.period >= longest) fix << " a shorter --period and --relax";
        }
        throw_input_error("--period ", c.period, " s and --relax ", c.relax, " s with dt = ", dt, " s (--dt-fraction ",
                          c.dt_fraction, ") make ", steps, " steps for the loading alone, more than 1e9 (days of computing); ",
                          fix.str());
    }
    mm::require_non_negative(c.wall_damping, "--wall-damping", "give gamma_w of Eq. 18 in kg/s");
    mm::require_non_negative(c.wall_follow_time, "--wall-follow-time", "use 0 for Eq. 18's damper");
    mm::require_non_negative(c.prepare_speed, "--prepare-speed", "give the walls' speed while preparing in m/s (0 = automatic)");
    if (!(c.inner_margin >= 0.0 && c.inner_margin < 0.5))
        throw_input_error("--inner-margin ", c.inner_margin, " is outside [0, 0.5); it is the fraction of each side left out "
                          "next to each wall (the paper's 0.1)");
    mm::require_positive(c.output_interval, "--output-interval", "give the time between rows in s");
    const double loading = 0.5 * c.period + c.relax;
    if (c.output_interval < dt)
        throw_input_error("--output-interval ", c.output_interval, " s is shorter than the time step dt = ", dt,
                          " s: rows cannot come more often than steps; use --output-interval >= ", dt);
    if (c.output_interval > loading)
        throw_input_error("--output-interval ", c.output_interval, " s is longer than the loading and relaxation (",
                          loading, " s): the time series would have no row but the first; use --output-interval <= ", loading / 100);
    if (loading / c.output_interval > 1e6)
        throw_input_error("--output-interval ", c.output_interval, " s gives ", loading / c.output_interval,
                          " rows (about 2 kB each), more than 1e6; use --output-interval >= ", loading / 1e6);
    if (!(c.radius_min > 0.0 && c.radius_max >= c.radius_min))
        throw_input_error("radii [", c.radius_min, ", ", c.radius_max, "] are invalid; need 0 < min <= max");
    c.contact_duration();  // throws for an overdamped contact
}

using micromacro::cli::Row;

/// `Integrator` and the storage precision `Real` are the choices the speed-accuracy table
/// compares; the biaxial program uses the defaults. A float run accepts its coarse positions.
/// `Law` is the linear law of Eq. 20-29 (mm::FrictionalLinear, Config::law "linear") or
/// mm::HertzMindlin ("hertz-mindlin"); the program chooses it from the configuration.
template <int dim, class Integrator = mm::VelocityVerlet, class Real = double, class Law = mm::FrictionalLinear>
class Experiment {
public:
    static_assert(std::is_same_v<Law, mm::FrictionalLinear> || std::is_same_v<Law, mm::HertzMindlin>);
    // The damping policies a run may choose; those it does not use stay at zero and cost no pass.
    using Sim = mm::BasicSimulation<dim, Real, Law, mm::Walls<dim>, Integrator, mm::LinkedCells, mm::BackgroundDamping,
                                    mm::AffineDamping, mm::LocalDamping>;
    using V = mm::Vec<dim>;
    static constexpr int up = dim - 1;  // the loaded axis (the paper's z, index 2)

    explicit Experiment(const Config& c)
        : c_(checked_law(c)), sim_(make_law(c, c.mu), {}, {}, {}, {}, mm::BackgroundDamping(0.0, 0.0), mm::AffineDamping(0.0, 0.0),
                      mm::LocalDamping(0.0)) {
        if constexpr (std::is_same_v<Real, float>) sim_.allow_coarse_positions(true);
    }

    Sim& simulation() { return sim_; }
    const Config& config() const { return c_; }

    /// Places the particles and walls of the preparation.
    void build() {
        const double L = c_.box_factor * c_.expected_side();
        std::mt19937_64 rng(c_.seed);
        std::uniform_real_distribution<double> U(0.0, 1.0);
        auto& p = sim_.particles();
        p.reserve(c_.particles);
        std::vector<V> placed;
        std::vector<double> radii;
        // Random sequential placement, each new particle checked against the particles placed so
        // far. Two particles overlap only if their centres lie within two largest radii, so the
        // placed ones are kept in cells at least that wide (a list per cell: `first`, `next`) and
        // only the new one's cell and its neighbours are checked: the decisions of checking every
        // placed particle, in time linear in N instead of quadratic (3D, 100 000 spheres: 0.3 s, not 16 s).
        // At most 1e7 cells (wider cells hold more particles each, and decide the same).
        const int cells = std::max(1, static_cast<int>(std::min(L / (2.0 * c_.radius_max), std::pow(1e7, 1.0 / dim))));
        const double cell = L / cells;
        auto cell_of = [&](double x) { return std::min(cells - 1, static_cast<int>(x / cell)); };
        std::vector<std::size_t> first(static_cast<std::size_t>(std::pow(cells, dim)), SIZE_MAX), next;
        for (std::size_t tries = 0; placed.size() < c_.particles; ++tries) {
            if (tries > 1000 * c_.particles)
                mm::throw_input_error("could not place ", c_.particles, " particles without overlap in the initial box; "
                                              "raise --box-factor");
            const double a = c_.radius_min + (c_.radius_max - c_.radius_min) * U(rng);
            V x;
            std::array<int, dim> home;
            std::size_t home_cell = 0;  // home's index among the cells, axis 0 fastest
            for (int k = 0; k < dim; ++k) x[k] = a + (L - 2 * a) * U(rng), home[k] = cell_of(x[k]);
            for (int k = dim - 1; k >= 0; --k) home_cell = home_cell * cells + static_cast<std::size_t>(home[k]);
            bool free = true;
            for (int around = 0; around < (dim == 2 ? 9 : 27) && free; ++around) {
                std::size_t c = 0;
                bool inside = true;
                for (int k = dim - 1, rest = around; k >= 0; --k, rest /= 3) {
                    const int ck = home[k] + rest % 3 - 1;
                    inside = inside && ck >= 0 && ck < cells;
                    c = c * cells + static_cast<std::size_t>(ck);
                }
                if (!inside) continue;
                for (std::size_t j = first[c]; j != SIZE_MAX && free; j = next[j]) free = (x - placed[j]).norm() > a + radii[j];
            }
            if (!free) continue;
            next.push_back(first[home_cell]);
            first[home_cell] = placed.size();
            placed.push_back(x);
            radii.push_back(a);
            p.add(x, a, mm::sphere_mass(c_.density, a));
        }
        auto& walls = sim_.walls();
        for (int k = 0; k < dim; ++k) {
            const bool both = c_.prepare_walls == "both";
            walls.add_axis_aligned(k, true, 0.0, both ? prepare_motion(L) : mm::WallMotion{}).frictionless = !c_.wall_friction;
            walls.add_axis_aligned(k, false, L, prepare_motion(L)).frictionless = !c_.wall_friction;
        }
        sim_.template body_force<mm::BackgroundDamping>() =
            mm::BackgroundDamping(c_.gamma_b_prepare, c_.rotational_damping(c_.gamma_b_prepare));
        sim_.law() = make_law(c_, c_.mu_prepare);
        sim_.set_time_step(c_.time_step());
        sim_.sort_spatially();  // placed in random order; neighbours close in memory run faster
        sim_.prepare();
    }

    /// Compresses isotropically until the kinetic energy of the particles and of the walls is below
    /// the configured fraction of the elastic energy and every controlled wall's push is within
    /// 1e-4 of p A; returns the simulated time it took. `scene` steps the built scene (SerialScene:
    /// this experiment's engine).
    template <class Scene>
    double prepare(Scene& scene, const std::function<void()>& progress = {}) {
        const double limit = c_.max_prepare_time > 0 ? c_.max_prepare_time
                                                     : 50.0 * scene.walls()[1].coordinate() / c_.wall_speed_prepare();
        const double start = scene.time();
        while (true) {
            scene.run(1000);
            if (progress) progress();
            const auto e = scene.energy();
            double wall_kinetic = 0.0;
            double imbalance = 0.0;  // of the controlled walls' push against p A: a light wall moves with little energy
            for (const auto& w : scene.walls()) {
                wall_kinetic += 0.5 * c_.wall_mass * w.speed * w.speed;
                if (const auto* s = std::get_if<mm::StressControlled>(&w.motion)) {
                    const double load = s->pressure * scene.walls().area(w, scene.box());
                    imbalance = std::max(imbalance, std::abs(-w.force.dot(w.normal) / load - 1.0));
                }
            }
            if (e.elastic_normal > 0.0 && e.kinetic() < c_.prepare_kinetic_ratio * e.potential() &&
                wall_kinetic < c_.prepare_kinetic_ratio * e.potential() && imbalance <= 1e-4)
                break;
            if (scene.time() - start > limit)
                mm::throw_input_error("the preparation did not come to rest within ", limit,
                                              " s (kinetic / elastic energy = ", e.kinetic() / e.potential(),
                                              ", largest wall push off p A by ", imbalance, ")", rest_advice(e));
        }
        return scene.time() - start;
    }
    /// What to change when the preparation has not come to rest: the damping or the speed, unless
    /// the particles are stored in float and the rest asked for lies below what float resolves. A
    /// particle whose step moves it by less than half the position resolution R stays where it is
    /// while its speed grows, so it moves at about R / (2 dt) or not at all: a floor that a smaller
    /// dt raises, and a float packing's rms speed stays at a fraction of it
    /// (tests/tools/biaxial_float_rest.cpp).
    std::string rest_advice(const mm::EnergyState& e) const {
        const std::string damping = "; raise --gamma-b-prepare or lower --prepare-speed";
        if constexpr (std::is_same_v<Real, double>) {
            return damping;
        } else {
            double mass = 0.0;
            for (const auto m : sim_.particles().mass()) mass += double(m);
            const double floor = sim_.position_resolution() / (2.0 * sim_.time_step());
            const double needed = std::sqrt(2.0 * c_.prepare_kinetic_ratio * e.potential() / mass);
            if (needed >= floor) return damping;
            std::ostringstream out;
            out.precision(3);
            out << "; positions stored in " << sizeof(Real) * 8 << " bits resolve " << sim_.position_resolution()
                << " m here, so a particle moves only once its step takes it half that far, at " << floor << " m/s (dt = "
                << sim_.time_step() << " s); rest needs rms speeds below " << needed << " m/s, and they are "
                << std::sqrt(2.0 * e.kinetic() / mass) << " m/s: store the particles in double precision";
            return out.str();
        }
    }

    double prepare(const std::function<void()>& progress = {}) {
        SerialScene<Sim> scene(sim_);
        return prepare(scene, progress);
    }

    /// Switches the walls and damping to the loading of Sec. 4.1 and records the reference box.
    void start_loading() {
        auto& walls = sim_.walls();
        for (int k = 0; k < dim; ++k) {
            auto& lower = walls[2 * k];
            auto& upper = walls[2 * k + 1];
            box0_[k] = upper.coordinate() - lower.coordinate();
            for (auto* w : {&lower, &upper}) {
                w->initial_offset = w->offset;
                w->speed = 0.0;
                w->frictionless = !c_.wall_friction;  // as built; a prepared state's walls take this run's
            }
            lower.motion = mm::FixedMotion{};
            if (k == up)
                upper.motion = mm::StrainControlled{c_.final_strain * box0_[k], c_.period, sim_.time()};
            else
                upper.motion = mm::StressControlled{c_.pressure, c_.wall_mass, c_.wall_damping, 0.0, c_.wall_follow_time};
        }
        const double gamma = c_.gamma_b, gamma_r = c_.rotational_damping(c_.gamma_b);
        sim_.template body_force<mm::BackgroundDamping>() = c_.damping == "lab" ? mm::BackgroundDamping(gamma, gamma_r) : mm::BackgroundDamping();
        sim_.template body_force<mm::AffineDamping>() = c_.damping == "affine" ? mm::AffineDamping(gamma, gamma_r) : mm::AffineDamping();
        sim_.template body_force<mm::LocalDamping>() = mm::LocalDamping(c_.damping == "local" ? c_.local_damping : 0.0);
        sim_.law() = make_law(c_, c_.mu);
        // The loading's time step is the preparation's, unless a run from a prepared state asks for
        // another (--dt-fraction), which then acts as run.json records it.
        if (sim_.time_step() != c_.time_step()) sim_.set_time_step(c_.time_step());
        load_start_ = sim_.time();
    }

    double load_start() const { return load_start_; }

    /// The experiment's own state beyond the simulation (for prepared states and checkpoints).
    std::vector<double> bookkeeping() const {
        std::vector<double> b(box0_.begin(), box0_.end());
        b.push_back(load_start_);
        return b;
    }
    void restore_bookkeeping(const std::vector<double>& b) {
        if (b.size() != dim + 1) mm::throw_input_error("the saved experiment state does not fit a ", dim, "D run");
        for (int k = 0; k < dim; ++k) box0_[k] = b[k];
        load_start_ = b[dim];
    }
    /// The box after preparation, per axis (m).
    std::vector<double> reference_box() const { return {box0_.begin(), box0_.end()}; }
    /// eps_zz = 1 - z / z0 of Eq. 17 (compression positive), with the walls `w` (the engine's by default).
    template <class Walls>
    double eps_zz(const Walls& w) const {
        return 1.0 - (w[2 * up + 1].coordinate() - w[2 * up].coordinate()) / box0_[up];
    }
    double eps_zz() const { return eps_zz(sim_.walls()); }
    double load_end() const { return load_start_ + 0.5 * c_.period + c_.relax; }
    /// Steps between two rows of the time series (the output interval, rounded to whole steps).
    std::size_t steps_per_row() const { return biaxial::steps_per_row(c_, sim_.time_step()); }
    /// Rows of the loading's time series, the first at its start.
    std::size_t loading_rows() const { return biaxial::loading_rows(c_, sim_.time_step(), load_end() - load_start_); }

    /// The time-series row of the present state of `scene` (SerialScene: this experiment's engine).
    template <class Scene>
    Row row(Scene& scene) const {
        Row r;
        const auto s = scene.snapshot();  // the walls and this process's particles and contacts
        const auto region = mm::Region<dim>::inner(s, c_.inner_margin);  // the paper's averaging box: 10%
        const auto m = scene.average(s, region);
        const auto wall = mm::wall_stress(s);
        const auto e = scene.energy();
        const auto books = scene.books();
        const auto& walls = scene.walls();
        constexpr auto idx = &micromacro::cli::component;
        r.add("time", scene.time() - load_start_);
        double volume = 1.0, volume0 = 1.0;
        for (int k = 0; k < dim; ++k) {
            const double extent = walls[2 * k + 1].coordinate() - walls[2 * k].coordinate();
            r.add("strain_" + idx({k, k}), 1.0 - extent / box0_[k]);
            volume *= extent;
            volume0 *= box0_[k];
        }
        r.add("volumetric_strain", 1.0 - volume / volume0);
        for (int k = 0; k < dim; ++k) {
            r.add("wall_" + idx({k}) + "_lower", walls[2 * k].coordinate());
            r.add("wall_" + idx({k}) + "_upper", walls[2 * k + 1].coordinate());
        }
        for (int k = 0; k < dim; ++k) r.add("sigma_wall_" + idx({k, k}), wall(k, k));
        for (int k = 0; k < dim; ++k) {  // each wall on its own, the moving one and the fixed one: its push over its area
            double area = 1.0;
            for (int b = 0; b < dim; ++b)
                if (b != k) area *= walls[2 * b + 1].coordinate() - walls[2 * b].coordinate();
            r.add("sigma_wall_" + idx({k, k}) + "_upper", -walls[2 * k + 1].force.dot(walls[2 * k + 1].normal) / area);
            r.add("sigma_wall_" + idx({k, k}) + "_lower", -walls[2 * k].force.dot(walls[2 * k].normal) / area);
        }
        for (int a = 0; a < dim; ++a)
            for (int b = a; b < dim; ++b) {
                r.add("sigma_" + idx({a, b}), m.stress(a, b));
                r.add("sigma_n_" + idx({a, b}), m.stress_normal(a, b));
                r.add("sigma_t_" + idx({a, b}), m.stress_tangential(a, b));
            }
        r.add("pressure", m.pressure);
        r.add("deviatoric_stress", m.stress_deviator);
        for (int a = 0; a < dim; ++a)
            for (int b = a; b < dim; ++b) r.add("F_" + idx({a, b}), m.fabric(a, b));
        r.add("trF", m.contact_number_density);
        // g2 measured (tr F / (nu C)) and g2 of the size distribution, <a^2> / <a>^2 of the
        // particles inside (the paper's 1.088 for radii uniform in [0.5, 1.5] mm); the paper's
        // corrected contact number density is tr F over the latter, to compare with nu C.
        std::vector<double> sums(3, 0.0);  // of a, a^2 and 1 over the particles inside
        for (std::size_t p = 0; p < scene.owned(); ++p)
            if (region.contains(s.position[p])) {
                sums[0] += s.radius[p];
                sums[1] += s.radius[p] * s.radius[p];
                sums[2] += 1.0;
            }
        scene.add_up(sums);
        const double a1 = sums[0], a2 = sums[1], count = sums[2];
        const double g2_size = count > 0 ? a2 * count / (a1 * a1) : 0.0;
        r.add("g2", m.g2);
        r.add("g2_size", g2_size);
        r.add("trF_over_g2", g2_size > 0 ? m.contact_number_density / g2_size : 0.0);
        r.add("deviatoric_fabric", m.fabric_deviator);
        if constexpr (dim == 2) r.add("phi_F", m.fabric_angle);
        r.add("coordination", m.coordination);
        r.add("volume_fraction", m.volume_fraction);
        micromacro::cli::add_stiffness_columns(r, m);
        r.add("kinetic_energy", e.kinetic());
        r.add("elastic_energy", e.elastic_normal + e.elastic_tangential);
        r.add("dissipated_energy", books.dissipated());
        r.add("dissipated_background", books.dissipated_background);
        r.add("work_by_walls", books.work_by_walls);
        r.add("sliding_fraction", m.sliding_fraction);
        return r;
    }
    Row row() {
        SerialScene<Sim> scene(sim_);
        return row(scene);
    }

private:
    static Law make_law(const Config& c, double mu) {
        if constexpr (std::is_same_v<Law, mm::HertzMindlin>)
            return mm::HertzMindlin(c.young, c.poisson, c.restitution, mu);
        else
            return Law{mm::LinearSpringDashpot(c.k, c.gamma0), mm::CundallStrack(c.kt_ratio * c.k, c.gammat_ratio * c.gamma0, mu)};
    }
    static const Config& checked_law(const Config& c) {
        if (c.hertz() != std::is_same_v<Law, mm::HertzMindlin>)
            mm::throw_input_error("a ", c.law, " configuration given to an experiment built for the other contact law");
        return c;
    }

    mm::WallMotion prepare_motion(double L) const {
        // Damped for a terminal speed of wall_speed_prepare() at the initial area; as the box shrinks
        // the push p A and with it the wall's speed drop.
        return mm::StressControlled{c_.pressure, c_.wall_mass, c_.prepare_wall_damping(L)};
    }

    Config c_;
    Sim sim_;
    std::array<double, dim> box0_{};
    double load_start_ = 0.0;
};

}  // namespace biaxial
