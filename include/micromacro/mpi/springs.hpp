#pragma once
// Springs by global ids: how a pair's spring travels between ranks and into a gathered scene
// (mpi::DistributedRun, mpi::whole_scene), and how a rank's engine takes them back.
#include <map>
#include <utility>

#include "micromacro/contact/tangential_history.hpp"
#include "micromacro/core/index.hpp"

namespace micromacro::mpi {

/// A pair's spring by the pair's global ids (a < b), as a sees it: how springs travel between
/// ranks and into a gathered scene (mpi/checkpoint.hpp).
template <class History>
struct PairSpring {
    Index a, b;
    History h;
    /// The spring of a pair whose particles have global ids `first` and `second`, as `first` sees it.
    static PairSpring of(Index first, Index second, const History& h) {
        return first < second ? PairSpring{first, second, h} : PairSpring{second, first, seen_from_partner(h)};
    }
};
template <class History>
using SpringsByPair = std::map<std::pair<Index, Index>, History>;

/// Every candidate pair's spring of `sim` from `springs`, its particles' global ids given by
/// `global_id(i)`; a pair without one starts anew.
template <class Sim, class GlobalId>
void restore_springs(Sim& sim, const SpringsByPair<typename Sim::History>& springs, GlobalId&& global_id) {
    sim.visit_pair_histories([&](Index i, Index j, typename Sim::History& h) {
        const Index a = global_id(i), b = global_id(j);
        const auto found = springs.find(a < b ? std::pair{a, b} : std::pair{b, a});
        if (found == springs.end()) h = {};
        else h = a < b ? found->second : seen_from_partner(found->second);
    });
}

/// Every candidate wall contact's spring of `sim` from `springs`, keyed by (global id of the
/// particle, wall); a contact without one starts anew.
template <class Sim, class GlobalId>
void restore_wall_springs(Sim& sim, const SpringsByPair<typename Sim::History>& springs, GlobalId&& global_id) {
    sim.visit_wall_histories([&](Index i, Index w, typename Sim::History& h) {
        const auto found = springs.find(std::pair{global_id(i), w});
        h = found == springs.end() ? typename Sim::History{} : found->second;
    });
}

}  // namespace micromacro::mpi
