#pragma once
// OpenMP without imposing it: compiled with -fopenmp the engine's loops run on the threads
// chosen by Simulation::set_threads; without it the pragmas vanish (no unknown-pragma warnings).
#include <cstddef>

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

}  // namespace micromacro::detail
