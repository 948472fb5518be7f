#pragma once
// Particle numbers and the pairs that name two of them: what neighbour searches produce and
// contact lists keep.
#include <cstdint>

namespace micromacro {

using Index = std::uint32_t;

struct IndexPair {
    Index i, j;  ///< particle i and partner j (a particle with j > i, or a wall number)
    friend bool operator<(const IndexPair& a, const IndexPair& b) { return a.i != b.i ? a.i < b.i : a.j < b.j; }
    friend bool operator==(const IndexPair&, const IndexPair&) = default;
};

}  // namespace micromacro
