#pragma once
// The energies and energy books of the whole scene a DistributedRun steps. Each rank's engine
// counts its own particles and half of each contact with a ghost (BasicSimulation::energy) and
// books likewise; rank 0 counts the walls' own energy and books (every rank holds every wall).
// The parts are added over the ranks.
#include <array>
#include <cstddef>
#include <vector>

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
    const EnergyState e = run.local().energy();
    std::array<double, 6> parts{e.kinetic_translational, e.kinetic_rotational, e.kinetic_walls,
                                e.elastic_normal,        e.elastic_tangential, e.gravitational};
    check(MPI_Allreduce(MPI_IN_PLACE, parts.data(), static_cast<int>(parts.size()), MPI_DOUBLE, MPI_SUM, run.comm().comm()),
          "MPI_Allreduce (energies)");
    return {parts[0], parts[1], parts[2], parts[3], parts[4], parts[5]};
}

/// The whole scene's books as a serial engine would continue them, the same on every rank (a
/// collective call): the ranks' sums, last evaluations' bookings, initial energies and shares of
/// the walls' pushes added; the walls' offsets and areas are every rank's.
template <class Sim>
OpenBooks open_books(const DistributedRun<Sim>& run) {
    OpenBooks b = run.local().open_books();
    std::vector<double> parts;
    for (EnergyBooks* e : {&b.books, &b.last_evaluation})
        parts.insert(parts.end(), {e->dissipated_normal, e->dissipated_tangential, e->dissipated_sliding, e->dissipated_background,
                                   e->dissipated_walls, e->work_by_walls, e->work_by_deformation});
    parts.push_back(b.initial_energy);
    for (const auto& w : b.walls) parts.push_back(w.push);
    check(MPI_Allreduce(MPI_IN_PLACE, parts.data(), static_cast<int>(parts.size()), MPI_DOUBLE, MPI_SUM, run.comm().comm()),
          "MPI_Allreduce (energy books)");
    std::size_t k = 0;
    for (EnergyBooks* e : {&b.books, &b.last_evaluation})
        for (double* x : {&e->dissipated_normal, &e->dissipated_tangential, &e->dissipated_sliding, &e->dissipated_background,
                          &e->dissipated_walls, &e->work_by_walls, &e->work_by_deformation})
            *x = parts[k++];
    b.initial_energy = parts[k++];
    for (auto& w : b.walls) w.push = parts[k++];
    return b;
}

/// The whole scene's books so far (a collective call).
template <class Sim>
EnergyBooks books(const DistributedRun<Sim>& run) {
    return open_books(run).books;
}

/// BasicSimulation::energy_residual of the whole scene (a collective call).
template <class Sim>
double energy_residual(DistributedRun<Sim>& run) {
    const EnergyState e = energy(run);
    const OpenBooks b = open_books(run);
    return micromacro::energy_residual(e, b.books, b.initial_energy);
}

}  // namespace micromacro::mpi
