#pragma once
// The parts of an engine type that each rank's engine of a distributed run is built from besides
// the law and the walls: its neighbour search and a copy of its body forces, which must act on a
// count of particles (ActsOnACount).
#include <cstddef>
#include <tuple>

#include "micromacro/core/affine_field.hpp"
#include "micromacro/core/energy.hpp"
#include "micromacro/engine/simulation.hpp"

namespace micromacro::mpi {

/// Whether body-force policy F acts on a count of particles, apply's last argument (as every
/// built-in policy does), so that a rank's engine applies it to its own particles only: a policy
/// without one acts on the ghosts too, whose owners apply it, and books their energy twice.
template <class F, class Sim>
concept ActsOnACount =
    requires(const F& f, typename Sim::ParticleSet& p, EnergyBooks& b, std::size_t n) { f.template apply<true>(p, b, 0.0, n); } ||
    requires(const F& f, typename Sim::ParticleSet& p, EnergyBooks& b, const AffineField<Sim::dimension>& u, std::size_t n) {
        f.template apply<true>(p, b, 0.0, u, n);
    };

namespace detail {
/// An engine type's neighbour search and body forces, and a copy of its body forces.
template <class Sim>
struct EngineParts;
template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
struct EngineParts<BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>> {
    using NeighborSearch = Neighbors;
    using Forces = std::tuple<BodyForces...>;
    static_assert((ActsOnACount<BodyForces, BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>> && ...),
                  "mpi::DistributedRun: every body force's apply must take the count of particles to act on as its last "
                  "argument (as BackgroundDamping::apply does), so that a rank applies it to its own particles, not to ghosts");
    static Forces forces_of(const BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>& s) {
        return Forces{s.template body_force<BodyForces>()...};
    }
};
}  // namespace detail

}  // namespace micromacro::mpi
