#pragma once
// Closed-form results for one linear spring-dashpot contact (Eq. 22) and the time-step limits
// that follow from them.
#include <cmath>
#include <numbers>

#include "micromacro/core/error.hpp"

namespace micromacro {

/// m12 = m1 m2 / (m1 + m2); a wall is an infinite mass, so reduced_mass(m, inf) = m.
inline double reduced_mass(double m1, double m2) {
    if (std::isinf(m2)) return m1;
    if (std::isinf(m1)) return m2;
    return m1 * m2 / (m1 + m2);
}

/// Eigenfrequency omega of Eq. 22; throws for an overdamped contact, where it does not exist.
inline double contact_frequency(double k, double gamma0, double m12) {
    detail::require_positive(k, "k", "give the spring constant in N/m");
    detail::require_positive(m12, "reduced mass m12", "masses must be positive");
    detail::require_non_negative(gamma0, "gamma_0", "damping cannot be negative");
    const double eta = gamma0 / (2.0 * m12);
    const double omega_sq = k / m12 - eta * eta;
    if (!(omega_sq > 0.0))
        detail::throw_input_error("the contact is overdamped: eta_0 = gamma_0/(2 m12) = ", eta,
                                  " is not below sqrt(k/m12) = ", std::sqrt(k / m12),
                                  ", so it never rebounds and has no contact duration; lower gamma_0 below ",
                                  2.0 * std::sqrt(k * m12));
    return std::sqrt(omega_sq);
}

/// Contact duration t_c = pi / omega (Eq. 22).
inline double contact_duration(double k, double gamma0, double m12) {
    return std::numbers::pi / contact_frequency(k, gamma0, m12);
}

/// Normal restitution coefficient e = exp(-eta_0 t_c).
inline double restitution(double k, double gamma0, double m12) {
    return std::exp(-gamma0 / (2.0 * m12) * contact_duration(k, gamma0, m12));
}

/// The gamma_0 that gives restitution e (0 < e <= 1) for stiffness k and reduced mass m12.
inline double damping_for_restitution(double k, double m12, double e) {
    detail::require_positive(k, "k", "give the spring constant in N/m");
    detail::require_positive(m12, "reduced mass m12", "masses must be positive");
    if (!(e > 0.0 && e <= 1.0))
        detail::throw_input_error("restitution e = ", e, " is outside (0, 1]");
    const double L = -std::log(e);
    const double eta = L * std::sqrt(k / m12) / std::sqrt(std::numbers::pi * std::numbers::pi + L * L);
    return 2.0 * m12 * eta;
}

}  // namespace micromacro
