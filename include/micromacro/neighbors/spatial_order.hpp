#pragma once
// An order of the particles along a space-filling curve (Morton, or Z, order of cells about a
// diameter wide): particles close in space get close indices, so the pair loop finds a
// particle's partners in the cache lines it has just used. Random placement, deposition and
// long flows scatter them otherwise (measured in tests/benchmarks/throughput --shuffle).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

#include "micromacro/contact/contact_list.hpp"
#include "micromacro/core/domain.hpp"

namespace micromacro {

namespace detail {
// Spreads the low bits of v so that `dim` such values interleave: bit b moves to bit dim * b.
template <int dim>
std::uint64_t spread_bits(std::uint64_t v) {
    std::uint64_t out = 0;
    for (int b = 0; b < 64 / dim; ++b) out |= ((v >> b) & 1u) << (dim * b);
    return out;
}

// Applies a permutation to every array it visits (an archive for serialize()): element k of
// each becomes its element order[k]. Arrays of another length (not sized yet) are left alone.
struct Permutation {
    const std::vector<Index>& order;
    template <class U>
    void array(std::vector<U>& a) const {
        if (a.size() != order.size()) return;
        std::vector<U> sorted(a.size());
        for (std::size_t k = 0; k < a.size(); ++k) sorted[k] = a[order[k]];
        a.swap(sorted);
    }
};
}  // namespace detail

/// The permutation that sorts the particles along a Morton curve through cells `cell` wide
/// (default: the largest diameter): `order[k]` is the particle that goes to index k. Ties
/// (particles in one cell) keep their present order, so the result is deterministic.
template <int dim, class Real>
std::vector<Index> spatial_order(const std::vector<Vec<dim, Real>>& x, const std::vector<Real>& r, const Domain<dim>& domain,
                                 double cell = 0.0) {
    const std::size_t n = x.size();
    std::vector<Index> order(n);
    std::iota(order.begin(), order.end(), Index{0});
    if (n < 2) return order;
    if (!(cell > 0.0)) cell = 2.0 * double(*std::max_element(r.begin(), r.end()));
    std::array<double, dim> lo;
    for (int k = 0; k < dim; ++k) {
        lo[k] = domain.periodic(k) ? domain.lo()[k] : double(x[0][k]);
        if (!domain.periodic(k))
            for (const auto& p : x) lo[k] = std::min(lo[k], double(p[k]));
    }
    constexpr int bits = 64 / dim;  // per axis: 32 in 2D, 21 in 3D
    const double max_cell = std::ldexp(1.0, bits) - 1.0;
    std::vector<std::uint64_t> key(n);
    for (std::size_t i = 0; i < n; ++i) {
        std::uint64_t k = 0;
        for (int a = 0; a < dim; ++a) {
            const double c = std::clamp(std::floor((double(x[i][a]) - lo[a]) / cell), 0.0, max_cell);
            k |= detail::spread_bits<dim>(static_cast<std::uint64_t>(c)) << a;
        }
        key[i] = k;
    }
    std::stable_sort(order.begin(), order.end(), [&](Index a, Index b) { return key[a] < key[b]; });
    return order;
}

}  // namespace micromacro
