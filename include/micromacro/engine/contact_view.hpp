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
    double normal_force = 0;          ///< f_n along n, elastic + viscous, positive = repulsive
    double normal_elastic_force = 0;  ///< the elastic part of f_n (k overlap for the linear spring)
    Vec<dim> tangential_force = Vec<dim>::Zero();  ///< on i
    double normal_energy = 0;         ///< J in the normal spring
    double tangential_energy = 0;     ///< J in the tangential spring
    double stiffness = 0;             ///< d f_n / d overlap, N/m
    double tangential_stiffness = 0;  ///< N/m; 0 on a frictionless contact
    bool sliding = false;
    Vec<dim> force() const { return normal_force * geometry.normal + tangential_force; }
    double elastic_energy() const { return normal_energy + tangential_energy; }
};

}  // namespace micromacro
