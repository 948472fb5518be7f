#pragma once
// MPI started before a test module's cases and finished after them (BOOST_TEST_GLOBAL_FIXTURE).
#include <mpi.h>

#include <micromacro/mpi/communicator.hpp>

namespace mmtest {
struct MpiRuntime : micromacro::mpi::Runtime {};

/// This process's rank in MPI_COMM_WORLD, and how many ranks it has.
inline int world_rank() {
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    return rank;
}
inline int world_size() {
    int ranks = 1;
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    return ranks;
}
}  // namespace mmtest
