// The main of the MPI test programs: MPI started before their suites and finished after them.
#define BOOST_TEST_MODULE micromacro_mpi
#include <boost/test/unit_test.hpp>

#include "support/mpi_runtime.hpp"

using mmtest::MpiRuntime;
BOOST_TEST_GLOBAL_FIXTURE(MpiRuntime);
