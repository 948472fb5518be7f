#pragma once
// A contact as analysis sees it: the engine's for_each_contact hands one to its caller.
#include "micromacro/contact/geometry.hpp"
#include "micromacro/core/dim_traits.hpp"
#include "micromacro/core/index.hpp"

namespace micromacro {

/// One contact as analysis sees it (see Simulation::for_each_contact).
template <int dim>
struct ContactView {
    Index i;                      ///< the particle
    Index j;                      ///< the partner particle, or the wall number when `wall`
    bool wall;                    ///< partner is a wall
    ContactGeometry<dim> geometry;
    Vec<dim> branch;              ///< r_i - r_j (minimum image); for a wall, r_i minus its projection on the plane
    double normal_force;          ///< f_n along n, elastic + viscous, positive = repulsive
    double normal_elastic_force;  ///< k overlap
    Vec<dim> tangential_force;    ///< on i
    double elastic_energy;        ///< normal + tangential spring energy
    bool sliding;
    Vec<dim> force() const { return normal_force * geometry.normal + tangential_force; }
};

}  // namespace micromacro
