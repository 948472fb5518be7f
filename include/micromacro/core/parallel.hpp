#pragma once
// OpenMP without imposing it: compiled with -fopenmp the engine's loops run on the threads
// chosen by Simulation::set_threads; without it the pragmas vanish (no unknown-pragma warnings).
#include <cstddef>

#include "micromacro/core/error.hpp"

#ifdef _OPENMP
#include <omp.h>
#define MICROMACRO_OMP(directive) _Pragma(#directive)
#else
#define MICROMACRO_OMP(directive)
#endif

namespace micromacro::detail {

/// Start of share `t` of `count` items split into `shares` contiguous, nearly equal parts.
inline std::size_t share_begin(std::size_t count, int t, int shares) {
    return count * static_cast<std::size_t>(t) / static_cast<std::size_t>(shares);
}

inline int thread_number() {
#ifdef _OPENMP
    return omp_get_thread_num();
#else
    return 0;
#endif
}

/// The number of threads in the current parallel region (1 outside one, or without OpenMP).
inline int thread_count() {
#ifdef _OPENMP
    return omp_get_num_threads();
#else
    return 1;
#endif
}

}  // namespace micromacro::detail

namespace micromacro {

/// Refuses a thread count the engine cannot run (Simulation::set_threads): 1 up to four times
/// OpenMP's threads, or 1 without OpenMP. Programs check it before they write anything.
inline void check_thread_count(int threads) {
#ifdef _OPENMP
    if (threads < 1 || threads > omp_get_max_threads() * 4)
        detail::throw_input_error("threads = ", threads, " is outside 1..", omp_get_max_threads() * 4,
                                  "; use up to the number of cores (", omp_get_num_procs(), " here)");
#else
    if (threads != 1)
        detail::throw_input_error("threads = ", threads, " needs OpenMP, but this program was compiled without "
                                  "it; compile with -fopenmp (CMake: link OpenMP::OpenMP_CXX) or use 1 thread");
#endif
}

}  // namespace micromacro
