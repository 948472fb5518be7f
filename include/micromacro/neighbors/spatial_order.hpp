#pragma once
// An order of the particles in which partners are close in memory: row order through cells
// about a diameter wide, the box's shortest axis fastest, like the lines of a page. Random
// placement, deposition and long flows scatter the particles otherwise (measured in
// tests/benchmarks/throughput --shuffle). The pair loop, which goes through the particles in
// order, then reads a particle's partners from a few sequential streams (its own row, the row
// before, in 3D the layer before), which the hardware prefetches. A space-filling curve (Morton
// order, used before) keeps partners as close but in jumps no prefetcher follows: after the same
// shuffle the row order ran 1.24x faster in 3D (N = 100 000) and 1.40x in 2D (N = 200 000). With
// the shortest axes fastest a layer is as small as the box allows. Shorter rows, to bring the
// layer above closer in memory, lose too: row order within slabs 8 or 24 cells wide ran at 0.83x
// and 0.92x (3D N = 100 000, a throwaway prototype): the prefetchers want long rows. Untested:
// once one layer no longer fits the last-level cache (about 10^5 particles of ~370 bytes for
// 32 MB), a curve's locality may win again.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

#include "micromacro/core/index.hpp"
#include "micromacro/core/domain.hpp"

namespace micromacro {

namespace detail {
// Applies a permutation to every array it visits (an archive for serialize()): element k of
// each becomes its element order[k]. Arrays of another length (not sized yet) are left alone.
// In place, cycle by cycle: no second copy of an array (the engine sorts large scenes on its
// own, and its peak memory would otherwise grow by the largest array).
struct Permutation {
    const std::vector<Index>& order;
    template <class U>
    void array(std::vector<U>& a) const {
        const std::size_t n = order.size();
        if (a.size() != n) return;
        std::vector<bool> placed(n, false);
        for (std::size_t start = 0; start < n; ++start) {
            if (placed[start]) continue;
            U first = a[start];
            std::size_t k = start;
            while (order[k] != start) {  // k takes the element at order[k], which moves on in turn
                a[k] = a[order[k]];
                placed[k] = true;
                k = order[k];
            }
            a[k] = first;
            placed[k] = true;
        }
    }
};
}  // namespace detail

/// The mean of |j - i| over candidate pairs: how far apart in memory partners lie, the
/// measure of an order's decay (0 for no pairs). Summed in integers, exactly, so that processes
/// adding their parts get the same number (mpi/serial_order.hpp).
inline double mean_index_gap(const std::vector<IndexPair>& pairs) {
    std::uint64_t sum = 0;
    for (const IndexPair& p : pairs) sum += p.j > p.i ? p.j - p.i : p.i - p.j;
    return pairs.empty() ? 0.0 : double(sum) / double(pairs.size());
}

/// What a neighbour search does about the particles' order, given the candidates' mean index
/// gap now and `sorted`, the gap the last sort left (0: never sorted; negative: sorted since the
/// last search, which measures it): sort when never sorted or when the gap has doubled (the
/// order has decayed), as BasicSimulation::set_auto_sort describes. mpi::DistributedRun decides
/// by the same rule from the gap its ranks measure together.
enum class OrderAction { keep, measure, sort };
inline OrderAction order_action(double sorted, double gap) {
    if (sorted < 0.0) return OrderAction::measure;
    return sorted == 0.0 || gap > 2.0 * sorted ? OrderAction::sort : OrderAction::keep;
}

/// The row order's cells: each axis's lower end, the cell width and the axis's place in the key
/// (0 for the fastest, the shortest extent; ties by axis number). spatial_order sorts by key();
/// a process holding part of the scene builds the same cells from the whole scene's extents
/// (mpi::DistributedRun).
template <int dim>
class RowCells {
public:
    /// `lo` and `hi`: the extent along each axis (the box's along a periodic one, the particles'
    /// along the others); `cell`: the cells' width.
    RowCells(const std::array<double, dim>& lo, const std::array<double, dim>& hi, double cell) : lo_(lo), cell_(cell) {
        std::array<int, dim> axes;
        std::iota(axes.begin(), axes.end(), 0);
        std::stable_sort(axes.begin(), axes.end(), [&](int a, int b) { return hi[a] - lo[a] < hi[b] - lo[b]; });
        for (int place = 0; place < dim; ++place) rank_[axes[place]] = place;
    }
    /// The cell of position x as one number, in row order.
    template <class P>
    std::uint64_t key(const P& x) const {
        std::uint64_t k = 0;
        for (int a = 0; a < dim; ++a) {
            const double c = std::clamp(std::floor((double(x[a]) - lo_[a]) / cell_), 0.0, max_cell);
            k |= static_cast<std::uint64_t>(c) << (bits * rank_[a]);
        }
        return k;
    }

private:
    static constexpr int bits = 64 / dim;  // per axis: 32 in 2D, 21 in 3D
    static constexpr double max_cell = double((std::uint64_t{1} << bits) - 1);
    std::array<double, dim> lo_;
    std::array<int, dim> rank_;
    double cell_;
};

/// The permutation that sorts the particles in row order through cells `cell` wide (default:
/// the largest diameter), the axes taken from the shortest extent (fastest) to the longest:
/// `order[k]` is the particle that goes to index k. Ties (particles in one cell) keep their
/// present order, so the result is deterministic.
template <int dim, class Real>
std::vector<Index> spatial_order(const std::vector<Vec<dim, Real>>& x, const std::vector<Real>& r, const Domain<dim>& domain,
                                 double cell = 0.0) {
    const std::size_t n = x.size();
    std::vector<Index> order(n);
    std::iota(order.begin(), order.end(), Index{0});
    if (n < 2) return order;
    if (!(cell > 0.0)) cell = 2.0 * double(*std::max_element(r.begin(), r.end()));
    std::array<double, dim> lo, hi;
    for (int k = 0; k < dim; ++k) {
        lo[k] = domain.periodic(k) ? domain.lo()[k] : double(x[0][k]);
        hi[k] = domain.periodic(k) ? domain.hi()[k] : double(x[0][k]);
        if (!domain.periodic(k))
            for (const auto& p : x) lo[k] = std::min(lo[k], double(p[k])), hi[k] = std::max(hi[k], double(p[k]));
    }
    const RowCells<dim> cells(lo, hi, cell);
    std::vector<std::uint64_t> key(n);
    for (std::size_t i = 0; i < n; ++i) key[i] = cells.key(x[i]);
    std::stable_sort(order.begin(), order.end(), [&](Index a, Index b) { return key[a] < key[b]; });
    return order;
}

}  // namespace micromacro
