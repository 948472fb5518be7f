#pragma once
// Forces that act on each particle alone. Each policy adds to the force (and torque) arrays and,
// when energy is tracked, books what it dissipates; a policy with a potential reports it.
#include <vector>

#include "micromacro/core/dim_traits.hpp"
#include "micromacro/core/energy.hpp"
#include "micromacro/core/error.hpp"
#include "micromacro/particles/particles.hpp"

namespace micromacro {

/// Background damping, Eq. 30: f_i -= gamma_b v_i, and t_i -= gamma_r omega_i when particles rotate.
struct BackgroundDamping {
    double translational = 0.0;  ///< gamma_b (kg/s)
    double rotational = 0.0;     ///< gamma_r (kg m^2/s)

    BackgroundDamping() = default;
    BackgroundDamping(double gamma_b, double gamma_r) : translational(gamma_b), rotational(gamma_r) {
        detail::require_non_negative(gamma_b, "background damping gamma_b", "use 0 to switch it off");
        detail::require_non_negative(gamma_r, "rotational background damping gamma_r", "use 0 to switch it off");
    }

    template <bool track_energy, int dim, bool rot, class Real>
    void apply(Particles<dim, rot, Real>& p, EnergyBooks& books, double dt) const {
        // One pass, raw pointers and local constants (through the members the compiler reloaded
        // them after every store). The power gamma |v|^2 is summed as |v|^2 and |omega|^2 apart,
        // two independent chains of additions instead of one running through both loops (perf had
        // the two loops at ~7% of the paper biaxial's loading, most of it on that chain).
        Vec<dim, Real>* f = p.template get<field::Force>().data();
        const Vec<dim, Real>* v = p.template get<field::Velocity>().data();
        [[maybe_unused]] Angular<dim, Real>* t = nullptr;
        [[maybe_unused]] const Angular<dim, Real>* w = nullptr;
        if constexpr (rot) {
            t = p.template get<field::Torque>().data();
            w = p.template get<field::AngularVelocity>().data();
        }
        const Real gamma_b = static_cast<Real>(translational), gamma_r = static_cast<Real>(rotational);
        const std::size_t n = p.size();
        double v_sq = 0.0, w_sq = 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            f[i] -= gamma_b * v[i];
            if constexpr (track_energy) v_sq += convert<double>(v[i]).squaredNorm();
            if constexpr (rot) {
                t[i] -= gamma_r * w[i];
                if constexpr (track_energy) w_sq += DimTraits<dim>::squared_norm(convert<double>(w[i]));
            }
        }
        if constexpr (track_energy) books.dissipated_background += (translational * v_sq + rotational * w_sq) * dt;
    }
};

/// Uniform gravity: f_i += m_i g, potential energy -sum m_i g . x_i.
template <int dim>
struct Gravity {
    Vec<dim> g = Vec<dim>::Zero();

    template <bool track_energy, bool rot, class Real>
    void apply(Particles<dim, rot, Real>& p, EnergyBooks&, double) const {
        auto& f = p.template get<field::Force>();
        const auto& m = p.template get<field::Mass>();
        const Vec<dim, Real> stored_g = convert<Real>(g);
        for (std::size_t i = 0; i < p.size(); ++i) f[i] += m[i] * stored_g;
    }
    template <bool rot, class Real>
    double potential_energy(const Particles<dim, rot, Real>& p) const {
        double u = 0.0;
        for (std::size_t i = 0; i < p.size(); ++i) u -= double(p.mass()[i]) * g.dot(convert<double>(p.position()[i]));
        return u;
    }
};

}  // namespace micromacro
