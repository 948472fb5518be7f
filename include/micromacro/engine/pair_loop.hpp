#pragma once
// The one pair loop: forces and torques of every touching candidate pair in a range of the
// contact list, through the contact law, into the particles' accumulators. The engine calls it
// once per thread share (engine/thread_shares.hpp); a partner owned by a later share goes into a
// spill list instead of its accumulator.
#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <vector>

#include "micromacro/contact/contact_law.hpp"
#include "micromacro/contact/geometry.hpp"
#include "micromacro/core/dim_traits.hpp"
#include "micromacro/core/domain.hpp"
#include "micromacro/core/energy.hpp"
#include "micromacro/core/index.hpp"
#include "micromacro/core/inline.hpp"
#include "micromacro/core/roots.hpp"
#include "micromacro/engine/contact_response.hpp"
#include "micromacro/engine/packet_pair_loop.hpp"
#include "micromacro/engine/pair_force_sums.hpp"

namespace micromacro::detail {

/// The stored arrays the pair and wall loops read, as raw pointers: the particles' (`w` null
/// without rotation) and one contact list's (`history` null for a law without history); and
/// where the ghosts begin (none by default; see pair_loop).
template <int dim, class Real, class History>
struct ContactLoopInput {
    const Vec<dim, Real>* x;
    const Vec<dim, Real>* v;
    const Real* r;
    const Real* inverse_mass;
    const Angular<dim, Real>* w;
    const IndexPair* pair;
    History* history;
    Index first_ghost = std::numeric_limits<Index>::max();
};

/// The velocity, relative to j, of the image of j that the pair (i, j) at separation d
/// (Domain::separation) meets: Domain::image_velocity of its shift x_i - x_j - d (zero for a pair
/// that crosses no boundary, where the shift is exactly zero). For a moving cell only.
template <int dim, class Real, class History>
MICROMACRO_INLINE Vec<dim> pair_image_velocity(const ContactLoopInput<dim, Real, History>& in, const Domain<dim>& domain, Index i,
                                               Index j, const Vec<dim>& d) {
    return domain.image_velocity(Vec<dim>(convert<double>(in.x[i]) - convert<double>(in.x[j]) - d));
}

/// v_i - v_j of the pair (i, j) at separation d, j's image moving with a moving cell.
template <int dim, class Real, class History>
MICROMACRO_INLINE Vec<dim> pair_velocity_difference(const ContactLoopInput<dim, Real, History>& in, const Domain<dim>& domain,
                                                    Index i, Index j, const Vec<dim>& d) {
    Vec<dim> dv = convert<double>(in.v[i]) - convert<double>(in.v[j]);
    if (domain.moving()) [[unlikely]] dv -= pair_image_velocity(in, domain, i, j, d);
    return dv;
}

/// v_ij of Eq. 25 for the pair (i, j) at separation d with normal n, read from the stored arrays
/// (for the passes outside the pair loop, which has v_i - v_j at hand already).
template <bool rotation, int dim, class Real, class History>
MICROMACRO_INLINE Vec<dim> pair_point_velocity(const ContactLoopInput<dim, Real, History>& in, const Domain<dim>& domain, Index i,
                                               Index j, const Vec<dim>& d, const Vec<dim>& n) {
    return contact_point_velocity<rotation>(n, pair_velocity_difference(in, domain, i, j, d), in.w, i, j, in.r[i], in.r[j]);
}

/// The kinematics of the pair (i, j) at separation d, distance `dist` along n, read from the
/// stored arrays (for the passes outside the pair loop).
template <bool rotation, int dim, class Real, class History>
MICROMACRO_INLINE ContactKinematics<dim> pair_kinematics(const ContactLoopInput<dim, Real, History>& in, const Domain<dim>& domain,
                                                         Index i, Index j, const Vec<dim>& d, const Vec<dim>& n, double dist,
                                                         double dt) {
    const Vec<dim> dv = pair_velocity_difference(in, domain, i, j, d);
    const Vec<dim> vr = contact_point_velocity<rotation>(n, dv, in.w, i, j, in.r[i], in.r[j]);
    return {{n, double(in.r[i]) + double(in.r[j]) - dist, n.dot(dv), vr}, in.r[i], in.r[j], in.inverse_mass[i], in.inverse_mass[j], dt};
}

/// What the law adds at the evaluation that finds a pair open whose history says it touched at
/// the last one (ContactLawIn::opening_force; for the built-in spring, the rest of its last
/// impulse), added to both particles like a contact's force. Out of the pair loop's way: one pair
/// in thousands per step comes here.
template <bool periodic, bool rotation, int dim, class Real, class Law, class History>
MICROMACRO_COLD void opened_pair(const ContactLoopInput<dim, Real, History>& in, const Domain<dim>& domain, const Law& law, double dt,
                                 IndexPair p, const History& h, Vec<dim>* f, Angular<dim>* torque, Index owned_end,
                                 std::vector<Spill<dim, rotation>>& spill) {
    using V = Vec<dim>;
    const auto [i, j] = p;
    const V d = domain.template separation_for<periodic>(convert<double>(in.x[i]), convert<double>(in.x[j]));
    const double dist = d.norm();
    if (!(dist > 0.0)) return;
    const V n = d / dist;
    const V force = law.opening_force(pair_kinematics<rotation>(in, domain, i, j, d, n, dist, dt), h);
    Angular<dim> arm{};
    if constexpr (rotation) arm = DimTraits<dim>::cross(n, force);
    add_pair_force<dim, rotation>(i, j, force, arm, double(in.r[i]), double(in.r[j]), f, torque, owned_end,
                                        spill);
}

/// The scalar pair loop (pair_loop below calls it, and then completes the opened contacts): one
/// contact at a time, with the arguments of pair_loop. With `weighed`, a pair with a particle
/// at or past in.first_ghost (a ghost: another process computes the pair too) counts half in the
/// books (a loop of its own: the weight costs up to 7% where no pair needs it). Local copies of
/// the law, the box and the energy account: through references the compiler would reload them
/// after every store to the forces. (Keeping i's values in registers over its run of partners was
/// tried: more instructions and no faster, the loop runs out of registers.) A coincident pair cannot be
/// thrown from a thread; it is recorded in `coincident` and reported after. `periodic`: whether
/// the box has a periodic axis (else separations are plain differences).
template <bool track, bool periodic, bool rotation, bool weighed, int dim, class Real, class Law, class History>
void scalar_pair_loop(const ContactLoopInput<dim, Real, History>& in, const Domain<dim>& box, const Law& contact_law, double dt,
                      std::size_t begin, std::size_t end, Vec<dim>* f, [[maybe_unused]] Angular<dim>* torque,
                      EnergyBooks& books, IndexPair& coincident, Index owned_end, std::vector<Spill<dim, rotation>>& spill,
                      std::vector<std::size_t>& opened_contacts) {
    using V = Vec<dim>;
    using SV = Vec<dim, Real>;
    constexpr bool has_history = Law::has_history;
    const SV* x = in.x;
    const SV* v = in.v;
    const Real* r = in.r;
    const Real* inverse_mass = in.inverse_mass;
    [[maybe_unused]] const Angular<dim, Real>* w = in.w;
    const IndexPair* pair = in.pair;
    [[maybe_unused]] History* history = in.history;
    // The copies must not escape (opened_pair gets the originals): a store to the forces could
    // then write into them as far as the compiler knows, and it would reload them after each.
    const Domain<dim> domain = box;
    const Law law = contact_law;
    EnergyBooks account = books;
    // Three passes per block of candidates: find the touching pairs (branch-free, the 20-30%
    // of candidates that do not touch would otherwise be a badly predicted jump), take their
    // square roots and reciprocals together (core/roots.hpp), then compute their forces. The
    // square root and division of each contact sat in one chain with its force and stalled the
    // single loop; as packets they pipeline two to eight at a time. The arithmetic and the
    // order of the sums are unchanged.
    constexpr std::size_t block = 128;
    std::array<std::uint32_t, block> touching;
    [[maybe_unused]] std::array<std::uint32_t, block> opened;
    std::array<V, block> separation;
    // Aligned to cache lines, so that roots_and_reciprocals reads and writes whole lines; the
    // squares initialised, for the lanes it computes past a block's last contact.
    alignas(64) std::array<double, block> separation_sq{};
    alignas(64) std::array<double, block> distance, inverse_distance;
    for (std::size_t b0 = begin; b0 < end; b0 += block) {
        const std::size_t b1 = std::min(end, b0 + block);
        std::size_t count = 0, open = 0;
        for (std::size_t c = b0; c < b1; ++c) {
            const auto [i, j] = pair[c];
            const V d = domain.template separation_for<periodic>(convert<double>(x[i]), convert<double>(x[j]));
            const double dist_sq = d.squaredNorm(), reach = double(r[i]) + double(r[j]);
            const bool touches = dist_sq < reach * reach;
            // The history record the force pass below reads and writes (24 bytes in 2D, 56 in 3D for the
            // built-in spring), asked for now: docs/performance.md measures 1.03-1.05x out of cache.
            if constexpr (has_history) __builtin_prefetch(&history[c], 1);
            touching[count] = static_cast<std::uint32_t>(c - b0);
            if constexpr (has_history) opened[open] = static_cast<std::uint32_t>(c - b0);
            separation[count] = d;
            separation_sq[count] = dist_sq;
            count += touches;
            open += !touches;
        }
        if constexpr (has_history)
            for (std::size_t k = 0; k < open; ++k) {  // the contact opened, if it was one
                History& h = history[b0 + opened[k]];
                if (law.touched(h)) [[unlikely]]
                    opened_contacts.push_back(b0 + opened[k]);
                else
                    h = History{};
            }
        roots_and_reciprocals(separation_sq, distance, inverse_distance, count);
        for (std::size_t k = 0; k < count; ++k) {
            const std::size_t c = b0 + touching[k];
            const auto [i, j] = pair[c];
            if (separation_sq[k] == 0.0) [[unlikely]] {
                coincident = pair[c];
                continue;
            }
            const double ri = r[i], rj = r[j], reach = ri + rj;
            // The law's view of the contact, its vectors computed in place (copies of them made
            // the compiler keep them in memory).
            ContactKinematics<dim> kinematics;
            const V& n = kinematics.normal;
            kinematics.normal = separation[k] * inverse_distance[k];
            V dv = convert<double>(v[i]) - convert<double>(v[j]);
            [[maybe_unused]] V image_velocity = V::Zero();
            if constexpr (periodic)
                if (domain.moving()) [[unlikely]] {  // j's image moves with the cell
                    image_velocity = pair_image_velocity(in, domain, i, j, separation[k]);
                    dv -= image_velocity;
                }
            kinematics.relative_velocity = contact_point_velocity<rotation>(n, dv, w, i, j, ri, rj);
            kinematics.overlap = reach - distance[k];
            kinematics.normal_velocity = n.dot(dv);
            kinematics.radius_i = ri;
            kinematics.radius_j = rj;
            kinematics.inverse_mass_i = inverse_mass[i];
            kinematics.inverse_mass_j = inverse_mass[j];
            kinematics.dt = dt;
            [[maybe_unused]] NoHistory none;
            History& h = [&]() -> History& {
                if constexpr (has_history) return history[c];
                else return none;
            }();
            const double weight = weighed && std::max(i, j) >= in.first_ghost ? 0.5 : 1.0;
            const ContactResponse<dim> resp = respond<track>(law, kinematics, h, account, false, weight);
            // The cell's power through a contact across its boundary: i feels the force, j's image
            // moves at image_velocity (zero for every other contact).
            if constexpr (track && periodic)
                if (domain.moving()) [[unlikely]] account.work_by_cell += weight * resp.force.dot(image_velocity) * dt;
            Angular<dim> arm{};
            if constexpr (rotation) arm = DimTraits<dim>::cross(n, resp.tangential);
            add_pair_force<dim, rotation>(i, j, resp.force, arm, ri, rj, f, torque, owned_end, spill);
        }
    }
    books = account;
}

/// The pair loop over candidates [begin, end), adding into the force and torque arrays f and
/// torque; a partner at or past owned_end goes to `spill`; `opened_contacts` (empty on entry)
/// holds the contacts found open, whose impulses are completed after the loop (a vector of the
/// caller's: one of the loop's own ran the 2D loop at 0.92x). FrictionalLinear (with rotation)
/// runs on packets of eight where the compiler targets AVX-512 (engine/packet_pair_loop.hpp),
/// every other law through scalar_pair_loop above.
template <bool track, bool periodic, bool rotation, bool weighed, int dim, class Real, class Law, class History>
void pair_loop(const ContactLoopInput<dim, Real, History>& in, const Domain<dim>& box, const Law& contact_law, double dt,
               std::size_t begin, std::size_t end, Vec<dim>* f, [[maybe_unused]] Angular<dim>* torque,
               EnergyBooks& books, IndexPair& coincident, Index owned_end, std::vector<Spill<dim, rotation>>& spill,
               std::vector<std::size_t>& opened_contacts) {
#ifdef MICROMACRO_PACKETS
    if constexpr (packet_pair_loop_applies<dim, rotation, Law>)
        packet_pair_loop<track, periodic, weighed>(in, box, contact_law, dt, begin, end, f, torque, books, coincident, owned_end,
                                                   spill, opened_contacts);
    else
#endif
        scalar_pair_loop<track, periodic, rotation, weighed>(in, box, contact_law, dt, begin, end, f, torque, books, coincident,
                                                             owned_end, spill, opened_contacts);
    // The rest of the impulses of contacts that opened, after every contact's force: so each
    // particle's sum runs through its contacts in the list's order and then through its opened
    // contacts in the list's order, whatever blocks the list falls into (a distributed run's
    // lists hold other pairs between a particle's, and must sum as the serial run does).
    if constexpr (Law::has_history)
        for (const std::size_t c : opened_contacts) {
            History& h = in.history[c];
            opened_pair<periodic, rotation>(in, box, contact_law, dt, in.pair[c], h, f, torque, owned_end, spill);
            h = History{};
        }
}

}  // namespace micromacro::detail
