// What the engine's threading costs by itself: the time of an empty OpenMP parallel region and of a
// barrier inside one, on the given number of threads. A time step on T threads opens two parallel
// regions (the particle pass, the pair loop) and passes one barrier (before the spill lists are
// added), so this bounds the synchronisation cost of a step; what a step loses to two threads
// beyond it is imbalance (the host slowing one core). Measured, never asserted.
//   sync_cost [--threads 2] [--repeats 200000]
#include <chrono>
#include <cstdio>
#include <vector>

#include <CLI/CLI.hpp>

#include "../../examples/command_line.hpp"

#include "micromacro/core/parallel.hpp"

int main(int argc, char** argv) {
    CLI::App app{"Time of an empty OpenMP parallel region and of a barrier, per occurrence"};
    int threads = 2, repeats = 200000;
    app.add_option("--threads", threads, "threads in each region")->check(CLI::Range(1, 256));
    app.add_option("--repeats", repeats, "regions (and barriers) timed per trial")->check(CLI::Range(1, 100000000));
    MICROMACRO_PARSE_COMMAND_LINE(app, argc, argv);
#ifndef _OPENMP
    std::fprintf(stderr, "sync_cost: built without OpenMP, so there is nothing to time; build with -fopenmp\n");
    return 1;
#else
    // One counter per thread, a page apart, so that the work inside is not false sharing.
    std::vector<double> touched(static_cast<std::size_t>(threads) * 512, 0.0);
    using clock = std::chrono::steady_clock;
    auto per_repeat_us = [&](clock::time_point a, clock::time_point b) {
        return std::chrono::duration<double, std::micro>(b - a).count() / repeats;
    };
    std::printf("sync_cost: %d threads, %d repeats per trial, three trials\n", threads, repeats);
    for (int trial = 0; trial < 3; ++trial) {
        const auto t0 = clock::now();
        for (int r = 0; r < repeats; ++r) {
            MICROMACRO_OMP(omp parallel num_threads(threads)) { touched[512 * micromacro::detail::thread_number()] += 1.0; }
        }
        const auto t1 = clock::now();
        MICROMACRO_OMP(omp parallel num_threads(threads)) {
            for (int r = 0; r < repeats; ++r) {
                touched[512 * micromacro::detail::thread_number()] += 1.0;
                MICROMACRO_OMP(omp barrier)
            }
        }
        const auto t2 = clock::now();
        std::printf("  parallel region %.2f us, barrier %.2f us\n", per_repeat_us(t0, t1), per_repeat_us(t1, t2));
    }
    return touched[0] > 0.0 ? 0 : 1;
#endif
}
