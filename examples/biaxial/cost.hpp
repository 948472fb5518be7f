#pragma once
// What a biaxial run will cost, told before it starts: memory, the loading's steps and time, and
// the VTK frames' disk space; and the refusal of a run this machine cannot hold (more memory than
// it has, more frames than its disk's free space). The figures per particle are estimates built
// from measured parts (examples/biaxial/README.md, "What a run costs"), not limits.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <string>
#include <system_error>

#include "biaxial.hpp"

namespace biaxial {

struct Cost {
    double memory_bytes = 0;      ///< the process's peak, about
    double loading_steps = 0;     ///< T/2 + relax over dt (the preparation's steps come first, unknown)
    double loading_seconds = 0;   ///< the loading's steps at the measured rate, on `threads` threads
    std::size_t rows = 0;         ///< of timeseries.csv
    std::size_t vtk_frames = 0;   ///< particles, contacts and walls per frame
    double vtk_bytes = 0;         ///< all frames, about
};

/// Peak memory per particle, VTK bytes per particle and frame, and particle-steps per second of
/// one thread in the loading, by dimension (measured: README, "What a run costs").
struct CostPerParticle {
    double memory_bytes, vtk_bytes_per_frame, steps_per_second;
};
inline CostPerParticle cost_per_particle(int dim) {
    return dim == 2 ? CostPerParticle{900.0, 200.0, 2.5e7} : CostPerParticle{1500.0, 300.0, 1e7};
}
/// What a process holds besides the particles (the program, its libraries, VTK's).
inline constexpr double baseline_memory_bytes = 20e6;

inline Cost estimate_cost(const Config& c, std::size_t vtk_every_rows, int threads) {
    const CostPerParticle per = cost_per_particle(c.dim);
    const double n = static_cast<double>(c.particles), dt = c.time_step();
    Cost cost;
    cost.memory_bytes = baseline_memory_bytes + per.memory_bytes * n;
    const double loading = 0.5 * c.period + c.relax;
    cost.loading_steps = loading / dt;
    cost.loading_seconds = cost.loading_steps * n / (per.steps_per_second * std::max(1, threads));
    cost.rows = loading_rows(c, dt, loading);
    cost.vtk_frames = vtk_every_rows ? (cost.rows - 1) / vtk_every_rows + 1 : 0;
    cost.vtk_bytes = static_cast<double>(cost.vtk_frames) * per.vtk_bytes_per_frame * n;
    return cost;
}

/// "1.6 GB", "340 MB", "12 kB".
inline std::string bytes_text(double bytes) {
    char text[32];
    if (bytes >= 1e9) std::snprintf(text, sizeof text, "%.3g GB", bytes / 1e9);
    else if (bytes >= 1e6) std::snprintf(text, sizeof text, "%.3g MB", bytes / 1e6);
    else std::snprintf(text, sizeof text, "%.3g kB", bytes / 1e3);
    return text;
}

/// "40 s", "12 min", "3.4 h", "2.1 days".
inline std::string duration_text(double seconds) {
    char text[32];
    if (seconds < 120) std::snprintf(text, sizeof text, "%.2g s", seconds);
    else if (seconds < 7200) std::snprintf(text, sizeof text, "%.2g min", seconds / 60);
    else if (seconds < 172800) std::snprintf(text, sizeof text, "%.2g h", seconds / 3600);
    else std::snprintf(text, sizeof text, "%.2g days", seconds / 86400);
    return text;
}

/// One line for the user before the run starts.
inline std::string describe_cost(const Config& c, const Cost& cost, int threads) {
    std::string line = "biaxial " + std::to_string(c.dim) + "D: " + std::to_string(c.particles) + " particles; about " +
                       bytes_text(cost.memory_bytes) + " of memory; the loading " + std::to_string(std::llround(cost.loading_steps)) +
                       " steps, about " + duration_text(cost.loading_seconds) + " on " + std::to_string(threads) +
                       (threads == 1 ? " thread" : " threads") + " after the preparation; " + std::to_string(cost.rows) + " rows";
    if (cost.vtk_frames) line += "; " + std::to_string(cost.vtk_frames) + " VTK frames, about " + bytes_text(cost.vtk_bytes);
    return line;
}

/// A run worth a word even with --quiet: a gigabyte of memory or of frames, or an hour of loading.
inline bool is_large(const Cost& cost) { return cost.memory_bytes > 1e9 || cost.vtk_bytes > 1e9 || cost.loading_seconds > 3600; }

/// The machine's memory in bytes (0 if unknown).
inline double physical_memory_bytes() {
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
    return pages > 0 && page > 0 ? static_cast<double>(pages) * static_cast<double>(page) : 0.0;
}

/// Refuses a run whose memory exceeds the machine's, or whose VTK frames exceed the free space
/// under `out` (the nearest existing folder of it), with the limit and the fix.
inline void refuse_unaffordable(const Config& c, const Cost& cost, std::size_t vtk_every_rows, const std::filesystem::path& out) {
    const CostPerParticle per = cost_per_particle(c.dim);
    if (const double memory = physical_memory_bytes(); memory > 0 && cost.memory_bytes > memory)
        micromacro::throw_input_error("--particles ", c.particles, " needs about ", bytes_text(cost.memory_bytes),
                                      " of memory, more than this machine's ", bytes_text(memory), "; use --particles <= ",
                                      static_cast<std::size_t>((memory - baseline_memory_bytes) / per.memory_bytes));
    if (cost.vtk_frames == 0) return;
    std::filesystem::path existing = std::filesystem::absolute(out);
    while (!std::filesystem::exists(existing) && existing.has_parent_path() && existing != existing.parent_path())
        existing = existing.parent_path();
    std::error_code ec;
    const auto space = std::filesystem::space(existing, ec);
    if (ec || space.capacity == 0) return;  // no disk (/proc, say): the claim of the folder refuses it
    const double free = static_cast<double>(space.available);
    if (cost.vtk_bytes > free) {
        const double frames_that_fit = std::floor(free / (per.vtk_bytes_per_frame * static_cast<double>(c.particles)));
        const std::size_t every = frames_that_fit >= 2 ? static_cast<std::size_t>(std::ceil((cost.rows - 1) / (frames_that_fit - 1)))
                                                       : cost.rows;
        micromacro::throw_input_error("--vtk-every ", vtk_every_rows, " writes ", cost.vtk_frames, " VTK frames of about ",
                                      bytes_text(cost.vtk_bytes), ", more than the ", bytes_text(free), " free under ",
                                      existing.string(), "; use --vtk-every >= ", std::max<std::size_t>(every, vtk_every_rows + 1),
                                      " or --vtk-every 0");
    }
}

}  // namespace biaxial
