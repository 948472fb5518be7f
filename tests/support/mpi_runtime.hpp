#pragma once
// MPI started before a test module's cases and finished after them (BOOST_TEST_GLOBAL_FIXTURE).
#include <mpi.h>

namespace mmtest {
struct MpiRuntime {
    MpiRuntime() { MPI_Init(nullptr, nullptr); }
    ~MpiRuntime() { MPI_Finalize(); }
};
}  // namespace mmtest
