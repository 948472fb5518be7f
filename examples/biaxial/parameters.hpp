#pragma once
// Every parameter of the biaxial test written once (see ../parameter_table.hpp): its option, its
// key in run.json and in saved states, its help text, whether it made the packing, and the contact
// law it belongs to.
#include <cstddef>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "../parameter_table.hpp"
#include "biaxial.hpp"

namespace biaxial {

/// In run.json's order. --dim and --preset choose the presets and are handled apart.
inline const micromacro::cli::ParameterTable<Config>& parameter_table() {
    using C = Config;
    static const micromacro::cli::ParameterTable<Config> table{
        {nullptr, "dim", "", &C::dim},
        {nullptr, "preset", "", &C::preset},
        {"--particles", "particles", "number of particles", &C::particles, true},
        {nullptr, "radius_min_m", "", &C::radius_min, true},
        {nullptr, "radius_max_m", "", &C::radius_max, true},
        {nullptr, "density_kg_m3", "", &C::density},
        {"--law", "law", "contact law: linear (default; Eq. 20-29) or hertz-mindlin (--young, --poisson, --restitution)", &C::law,
         true, nullptr, true},
        {"--young", "young_Pa", "hertz-mindlin: Young's modulus E of the particles in Pa (default 1e10)", &C::young, true,
         "hertz-mindlin", true},
        {"--poisson", "poisson", "hertz-mindlin: Poisson's ratio (default 0.25)", &C::poisson, true, "hertz-mindlin", true},
        {"--restitution", "restitution", "hertz-mindlin: normal restitution coefficient (default 0.8)", &C::restitution, true,
         "hertz-mindlin", true},
        {nullptr, "k_N_m", "", &C::k, false, "linear"},
        {nullptr, "gamma0_kg_s", "", &C::gamma0, false, "linear"},
        {"--mu", "mu", "friction coefficient mu_s = mu_d (default 0.5)", &C::mu},
        {"--mu-prepare", "mu_prepare", "friction while preparing (default 0.1: volume fraction 0.83; 0.5 leaves 0.80)",
         &C::mu_prepare, true},
        {"--prepare-walls", "prepare_walls",
         "walls that compress while preparing: upper (the lower walls stay; the default in 2D) or both (opposite walls close in "
         "together; the default in 3D)",
         &C::prepare_walls, true, nullptr, true},
        {"--kt-ratio", "kt_ratio", "linear law: k_t / k (default 0.2)", &C::kt_ratio, false, "linear"},
        {nullptr, "gammat_ratio", "", &C::gammat_ratio, false, "linear"},
        {"--pressure", "pressure", "side pressure p (N/m in 2D, Pa in 3D; default 20 and 1e4)", &C::pressure},
        {"--period", "period_s", "T of Eq. 17 in s (loading lasts T/2)", &C::period},
        {"--final-strain", "final_strain", "eps_zz at the end of the motion (default 0.2)", &C::final_strain},
        {"--relax", "relax_s", "relaxation after T/2 in s", &C::relax},
        {"--dt-fraction", "dt_fraction", "dt = t_c / this, t_c of two mean particles (default 50)", &C::dt_fraction},
        {"--seed", "seed", "random seed of the initial placement (default 1)", &C::seed, true},
        {"--damping", "damping",
         "damping while loading: affine (default: Eq. 30 against the walls' mean flow), lab (Eq. 30 as printed) or local "
         "(Cundall's)",
         &C::damping},
        {"--gamma-b", "gamma_b_kg_s", "lab or affine damping while loading in kg/s (default 5e-2 affine, 1e-4 lab as in the paper)",
         &C::gamma_b},
        {"--local-damping", "local_damping", "alpha of the local damping while loading (default 0.2)", &C::local_damping},
        {"--gamma-b-prepare", "gamma_b_prepare_kg_s", "background damping while preparing in kg/s (default 1e-3)",
         &C::gamma_b_prepare, true},
        {"--wall-mass", "wall_mass_kg", "m_w of Eq. 18 in kg (default 1e-4)", &C::wall_mass},
        {"--wall-damping", "wall_damping_kg_s", "gamma_w of Eq. 18 in kg/s while loading (default 0)", &C::wall_damping},
        {"--wall-follow-time", "wall_follow_time_s",
         "the side wall's damper follows its velocity with this time constant in s (0: Eq. 18, anchored; see walls.hpp)",
         &C::wall_follow_time},
        {"--prepare-speed", "prepare_speed_m_s",
         "wall speed while preparing in m/s: wall damping = p A / speed (default 0: 5 m/s, in proportion to p/k below "
         "p/k = 1e-5)",
         &C::prepare_speed, true},
        {nullptr, "prepare_kinetic_ratio", "", &C::prepare_kinetic_ratio, true},
        {"--output-interval", "output_interval_s", "time between rows of timeseries.csv in s", &C::output_interval},
        {nullptr, "box_factor", "", &C::box_factor, true},
        {"--inner-margin", "inner_margin",
         "averaging box: fraction of each side left out next to each wall (default 0.1, the paper's)", &C::inner_margin, false,
         nullptr, true},
        {"--wall-friction", "wall_friction", "walls use the particles' friction (default: smooth walls)", &C::wall_friction},
    };
    return table;
}

/// run.json's "parameters": the table, then two derived figures.
inline nlohmann::ordered_json parameters_json(const Config& c) {
    nlohmann::ordered_json j = micromacro::cli::parameters_json(parameter_table(), c);
    j["pressure_unit"] = c.dim == 2 ? "N/m" : "Pa";
    j["gamma_r_kg_m2_s"] = c.rotational_damping(c.gamma_b);
    return j;
}

/// The configuration saved in run.json or a state (`j` holds "parameters"), over `c`. A file
/// written before a `later` parameter existed takes the value every run had then, Config's
/// default (the paper's inner box, the linear law, the upper walls preparing), whatever the
/// presets set now.
inline Config config_from_json(const nlohmann::ordered_json& j, Config c) {
    return micromacro::cli::config_from_json(parameter_table(), j.at("parameters"), c);
}

/// The options of the table that belong to another contact law than the configuration's and
/// were given (refused: --kt-ratio with Hertz-Mindlin, whose k_t follows from E and nu; --young
/// and the others of Hertz-Mindlin with the linear law).
inline std::vector<std::string> options_of_other_law(const std::vector<CLI::Option*>& options, const Config& c) {
    std::vector<std::string> given;
    if (c.law != "linear" && !c.hertz()) return given;  // an unknown law: validate() names it
    const auto& table = parameter_table();
    for (std::size_t k = 0; k < table.size(); ++k)
        if (table[k].law && c.law != table[k].law && options[k] && options[k]->count()) given.push_back(options[k]->get_name());
    return given;
}

}  // namespace biaxial
