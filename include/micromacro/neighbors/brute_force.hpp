#pragma once
// O(N^2) neighbour search: every pair is tested. The reference the tests hold the linked-cell
// search to, and a fine choice below a few hundred particles.
#include <vector>

#include "micromacro/core/index.hpp"
#include "micromacro/core/domain.hpp"

namespace micromacro {

struct BruteForce {
    /// Appends to `out`, sorted by (i, j), every pair i < j whose surfaces are closer than `skin`.
    template <int dim, class Real>
    void find_pairs(const std::vector<Vec<dim, Real>>& x, const std::vector<Real>& r, const Domain<dim>& domain,
                    double skin, std::vector<IndexPair>& out) const {
        const auto n = static_cast<Index>(x.size());
        for (Index i = 0; i < n; ++i)
            for (Index j = i + 1; j < n; ++j) {
                const double reach = double(r[i]) + double(r[j]) + skin;
                if (domain.separation(convert<double>(x[i]), convert<double>(x[j])).squaredNorm() < reach * reach)
                    out.push_back({i, j});
            }
    }
};

}  // namespace micromacro
