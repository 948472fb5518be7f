#pragma once
// What the engine asks of a neighbour search (BruteForce, LinkedCells, or a user's own).
#include <vector>

#include "micromacro/core/domain.hpp"
#include "micromacro/core/index.hpp"

namespace micromacro {

/// A neighbour search: find_pairs(x, r, domain, skin, out) appends to `out`, sorted by (i, j),
/// every pair i < j whose surfaces are closer than `skin` (measured by the domain's minimum
/// image). It may keep scratch between calls (non-const).
template <class N, int dim, class Real>
concept NeighborSearch = requires(N& search, const std::vector<Vec<dim, Real>>& x, const std::vector<Real>& r,
                                  const Domain<dim>& domain, double skin, std::vector<IndexPair>& out) {
    search.find_pairs(x, r, domain, skin, out);
};

}  // namespace micromacro
