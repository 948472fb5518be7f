#pragma once
// The parts of an engine type that each rank's engine of a distributed run is built from besides
// the law and the walls: its neighbour search and a copy of its body forces (each acts on the
// count of particles the engine hands it, BodyForceStep::count: a rank's own, not its ghosts).
#include <tuple>

#include "micromacro/engine/simulation.hpp"

namespace micromacro::mpi {

namespace detail {
/// An engine type's neighbour search and body forces, and a copy of its body forces.
template <class Sim>
struct EngineParts;
template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
struct EngineParts<BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>> {
    using NeighborSearch = Neighbors;
    using Forces = std::tuple<BodyForces...>;
    static Forces forces_of(const BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>& s) {
        return Forces{s.template body_force<BodyForces>()...};
    }
};
}  // namespace detail

}  // namespace micromacro::mpi
