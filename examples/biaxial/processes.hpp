#pragma once
// The processes a biaxial run spans: one, or the ranks of MPI_COMM_WORLD under mpirun
// (biaxial_mpi, built with MICROMACRO_HAVE_MPI). A file that every process would write alike (the
// time series, run.json, the states) is written by the first; a failure there fails every
// process with its message, so that no process waits for one that has stopped.
#include <exception>
#include <functional>
#include <string>

#ifdef MICROMACRO_HAVE_MPI
#include <mpi.h>
#endif

#include <micromacro/core/error.hpp>

namespace biaxial {

inline int process_rank() {
    int rank = 0;
#ifdef MICROMACRO_HAVE_MPI
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
#endif
    return rank;
}

inline int process_count() {
    int count = 1;
#ifdef MICROMACRO_HAVE_MPI
    MPI_Comm_size(MPI_COMM_WORLD, &count);
#endif
    return count;
}

inline bool first_process() { return process_rank() == 0; }

/// `text` as the first process has it, on every process (a collective call).
inline std::string as_on_first(std::string text) {
#ifdef MICROMACRO_HAVE_MPI
    unsigned long long size = text.size();
    MPI_Bcast(&size, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
    text.resize(size);
    MPI_Bcast(text.data(), static_cast<int>(size), MPI_CHAR, 0, MPI_COMM_WORLD);
#endif
    return text;
}

/// Runs `work` on the first process only; if it fails, every process throws its message (a
/// collective call). With one process, `work`'s exception itself.
inline void on_first(const std::function<void()>& work) {
    if (process_count() == 1) return work();
    std::string failure;
    if (first_process()) try {
            work();
        } catch (const std::exception& e) {
            failure = *e.what() ? e.what() : "failed";
        }
    failure = as_on_first(failure);
    if (!failure.empty()) micromacro::throw_input_error(failure);
}

}  // namespace biaxial
