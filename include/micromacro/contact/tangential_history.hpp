#pragma once
// What a tangential contact model gives the engine and keeps per contact: the tangential force of
// an evaluation, and the Cundall-Strack spring's record, with how it reads from the pair's other
// partner.
#include "micromacro/core/dim_traits.hpp"
#include "micromacro/core/inline.hpp"

namespace micromacro {

/// Tangential force on particle i and the energy it dissipated during this step.
template <int dim>
struct TangentialForce {
    Vec<dim> force = Vec<dim>::Zero();
    double dissipated_viscous = 0.0;  ///< by gamma_t while sticking
    double dissipated_sliding = 0.0;  ///< by Coulomb sliding (incl. the spring reset of Eq. 28)
    bool sliding = false;
};

struct NoHistory {};

/// The Cundall-Strack tangential spring of Eq. 23-29 with what its next step needs to know of
/// the last one (see CundallStrack::force). In 3D the spring is a vector in the tangent plane,
/// projected onto the new plane as the contact turns (Eq. 23). In 2D the tangent plane is the
/// line along t = (-n_1, n_0) and the spring is its component along t, a number that turns with
/// the contact exactly (the limit of Eq. 23's projections as the steps shrink, which shorten a
/// turning vector a little at every step): 24 bytes, half the vector record (docs/model.md).
template <int dim>
struct TangentialSpring {
    Vec<dim> spring = Vec<dim>::Zero();  ///< xi of Eq. 23-28 at the last evaluation, t_n
    Vec<dim> ahead = Vec<dim>::Zero();   ///< xi_n + dt v_{n-1/2} / 3, where the next step starts from
    float trial = 0;                     ///< |trial force| of a sliding last evaluation (for opening_correction)
    bool sliding = false;                ///< Coulomb state, for the static/dynamic hysteresis
    bool touching = false;               ///< evaluated in contact before; false on a new contact
    bool fresh = false;                  ///< the last evaluation was the contact's first
};
template <>
struct TangentialSpring<2> {
    double spring = 0.0;  ///< xi along t at the last evaluation, t_n
    double ahead = 0.0;   ///< xi_n + dt v_{t,n-1/2} / 3 along t
    float trial = 0;
    bool sliding = false;
    bool touching = false;
    bool fresh = false;
};

/// The tangent line's direction of a 2D contact with normal n, the axis of its spring.
MICROMACRO_INLINE Vec<2> tangent_of(const Vec<2>& n) { return {-n.y(), n.x()}; }

/// A contact's history as its other partner sees it, for when particles are renumbered and a
/// pair's two particles swap roles: the spring vector is odd under the swap (the relative
/// velocity it integrates and the force it gives change sign), the sliding state is shared. A 2D
/// spring's component is even: t turns over with n.
inline NoHistory seen_from_partner(NoHistory h) { return h; }
template <int dim>
TangentialSpring<dim> seen_from_partner(const TangentialSpring<dim>& h) {
    return {Vec<dim>(-h.spring), Vec<dim>(-h.ahead), h.trial, h.sliding, h.touching, h.fresh};
}
inline TangentialSpring<2> seen_from_partner(const TangentialSpring<2>& h) { return h; }

}  // namespace micromacro
