#pragma once
// What a contact law sees of one contact.
//
// Sign convention (used everywhere in micromacro): the overlap is POSITIVE when the particles
// interpenetrate, overlap = a_i + a_j - |r_i - r_j| (for a wall: a_i - distance to the plane).
// The paper's Eq. 20 defines Delta = -overlap (negative on contact). The normal n points from
// partner j to particle i, and every force a law returns is the force ON i FROM j.
#include "micromacro/core/dim_traits.hpp"

namespace micromacro {

template <int dim>
struct ContactGeometry {
    Vec<dim> normal;             ///< unit vector from j to i
    double overlap;              ///< > 0 in contact
    double normal_velocity;      ///< n . (v_i - v_j); negative while approaching
    Vec<dim> relative_velocity;  ///< v_ij of Eq. 25, relative velocity of the contact points
};

}  // namespace micromacro
