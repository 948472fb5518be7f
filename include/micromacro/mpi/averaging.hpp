#pragma once
// The micro-macro averages and coarse-grained fields of a scene run over MPI ranks
// (DistributedRun): each rank adds its own particles and the contacts it is the one to count,
// and the sums are added over the ranks before the tensors are derived (micro_macro.hpp's average_sums and finish_average), so the
// region, the selection rules and the options are the serial ones. A contact is counted by the
// rank that owns its partner of smaller global id; that rank holds the other partner too (as a
// ghost if another rank owns it), since the halo reaches past the contact distance. Rattlers
// are peeled over the ranks: each rank drops its particles with fewer than dim + 1 contacts with
// the others left, sends the flags to the ranks that hold them as ghosts, and repeats until no
// rank drops one (the same set as the serial peel: the largest in which every particle keeps
// dim + 1 contacts).
#include <algorithm>
#include <cstddef>
#include <vector>

#include <mpi.h>

#include "micromacro/averaging/coarse_graining.hpp"
#include "micromacro/averaging/micro_macro.hpp"
#include "micromacro/averaging/region.hpp"
#include "micromacro/engine/snapshot.hpp"
#include "micromacro/mpi/communicator.hpp"
#include "micromacro/mpi/distributed_run.hpp"

namespace micromacro::mpi {

/// This rank's part of the whole scene's snapshot: its particles [0, run.owned()) and its ghosts,
/// its contacts, the walls (every rank's are the same, with the forces summed over the ranks), the
/// whole box, positions and contact points wrapped into it.
/// A collective call: it brings the ghosts up to date first.
template <class Sim>
PackingSnapshot<Sim::dimension> local_snapshot(DistributedRun<Sim>& run) {
    run.refresh_ghosts();
    PackingSnapshot<Sim::dimension> s = take_snapshot(run.local());
    s.domain = run.box();
    for (auto& c : s.contacts) s.domain.wrap(c.point);
    return s;
}

namespace averaging_detail {
/// Which of the snapshot's particles and contacts this rank adds.
template <class Sim>
AveragingShare share_of(const DistributedRun<Sim>& run, const PackingSnapshot<Sim::dimension>& s) {
    AveragingShare share;
    share.particle.assign(s.size(), 0);
    for (std::size_t p = 0; p < run.owned(); ++p) share.particle[p] = 1;
    share.contact.resize(s.contacts.size());
    for (std::size_t q = 0; q < s.contacts.size(); ++q) {
        const auto& c = s.contacts[q];
        const std::size_t counter = c.wall || run.global_id(c.i) < run.global_id(c.j) ? c.i : c.j;
        share.contact[q] = counter < run.owned();
    }
    return share;
}

/// The rattlers among the snapshot's particles, peeled over all ranks (see the top).
template <class Sim>
std::vector<char> rattlers(const DistributedRun<Sim>& run, const PackingSnapshot<Sim::dimension>& s) {
    constexpr int dim = Sim::dimension;
    const std::size_t n = s.size(), owned = run.owned();
    std::vector<int> wall_contacts(owned, 0);
    std::vector<std::vector<std::size_t>> partners(owned);
    for (const auto& c : s.contacts) {
        if (c.wall) {
            if (c.i < owned) ++wall_contacts[c.i];
            continue;
        }
        if (c.i < owned) partners[c.i].push_back(c.j);
        if (c.j < owned) partners[c.j].push_back(c.i);
    }
    std::vector<char> rattler(n, 0);
    for (;;) {
        int dropped = 0;
        for (std::size_t p = 0; p < owned; ++p) {
            if (rattler[p]) continue;
            int count = wall_contacts[p];
            for (const std::size_t q : partners[p]) count += !rattler[q];
            if (count < dim + 1) rattler[p] = 1, dropped = 1;
        }
        const std::vector<char> mine(rattler.begin(), rattler.begin() + static_cast<std::ptrdiff_t>(owned));
        const std::vector<char> ghosts = run.halo().forward(run.comm(), mine);
        std::copy(ghosts.begin(), ghosts.end(), rattler.begin() + static_cast<std::ptrdiff_t>(owned));
        int anywhere = 0;
        check(MPI_Allreduce(&dropped, &anywhere, 1, MPI_INT, MPI_MAX, run.comm().comm()), "MPI_Allreduce (rattlers)");
        if (!anywhere) return rattler;
    }
}
}  // namespace averaging_detail

/// The average over `region` of the whole scene a DistributedRun steps, the same on every rank
/// (a collective call: every rank must make it; it brings the ghosts up to date first).
template <class Sim>
MicroMacro<Sim::dimension> average(DistributedRun<Sim>& run, const Region<Sim::dimension>& region,
                                   const AveragingOptions& opt = {}) {
    const auto s = local_snapshot(run);
    const AveragingShare share = averaging_detail::share_of(run, s);
    const auto weights = contact_weights(s, region, opt, averaging_detail::rattlers(run, s));
    AverageSums<Sim::dimension> sums = average_sums(s, region, opt, weights, &share);
    add_over_ranks(sums, run.comm().comm(), "MPI_Allreduce (averages)");
    return finish_average(sums, region.volume());
}

/// The coarse-grained fields of the whole scene a DistributedRun steps on `grid`, the same on
/// every rank (a collective call): each rank spreads its own particles and the contacts it
/// counts, and the grids are added over the ranks (every rank holds the whole grid).
template <class Sim, CoarseGrainingKernel Kernel>
CoarseGrainedFields<Sim::dimension> coarse_grain(DistributedRun<Sim>& run, const Grid<Sim::dimension>& grid, const Kernel& kernel,
                                                 const AveragingOptions& opt = {}) {
    constexpr int dim = Sim::dimension;
    const auto s = local_snapshot(run);
    const AveragingShare share = averaging_detail::share_of(run, s);
    const auto weights = contact_weights(s, Region<dim>::whole(s), opt, averaging_detail::rattlers(run, s));
    CoarseGrainedFields<dim> f = micromacro::coarse_grain(s, grid, kernel, opt, weights, &share);
    add_over_ranks(f, run.comm().comm(), "MPI_Allreduce (coarse-grained fields)");
    return f;
}

}  // namespace micromacro::mpi
