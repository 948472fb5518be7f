#pragma once
// The split's boundaries where the particles are (as LAMMPS's `balance ... shift`): along each
// axis of more than one slab, each inner boundary where an equal share of the particles lies
// below it, from a histogram of the particles along the axis added over the ranks
// (CartesianSplit::balanced_cuts). So the slabs of a box that the particles fill unevenly (a
// packing settled at the bottom, a lattice short of its box, a box of walls that deforms) keep
// equal shares. A boundary moves at most to a halo width of its neighbours at a time, so that a
// particle goes at most one slab on at a redistribution, and no slab gets narrower than the halo.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include <mpi.h>

#include "micromacro/mpi/communicator.hpp"

namespace micromacro::mpi {

/// Bins per slab of the histograms balance_split() draws.
inline constexpr int balance_bins_per_slab = 64;

/// Sets the split's cuts from the coordinates `coordinate(i, a)` of `n` particles: the ranks'
/// own particles, added over the ranks (`over_ranks`), or every particle on every rank (not
/// added). `width`: the halo width. `passes` > 1 moves each boundary again from where the last
/// pass left it, for a split not yet handed out (a run's start). A collective call where
/// `over_ranks`.
template <int dim, class Coordinate>
void balance_split(CartesianComm<dim>& comm, std::size_t n, Coordinate&& coordinate, double width, bool over_ranks, int passes = 1) {
    for (int a = 0; a < dim; ++a) {
        const CartesianSplit<dim>& split = comm.split();
        if (split.dims[a] == 1) continue;
        const int bins = balance_bins_per_slab * split.dims[a];
        const double lo = split.lo[a], L = split.hi[a] - split.lo[a];
        std::vector<double> counts(static_cast<std::size_t>(bins), 0.0);
        for (std::size_t i = 0; i < n; ++i) {
            const double k = std::floor((coordinate(i, a) - lo) / L * bins);  // outside the box (an open axis): the end bins
            counts[static_cast<std::size_t>(std::clamp(k, 0.0, double(bins - 1)))] += 1.0;
        }
        if (over_ranks)
            check(MPI_Allreduce(MPI_IN_PLACE, counts.data(), bins, MPI_DOUBLE, MPI_SUM, comm.comm()), "MPI_Allreduce (balance)");
        for (int pass = 0; pass < passes; ++pass) comm.set_cuts(a, split.balanced_cuts(a, counts, width));
    }
}

}  // namespace micromacro::mpi
