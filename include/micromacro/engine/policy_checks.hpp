#pragma once
// The engine's template arguments checked against what it needs of them, each refusal naming the
// concept and the header that defines it (a wrong policy fails here, not deep in instantiation).
#include <type_traits>

#include "micromacro/contact/contact_law.hpp"
#include "micromacro/core/dim_traits.hpp"
#include "micromacro/forces/body_forces.hpp"
#include "micromacro/integrators/integrators.hpp"
#include "micromacro/neighbors/neighbor_search.hpp"

namespace micromacro::detail {

template <int dim, class Real, class Law, class Integrator, class Neighbors, class... BodyForces>
consteval bool check_policies() {
    static_assert(SupportedDimension<dim>, "the engine runs in 2 or 3 dimensions");
    static_assert(std::is_same_v<Real, double> || std::is_same_v<Real, float>, "particle state is stored in double or float");
    static_assert(ContactLawIn<Law, dim>, "the contact law does not satisfy ContactLawModel (contact/contact_law.hpp)");
    static_assert(TimeIntegrator<Integrator>, "the integrator does not satisfy TimeIntegrator (integrators/integrators.hpp)");
    static_assert(NeighborSearch<Neighbors, dim, Real>,
                  "the neighbour search does not satisfy NeighborSearch (neighbors/neighbor_search.hpp)");
    static_assert((BodyForce<BodyForces, dim, Law::needs_rotation, Real> && ...),
                  "a body force does not satisfy BodyForce (forces/body_forces.hpp): apply(particles, books, BodyForceStep)");
    return true;
}

}  // namespace micromacro::detail
