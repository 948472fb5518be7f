#pragma once
// Normal contact models. A normal model maps (overlap, normal velocity) to a force magnitude
// along n, split into its elastic and viscous parts so the energy books can tell them apart.
#include <concepts>

#include "micromacro/core/error.hpp"
#include "micromacro/core/inline.hpp"

namespace micromacro {

/// Normal force along n on particle i; positive = repulsive.
struct NormalForce {
    double elastic;  ///< conservative part
    double viscous;  ///< dissipative part
    double total() const { return elastic + viscous; }
};

template <class N>
concept NormalModel = requires(const N& n, double overlap, double normal_velocity) {
    { n.force(overlap, normal_velocity) } -> std::same_as<NormalForce>;
    { n.elastic_energy(overlap) } -> std::convertible_to<double>;
    { n.stiffness() } -> std::convertible_to<double>;  // for the stable time step
    { n.damping() } -> std::convertible_to<double>;
};

/// Linear spring-dashpot, Eq. 21: f = k overlap - gamma_0 (n . v_ij). Not clipped at zero: the
/// short tensile phase at the end of a damped collision is what makes the restitution
/// exp(-eta_0 t_c) of Eq. 22 exact.
class LinearSpringDashpot {
public:
    LinearSpringDashpot(double k, double gamma0) : k_(k), gamma0_(gamma0) {
        detail::require_positive(k, "normal stiffness k", "give the spring constant in N/m");
        detail::require_non_negative(gamma0, "normal damping gamma_0", "use 0 for an elastic contact");
    }
    MICROMACRO_INLINE NormalForce force(double overlap, double normal_velocity) const {
        return {k_ * overlap, -gamma0_ * normal_velocity};
    }
    double elastic_energy(double overlap) const { return 0.5 * k_ * overlap * overlap; }
    double stiffness() const { return k_; }
    double damping() const { return gamma0_; }

private:
    double k_, gamma0_;
};
static_assert(NormalModel<LinearSpringDashpot>);

}  // namespace micromacro
