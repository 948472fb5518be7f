#pragma once
// The energies and energy books of the whole scene a DistributedRun steps. Each rank's engine
// counts its own particles and half of each contact with a ghost (BasicSimulation::energy) and
// books likewise; rank 0 counts the walls' own energy and books (every rank holds every wall).
// The parts are added over the ranks.
#include <initializer_list>

#include <mpi.h>

#include "micromacro/core/energy.hpp"
#include "micromacro/mpi/communicator.hpp"
#include "micromacro/mpi/distributed_run.hpp"

namespace micromacro::mpi {

namespace energy_detail {
/// The numbers of an EnergyState that add over the ranks (add_over_ranks).
struct StateSums {
    EnergyState& e;
    template <class F>
    void for_each_number(F&& f) {
        for (double* x : {&e.kinetic_translational, &e.kinetic_rotational, &e.kinetic_walls, &e.elastic_normal,
                          &e.elastic_tangential, &e.gravitational})
            f(*x);
    }
};
/// The numbers of OpenBooks that add over the ranks: the sums, the last evaluation's bookings,
/// the initial energy and the walls' pushes (their offsets and areas are every rank's).
struct BookSums {
    OpenBooks& b;
    template <class F>
    void for_each_number(F&& f) {
        for (EnergyBooks* e : {&b.books, &b.last_evaluation})
            for (double* x : {&e->dissipated_normal, &e->dissipated_tangential, &e->dissipated_sliding, &e->dissipated_background,
                              &e->dissipated_walls, &e->work_by_walls, &e->work_by_deformation, &e->work_by_cell})
                f(*x);
        f(b.initial_energy);
        for (auto& w : b.walls) f(w.push);
    }
};
}  // namespace energy_detail

/// The same on every rank (a collective call: every rank must make it; it brings the ghosts up
/// to date first, since a contact's energy reads its partner's state).
template <class Sim>
EnergyState energy(DistributedRun<Sim>& run) {
    run.refresh_ghosts();
    EnergyState e = run.local().energy();
    energy_detail::StateSums sums{e};
    add_over_ranks(sums, run.comm().comm(), "MPI_Allreduce (energies)");
    return e;
}

/// The whole scene's books as a serial engine would continue them, the same on every rank (a
/// collective call): the ranks' sums, last evaluations' bookings, initial energies and shares of
/// the walls' pushes added; the walls' offsets and areas are every rank's.
template <class Sim>
OpenBooks open_books(const DistributedRun<Sim>& run) {
    OpenBooks b = run.local().open_books();
    energy_detail::BookSums sums{b};
    add_over_ranks(sums, run.comm().comm(), "MPI_Allreduce (energy books)");
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
