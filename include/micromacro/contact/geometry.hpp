#pragma once
// What a contact law sees of one contact.
//
// Sign convention (used everywhere in micromacro): the overlap is POSITIVE when the particles
// interpenetrate, overlap = a_i + a_j - |r_i - r_j| (for a wall: a_i - distance to the plane).
// The paper's Eq. 20 defines Delta = -overlap (negative on contact). The normal n points from
// partner j to particle i, and every force a law returns is the force ON i FROM j.
#include <cmath>

#include "micromacro/core/dim_traits.hpp"

namespace micromacro {

template <int dim>
struct ContactGeometry {
    Vec<dim> normal;             ///< unit vector from j to i
    double overlap;              ///< > 0 in contact
    double normal_velocity;      ///< n . (v_i - v_j); negative while approaching
    Vec<dim> relative_velocity;  ///< v_ij of Eq. 25, relative velocity of the contact points
};

/// One contact as the engine hands it to a contact law: the geometry and velocities above, the
/// two bodies, and the time step. A plane wall is a body of infinite radius and zero inverse
/// mass. A law that does not use a field costs nothing for it: the engine's loops are inlined
/// and the compiler drops what no law reads.
template <int dim>
struct ContactKinematics : ContactGeometry<dim> {
    double radius_i, radius_j;              ///< m; radius_j is infinite for a wall
    double inverse_mass_i, inverse_mass_j;  ///< 1/kg; inverse_mass_j is 0 for a wall
    double dt;                              ///< the step the evaluation advances the contact by

    /// R* = a_i a_j / (a_i + a_j), the radius of curvature of the contact (a_i on a wall).
    double effective_radius() const {
        return std::isinf(radius_j) ? radius_i : radius_i * radius_j / (radius_i + radius_j);
    }
    /// m* = m_i m_j / (m_i + m_j), the reduced mass (m_i on a wall).
    double effective_mass() const { return 1.0 / (inverse_mass_i + inverse_mass_j); }
};

}  // namespace micromacro
