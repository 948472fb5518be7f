#pragma once
// Particle numbers and the pairs that name two of them: what neighbour searches produce and
// contact lists keep.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace micromacro {

using Index = std::uint32_t;

struct IndexPair {
    Index i, j;  ///< particle i and partner j (a particle with j > i, or a wall number)
    friend bool operator<(const IndexPair& a, const IndexPair& b) { return a.i != b.i ? a.i < b.i : a.j < b.j; }
    friend bool operator==(const IndexPair&, const IndexPair&) = default;
};

/// Where `numbers` stops being a permutation of 0..size-1: the first entry out of range or named
/// before, or numbers.size() if it is one (particle ids, a renumbering's order).
inline std::size_t first_not_permuted(const std::vector<Index>& numbers) {
    std::vector<bool> seen(numbers.size(), false);
    for (std::size_t k = 0; k < numbers.size(); ++k) {
        if (numbers[k] >= numbers.size() || seen[numbers[k]]) return k;
        seen[numbers[k]] = true;
    }
    return numbers.size();
}

}  // namespace micromacro
