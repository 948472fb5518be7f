#pragma once
// JSON views of the averaging results (nlohmann::ordered_json, an optional dependency of the I/O part).
// Rank-2 tensors become nested lists [dim][dim], rank-4 tensors [dim][dim][dim][dim].
#include <nlohmann/json.hpp>

#include "micromacro/averaging/anisotropy.hpp"
#include "micromacro/averaging/micro_macro.hpp"

namespace micromacro::io {

template <int dim>
nlohmann::ordered_json to_json(const Tensor2<dim>& t) {
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (int a = 0; a < dim; ++a) {
        nlohmann::ordered_json row = nlohmann::ordered_json::array();
        for (int b = 0; b < dim; ++b) row.push_back(t(a, b));
        out.push_back(row);
    }
    return out;
}

template <int dim>
nlohmann::ordered_json to_json(const Tensor4<dim>& t) {
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (int a = 0; a < dim; ++a) {
        nlohmann::ordered_json ra = nlohmann::ordered_json::array();
        for (int b = 0; b < dim; ++b) {
            nlohmann::ordered_json rb = nlohmann::ordered_json::array();
            for (int c = 0; c < dim; ++c) {
                nlohmann::ordered_json rc = nlohmann::ordered_json::array();
                for (int d = 0; d < dim; ++d) rc.push_back(t(a, b, c, d));
                rb.push_back(rc);
            }
            ra.push_back(rb);
        }
        out.push_back(ra);
    }
    return out;
}

template <class V>
nlohmann::ordered_json vector_json(const V& v) {
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (Eigen::Index i = 0; i < v.size(); ++i) out.push_back(v[i]);
    return out;
}

/// Every quantity of a box average (SI units; docs/analyze-packing.md lists the keys).
template <int dim>
nlohmann::ordered_json to_json(const MicroMacro<dim>& m) {
    nlohmann::ordered_json j;
    j["dim"] = dim;
    j["volume"] = m.volume;
    j["particles"] = m.particles;
    j["rattlers"] = m.rattlers;
    j["contacts"] = m.contacts;
    j["coordination"] = m.coordination;
    j["coordination_without_rattlers"] = m.coordination_without_rattlers;
    j["volume_fraction"] = m.volume_fraction;
    j["contact_number_density"] = m.contact_number_density;
    j["g2"] = m.g2;
    j["fabric"] = to_json<dim>(m.fabric);
    j["fabric_deviator"] = m.fabric_deviator;
    if constexpr (dim == 2) j["fabric_angle"] = m.fabric_angle;
    j["fabric_axes"] = to_json<dim>(m.fabric_axes);
    j["stress"] = to_json<dim>(m.stress);
    j["stress_normal"] = to_json<dim>(m.stress_normal);
    j["stress_tangential"] = to_json<dim>(m.stress_tangential);
    j["stress_kinetic"] = to_json<dim>(m.stress_kinetic);
    j["pressure"] = m.pressure;
    j["stress_deviator"] = m.stress_deviator;
    j["stiffness_normal"] = to_json<dim>(m.stiffness_normal);
    j["stiffness_tangential"] = to_json<dim>(m.stiffness_tangential);
    j["stiffness_kelvin_eigenvalues"] = vector_json((m.stiffness_normal + m.stiffness_tangential).kelvin_eigenvalues());
    j["sliding_fraction"] = m.sliding_fraction;
    return j;
}

/// The anisotropy of the same contacts (docs/analyze-packing.md lists the keys).
template <int dim>
nlohmann::ordered_json to_json(const Anisotropy<dim>& a) {
    nlohmann::ordered_json j;
    j["a_c"] = a.a_c;
    j["a_n"] = a.a_n;
    j["a_t"] = a.a_t;
    if constexpr (dim == 2) {
        j["theta_c"] = a.theta_c;
        j["theta_n"] = a.theta_n;
        j["theta_t"] = a.theta_t;
    }
    j["contact"] = to_json<dim>(a.contact);
    j["normal_force"] = to_json<dim>(a.normal_force);
    j["tangential_force"] = to_json<dim>(a.tangential_force);
    j["mean_normal_force"] = a.mean_normal_force;
    j["stress_ratio"] = to_json<dim>(a.stress_ratio());
    return j;
}

}  // namespace micromacro::io
