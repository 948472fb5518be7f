#pragma once
// The energies of the whole scene a DistributedRun steps (EnergyState): each rank's engine counts
// its own particles and half of each contact with a ghost (BasicSimulation::energy), the walls'
// kinetic energy is taken once (every rank holds every wall), and the parts are added over the
// ranks.
#include <array>

#include <mpi.h>

#include "micromacro/core/energy.hpp"
#include "micromacro/mpi/communicator.hpp"
#include "micromacro/mpi/distributed_run.hpp"

namespace micromacro::mpi {

/// The same on every rank (a collective call: every rank must make it; it brings the ghosts up
/// to date first, since a contact's energy reads its partner's state).
template <class Sim>
EnergyState energy(DistributedRun<Sim>& run) {
    run.refresh_ghosts();
    EnergyState e = run.local().energy();
    if (run.comm().rank() != 0) e.kinetic_walls = 0.0;
    std::array<double, 6> parts{e.kinetic_translational, e.kinetic_rotational, e.kinetic_walls,
                                e.elastic_normal,        e.elastic_tangential, e.gravitational};
    check(MPI_Allreduce(MPI_IN_PLACE, parts.data(), static_cast<int>(parts.size()), MPI_DOUBLE, MPI_SUM, run.comm().comm()),
          "MPI_Allreduce (energies)");
    return {parts[0], parts[1], parts[2], parts[3], parts[4], parts[5]};
}

}  // namespace micromacro::mpi
