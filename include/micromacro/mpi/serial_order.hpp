#pragma once
// The serial engine's spatial sorts followed over the ranks (mpi::DistributedRun). The serial
// engine renumbers its particles in row order when the candidates' mean index gap has doubled
// since its last sort (neighbors/spatial_order.hpp, order_action). At each neighbour search where
// the serial engine searches, the ranks measure that gap in the serial numbering together, decide
// by the same rule, and where it sorts they renumber the particles' places in the serial
// numbering as its sort renumbers its indices: by cell in row order over the whole scene's
// extents (RowCells), ties by the places before. So every rank count sums each particle's forces
// in the serial engine's order, sorted or not. The ranks' own numbering does not change.
#include <algorithm>
#include <array>
#include <compare>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include <mpi.h>

#include "micromacro/core/domain.hpp"
#include "micromacro/core/index.hpp"
#include "micromacro/mpi/communicator.hpp"
#include "micromacro/mpi/halo.hpp"
#include "micromacro/neighbors/spatial_order.hpp"

namespace micromacro::mpi {

class SerialOrder {
public:
    SerialOrder() = default;
    /// The serial scene's sorting as rank 0 holds it, the same on every rank afterwards: `on`,
    /// its set_auto_sort; `applies`, whether it sorts a scene of this size
    /// (auto_sort_min_particles); `sorted_gap`, SearchState::sorted_gap; `sorts`, its count.
    SerialOrder(MPI_Comm comm, bool on, bool applies, double sorted_gap, std::size_t sorts) {
        double state[4] = {double(on), double(applies), sorted_gap, double(sorts)};
        check(MPI_Bcast(state, 4, MPI_DOUBLE, 0, comm), "MPI_Bcast (the serial sorting)");
        on_ = state[0] != 0.0, applies_ = on_ && state[1] != 0.0, sorted_gap_ = state[2];
        sorts_ = static_cast<std::size_t>(state[3]);
    }

    bool on() const { return on_; }
    double sorted_gap() const { return sorted_gap_; }
    std::size_t sorts() const { return sorts_; }

    /// What the serial engine does about its order at this search (order_action): `gap()` gives
    /// the candidates' mean gap over the ranks (mean_gap), asked only where the engine sorts this
    /// scene. A measure is recorded here; after a sort the caller renumbers (sorted_places),
    /// searches again and reports the new gap to sorted().
    template <class Gap>
    OrderAction at_search(Gap&& gap) {
        if (!applies_) return OrderAction::keep;
        const std::optional<double> now = gap();
        if (!now) return OrderAction::keep;  // no candidates anywhere
        const OrderAction action = order_action(sorted_gap_, *now);
        if (action == OrderAction::measure) sorted_gap_ = *now;
        return action;
    }
    void sorted(double gap) { sorted_gap_ = gap, ++sorts_; }

    /// The candidates' mean gap in the serial numbering over the ranks (mean_index_gap of the
    /// serial engine's list): `visit(f)` calls f(i, j) for this rank's candidate pairs, `place(i)`
    /// is local particle i's place, the first `owned` particles are this rank's. A pair with a
    /// ghost is on its two owners' lists; the owner of its particle of smaller place counts it.
    /// Integer sums, so the result has the serial engine's bits. A collective call; nullopt where
    /// no rank has a candidate.
    template <class Visit, class Place>
    static std::optional<double> mean_gap(MPI_Comm comm, Visit&& visit, Place&& place, std::size_t owned) {
        unsigned long long here[2] = {0, 0}, all[2] = {0, 0};  // the gaps' sum, the pairs
        visit([&](Index i, Index j) {
            const Index a = place(i), b = place(j);
            const Index first = a < b ? i : j;
            if (first >= owned) return;  // the ghost's owner counts it
            here[0] += a < b ? b - a : a - b;
            ++here[1];
        });
        check(MPI_Allreduce(here, all, 2, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm), "MPI_Allreduce (index gaps)");
        if (all[1] == 0) return std::nullopt;
        return double(all[0]) / double(all[1]);
    }

    /// The places of this rank's first `owned` particles (positions x, radii r, places `place(i)`)
    /// after the serial engine's sort: each particle's rank by (cell, place) among every rank's
    /// particles, the cells those spatial_order draws over the whole scene (the box along periodic
    /// axes, the particles' extent along the others, a cell the largest diameter wide). The ranks'
    /// sorted keys pass round the ring of ranks, each rank counting the keys below its own: every
    /// rank holds one other rank's share at a time. A collective call.
    template <int dim, class Positions, class Radii, class Place>
    static std::vector<Index> sorted_places(MPI_Comm comm, const Domain<dim>& box, const Positions& x, const Radii& r,
                                            Place&& place, std::size_t owned) {
        constexpr double none = -std::numeric_limits<double>::infinity();
        std::array<double, 2 * dim + 1> extent;  // -lowest and highest along each axis, the largest radius
        extent.fill(none);
        for (std::size_t i = 0; i < owned; ++i) {
            for (int a = 0; a < dim; ++a)
                extent[a] = std::max(extent[a], -double(x[i][a])), extent[dim + a] = std::max(extent[dim + a], double(x[i][a]));
            extent[2 * dim] = std::max(extent[2 * dim], double(r[i]));
        }
        check(MPI_Allreduce(MPI_IN_PLACE, extent.data(), 2 * dim + 1, MPI_DOUBLE, MPI_MAX, comm), "MPI_Allreduce (extents)");
        std::array<double, dim> lo, hi;
        for (int a = 0; a < dim; ++a) {
            lo[a] = box.periodic(a) ? box.lo()[a] : -extent[a];
            hi[a] = box.periodic(a) ? box.hi()[a] : extent[dim + a];
        }
        const RowCells<dim> cells(lo, hi, 2.0 * extent[2 * dim]);
        std::vector<std::pair<Key, std::size_t>> mine(owned);
        for (std::size_t i = 0; i < owned; ++i) mine[i] = {Key{cells.key(x[i]), place(i)}, i};
        std::sort(mine.begin(), mine.end());
        std::vector<Key> passing(owned);
        for (std::size_t k = 0; k < owned; ++k) passing[k] = mine[k].first;
        std::vector<std::uint64_t> below(owned, 0);
        int ranks = 1, rank = 0;
        check(MPI_Comm_size(comm, &ranks), "MPI_Comm_size");
        check(MPI_Comm_rank(comm, &rank), "MPI_Comm_rank");
        for (int turn = 0; turn < ranks; ++turn) {
            std::size_t b = 0;  // both sorted: one pass
            for (std::size_t k = 0; k < owned; ++k) {
                while (b < passing.size() && passing[b] < mine[k].first) ++b;
                below[k] += b;
            }
            if (turn + 1 < ranks) passing = halo_detail::shift(comm, passing, (rank + 1) % ranks, (rank + ranks - 1) % ranks);
        }
        std::vector<Index> places(owned);
        for (std::size_t k = 0; k < owned; ++k) places[mine[k].second] = static_cast<Index>(below[k]);
        return places;
    }

private:
    struct Key {
        std::uint64_t cell, place;
        friend auto operator<=>(const Key&, const Key&) = default;
    };

    bool on_ = false, applies_ = false;
    double sorted_gap_ = 0.0;
    std::size_t sorts_ = 0;
};

}  // namespace micromacro::mpi
