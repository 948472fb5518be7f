#pragma once
// How the pair loop is shared among threads. The candidates are sorted by their first particle
// i; each thread takes a nearly equal contiguous share, cut where i changes, and so owns the
// particles from its first i to the next share's first i: it writes their forces directly. Only
// a partner j past its own particles (j > i, so it belongs to a later thread) goes into the
// thread's spill list, which the owner adds after the loop, threads in order. With particles in
// spatial order the spill lists stay short. Bitwise the same for a fixed thread count.
#include <algorithm>
#include <cstddef>
#include <vector>

#include "micromacro/core/index.hpp"
#include "micromacro/core/parallel.hpp"
#include "micromacro/engine/pair_loop.hpp"

namespace micromacro::detail {

/// start[t] is where share t of `shares` begins among `count` candidates sorted by i;
/// start[shares] = count. A particle's run of pairs is never split.
inline void split_shares(const IndexPair* pair, std::size_t count, int shares, std::vector<std::size_t>& start) {
    start.assign(shares + 1, count);
    start[0] = 0;
    for (int t = 1; t < shares; ++t) {
        std::size_t c = std::max(start[t - 1], share_begin(count, t, shares));
        while (c > 0 && c < count && pair[c].i == pair[c - 1].i) ++c;  // do not split a particle's run
        start[t] = c;
    }
}

/// Adds to the particles [owned_begin, owned_end) what the shares before `share` spilled on
/// them, share by share in order.
template <int dim, class Real, bool rotation>
void add_spills(const std::vector<std::vector<Spill<dim, Real, rotation>>>& spills, int share, Index owned_begin, Index owned_end,
                Vec<dim, Real>* f, [[maybe_unused]] Angular<dim, Real>* torque) {
    for (int u = 0; u < share; ++u)
        for (const auto& s : spills[u]) {
            if (s.particle < owned_begin || s.particle >= owned_end) continue;
            f[s.particle] -= s.force;
            if constexpr (rotation) torque[s.particle] -= s.torque;
        }
}

}  // namespace micromacro::detail
