#pragma once
// How a pair's force and torque reach the particles' sums in the pair loops (engine/pair_loop.hpp,
// engine/packet_pair_loop.hpp): +force on i, -force on j, the torque arm times each radius; a
// partner owned by a later thread share goes into that share's spill list instead
// (engine/thread_shares.hpp).
#include <type_traits>
#include <vector>

#include "micromacro/contact/tangential_history.hpp"
#include "micromacro/core/dim_traits.hpp"
#include "micromacro/core/index.hpp"
#include "micromacro/core/inline.hpp"

namespace micromacro::detail {

/// What a thread's share of the pair loop owes a particle of a later share: subtracted from its
/// force and torque, as the partner of a pair.
template <int dim, bool rotation>
struct Spill {
    Index particle;
    Vec<dim> force;
    [[no_unique_address]] std::conditional_t<rotation, Angular<dim>, NoHistory> torque;
};

/// Adds the pair's force and torque to its partner j (-force, -r_j arm) if this share owns j,
/// else to the spill list.
template <int dim, bool rotation>
MICROMACRO_INLINE void add_partner_force(Index j, const Vec<dim>& force, [[maybe_unused]] const Angular<dim>& arm, double rj,
                                         Vec<dim>* f, [[maybe_unused]] Angular<dim>* torque, Index owned_end,
                                         std::vector<Spill<dim, rotation>>& spill) {
    using A = Angular<dim>;
    if (j < owned_end) [[likely]] {
        f[j] -= force;
        if constexpr (rotation) torque[j] -= A(rj * arm);
    } else {  // another thread's particle: added by its owner after the loop
        auto& s = spill.emplace_back();
        s.particle = j;
        s.force = force;
        if constexpr (rotation) s.torque = A(rj * arm);
    }
}

/// Adds the pair's force on i and its torque arm to i, and to j if this share owns it.
template <int dim, bool rotation>
MICROMACRO_INLINE void add_pair_force(Index i, Index j, const Vec<dim>& force, [[maybe_unused]] const Angular<dim>& arm,
                                      double ri, double rj, Vec<dim>* f, [[maybe_unused]] Angular<dim>* torque,
                                      Index owned_end, std::vector<Spill<dim, rotation>>& spill) {
    f[i] += force;
    if constexpr (rotation) torque[i] -= Angular<dim>(ri * arm);  // torque on i is (-a_i n) x f_t
    add_partner_force<dim, rotation>(j, force, arm, rj, f, torque, owned_end, spill);
}

}  // namespace micromacro::detail
