#pragma once
// Walls over MPI ranks (mpi::DistributedRun): the box the ranks split when walls alone bound the
// scene and how it follows the particles, the stress-controlled walls a split cannot measure, and
// the walls' forces summed over the ranks so that every rank moves the walls by the same numbers.
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <variant>
#include <vector>

#include <mpi.h>

#include "micromacro/core/dim_traits.hpp"
#include "micromacro/core/domain.hpp"
#include "micromacro/core/error.hpp"
#include "micromacro/core/index.hpp"
#include "micromacro/engine/wall_contacts.hpp"
#include "micromacro/mpi/communicator.hpp"
#include "micromacro/walls/motion.hpp"

namespace micromacro::mpi {

/// The extent of the first `count` particles of `p`, [min (x - r), max (x + r)] per axis, over
/// every rank of `over` (MPI_COMM_NULL: this rank's alone); infinite bounds when there are none.
template <int dim, class Particles>
std::pair<Vec<dim>, Vec<dim>> particle_extent(const Particles& p, std::size_t count, MPI_Comm over) {
    std::array<double, 2 * dim> extent;  // -lo, then hi: one MPI_MAX
    extent.fill(-std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < count; ++i)
        for (int a = 0; a < dim; ++a) {
            const double x = p.position()[i][a], r = p.radius()[i];
            extent[a] = std::max(extent[a], -(x - r));
            extent[dim + a] = std::max(extent[dim + a], x + r);
        }
    if (over != MPI_COMM_NULL)
        check(MPI_Allreduce(MPI_IN_PLACE, extent.data(), 2 * dim, MPI_DOUBLE, MPI_MAX, over), "MPI_Allreduce (extent)");
    Vec<dim> lo, hi;
    for (int a = 0; a < dim; ++a) lo[a] = -extent[a], hi[a] = extent[dim + a];
    return {lo, hi};
}

/// The box the ranks split: the scene's, or for a scene without bounds (walls alone, as the
/// biaxial test's), the particles' extent at the start; particles that leave it later belong to
/// the end slabs (CartesianSplit::slab). `shares`: the communicator over which the particles are
/// shared out (their extent is taken over all of them), or MPI_COMM_NULL when `scene` holds them
/// all.
template <class Sim>
Domain<Sim::dimension> split_box(const Sim& scene, MPI_Comm shares = MPI_COMM_NULL) {
    constexpr int dim = Sim::dimension;
    const Domain<dim>& d = scene.domain();
    bool bounded = true;
    for (int a = 0; a < dim; ++a) bounded = bounded && d.hi()[a] > d.lo()[a];
    if (bounded) return d;
    const auto [lo, hi] = particle_extent<dim>(scene.particles(), scene.particles().size(), shares);
    if (!(lo[0] < std::numeric_limits<double>::infinity())) return d;  // no particles: CartesianSplit refuses it
    std::array<bool, dim> periodic{};
    for (int a = 0; a < dim; ++a) periodic[a] = d.periodic(a);
    return Domain<dim>(lo, hi, periodic);
}

/// The axes along which the split follows the particles: those the scene leaves unbounded (a
/// box of walls alone), where split_box took the particles' extent.
template <class Sim>
std::array<bool, Sim::dimension> following_axes(const Sim& whole) {
    std::array<bool, Sim::dimension> follows{};
    for (int a = 0; a < Sim::dimension; ++a) follows[a] = !whole.domain().periodic(a) && !(whole.domain().hi()[a] > whole.domain().lo()[a]);
    return follows;
}

/// Moves the split's box along the `follows` axes to the particles' extent now, over every
/// rank's first `owned` particles (a collective call): as the walls compress or widen the box,
/// the slabs keep equal shares of it.
template <int dim, class Particles>
void follow_extent(CartesianComm<dim>& comm, const Particles& p, std::size_t owned, const std::array<bool, dim>& follows) {
    bool any = false;
    for (bool f : follows) any = any || f;
    if (!any) return;
    const auto [lo, hi] = particle_extent<dim>(p, owned, comm.comm());
    comm.move_box(lo, hi, follows);
}

/// Refuses a stress-controlled wall that measures its area along a periodic axis split over
/// ranks: a rank's engine sees its slab there, not the period.
template <int dim, class Walls>
void check_wall_areas(const Walls& walls, const CartesianSplit<dim>& split) {
    for (std::size_t k = 0; k < walls.size(); ++k) {
        const auto* s = std::get_if<StressControlled>(&walls[k].motion);
        if (!s || s->area > 0.0) continue;
        for (int a = 0; a < dim; ++a)
            if (split.periodic[a] && split.dims[a] > 1 && walls[k].axis() != a)
                micromacro::detail::throw_input_error("stress-controlled wall ", k, " measures its area along periodic axis ", a,
                                                      ", which is split over ", split.dims[a],
                                                      " ranks (a rank's engine sees its slab, not the period); give "
                                                      "StressControlled::area");
    }
}

/// The walls' forces, each rank's share of them summed over the ranks in rank order (the same
/// numbers on every rank; one rank keeps its own bits). A collective call.
template <int dim, class Walls>
void sum_wall_forces(Walls& walls, const CartesianComm<dim>& comm) {
    const std::size_t n = walls.size() * dim;
    if (n == 0) return;
    std::vector<double> mine(n), all(n * static_cast<std::size_t>(comm.size()));
    for (std::size_t k = 0; k < walls.size(); ++k)
        for (int a = 0; a < dim; ++a) mine[k * dim + a] = walls[k].force[a];
    check(MPI_Allgather(mine.data(), static_cast<int>(n), MPI_DOUBLE, all.data(), static_cast<int>(n), MPI_DOUBLE, comm.comm()),
          "MPI_Allgather (wall forces)");
    for (std::size_t k = 0; k < walls.size(); ++k) {
        Vec<dim> f = Vec<dim>::Zero();
        for (int r = 0; r < comm.size(); ++r)
            for (int a = 0; a < dim; ++a) f[a] += all[std::size_t(r) * n + k * dim + a];
        walls[k].force = f;
    }
}

/// The walls' forces as the serial run sums them, on any number of ranks: every rank's wall
/// candidates' parts (BasicSimulation::wall_terms) go to every rank, which subtracts them from
/// zero in the order of their particles' places in the serial numbering, as the serial wall loop
/// does in the order of the particles (a candidate that does not touch adds a zero, which changes
/// no sum). The candidates change only when the engines rebuild their lists, so their order over
/// the ranks is arranged at the first sum after a rebuild (the engines' prepare(); `rearrange`)
/// and each evaluation sends only the forces: one MPI_Allgather of dim numbers per candidate,
/// which every rank receives, a volume that does not shrink as ranks are added (docs/mpi.md).
template <int dim>
class SerialWallSum {
public:
    using Terms = std::vector<micromacro::detail::WallTerm<dim>>;

    /// The engines' lists were built again: the next sum arranges the candidates anew.
    void rearrange() { arranged_ = false; }

    /// The walls' forces from this evaluation's parts (`place`: the serial place of each local
    /// particle). A collective call.
    template <class Walls>
    void sum(Walls& walls, const Terms& terms, const std::vector<Index>& place, const CartesianComm<dim>& comm) {
        if (!arranged_) arrange(terms, place, comm);
        // Each rank's parts, then its count of candidates, which every rank checks against the
        // arrangement's (so that all ranks stop together if an engine rebuilt its lists unseen).
        const std::size_t stride = width_ * dim + 1;
        mine_.assign(stride, 0.0);
        for (std::size_t c = 0; c < std::min(terms.size(), width_); ++c)
            for (int a = 0; a < dim; ++a) mine_[c * dim + a] = terms[c].force[a];
        mine_.back() = double(terms.size());
        all_.resize(stride * static_cast<std::size_t>(comm.size()));
        check(MPI_Allgather(mine_.data(), static_cast<int>(stride), MPI_DOUBLE, all_.data(), static_cast<int>(stride), MPI_DOUBLE,
                            comm.comm()),
              "MPI_Allgather (wall forces)");
        for (int r = 0; r < comm.size(); ++r)
            if (all_[std::size_t(r) * stride + stride - 1] != double(counts_[std::size_t(r)]))
                micromacro::detail::throw_input_error("SerialWallSum: rank ", r, " has ", all_[std::size_t(r) * stride + stride - 1],
                                                      " wall candidates, arranged for ", counts_[std::size_t(r)],
                                                      " (its engine rebuilt its lists without rearrange())");
        for (auto& wall : walls) wall.force = Vec<dim>::Zero();
        for (std::size_t k = 0; k < order_.size(); ++k) {
            Vec<dim> f;
            for (int a = 0; a < dim; ++a) f[a] = all_[order_[k] + std::size_t(a)];
            walls[wall_[k]].force -= f;
        }
    }

private:
    /// The order of every rank's candidates, by key: the particle's place, then the wall.
    void arrange(const Terms& terms, const std::vector<Index>& place, const CartesianComm<dim>& comm) {
        std::vector<std::uint64_t> mine(terms.size());
        for (std::size_t c = 0; c < terms.size(); ++c) mine[c] = (std::uint64_t(place[terms[c].particle]) << 32) | terms[c].wall;
        const int ranks = comm.size(), count = static_cast<int>(mine.size());
        std::vector<int> counts(static_cast<std::size_t>(ranks)), offsets(static_cast<std::size_t>(ranks), 0);
        check(MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm.comm()), "MPI_Allgather (wall candidates)");
        for (int r = 1; r < ranks; ++r) offsets[std::size_t(r)] = offsets[std::size_t(r) - 1] + counts[std::size_t(r) - 1];
        std::vector<std::uint64_t> keys(static_cast<std::size_t>(offsets.back() + counts.back()));
        check(MPI_Allgatherv(mine.data(), count, MPI_UINT64_T, keys.data(), counts.data(), offsets.data(), MPI_UINT64_T, comm.comm()),
              "MPI_Allgatherv (wall candidates)");
        // Each rank's parts padded to the largest count, so that an evaluation needs one
        // MPI_Allgather, as the sums in rank order do: candidate c of rank r at r * stride + c dim.
        width_ = static_cast<std::size_t>(*std::max_element(counts.begin(), counts.end()));
        const std::size_t stride = width_ * dim + 1;
        std::vector<std::pair<std::uint64_t, std::size_t>> sorted(keys.size());  // key, where its force goes
        for (int r = 0; r < ranks; ++r)
            for (int c = 0; c < counts[std::size_t(r)]; ++c) {
                const std::size_t k = std::size_t(offsets[std::size_t(r)] + c);
                sorted[k] = {keys[k], std::size_t(r) * stride + std::size_t(c) * dim};
            }
        std::sort(sorted.begin(), sorted.end());
        order_.resize(sorted.size());
        wall_.resize(sorted.size());
        for (std::size_t k = 0; k < sorted.size(); ++k) {
            order_[k] = sorted[k].second;
            wall_[k] = static_cast<Index>(sorted[k].first & 0xffffffffu);
        }
        counts_ = std::move(counts);
        arranged_ = true;
    }

    std::vector<std::size_t> order_;  // the candidates over the ranks by key: where each one's force sits
    std::vector<Index> wall_;         // the wall of each, in that order
    std::vector<int> counts_;         // each rank's candidates
    std::vector<double> mine_, all_;  // this rank's parts padded to width_ and its count, and every rank's
    std::size_t width_ = 0;
    bool arranged_ = false;
};

}  // namespace micromacro::mpi
