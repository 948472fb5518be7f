#pragma once
// How the pair loop is shared among threads. The candidates are sorted by their first particle
// i; each thread takes a nearly equal contiguous share, cut where i changes, and so owns the
// particles from its first i to the next share's first i: it writes their forces directly. Only
// a partner j past its own particles (j > i, so it belongs to a later thread) goes into the
// thread's spill list, which the owner adds after the loop, threads in order. With particles in
// spatial order the spill lists stay short. Bitwise the same for a fixed thread count.
#include <algorithm>
#include <cstddef>
#include <type_traits>
#include <vector>

#include "micromacro/core/domain.hpp"
#include "micromacro/core/energy.hpp"
#include "micromacro/core/error.hpp"

#include "micromacro/core/index.hpp"
#include "micromacro/core/parallel.hpp"
#include "micromacro/engine/pair_loop.hpp"

namespace micromacro::detail {

/// start[t] is where share t of `shares` begins among `count` candidates sorted by i;
/// start[shares] = count. A particle's run of pairs is never split.
inline void split_shares(const IndexPair* pair, std::size_t count, int shares, std::vector<std::size_t>& start) {
    start.assign(shares + 1, count);
    start[0] = 0;
    for (int t = 1; t < shares; ++t) {
        std::size_t c = std::max(start[t - 1], share_begin(count, t, shares));
        while (c > 0 && c < count && pair[c].i == pair[c - 1].i) ++c;  // do not split a particle's run
        start[t] = c;
    }
}

/// Adds to the particles [owned_begin, owned_end) what the shares before `share` spilled on
/// them, share by share in order.
template <int dim, bool rotation>
void add_spills(const std::vector<std::vector<Spill<dim, rotation>>>& spills, int share, Index owned_begin, Index owned_end,
                Vec<dim>* f, [[maybe_unused]] Angular<dim>* torque) {
    for (int u = 0; u < share; ++u)
        for (const auto& s : spills[u]) {
            if (s.particle < owned_begin || s.particle >= owned_end) continue;
            f[s.particle] -= s.force;
            if constexpr (rotation) torque[s.particle] -= s.torque;
        }
}

/// All pair forces of a contact list on `shares` threads (one runs serially): the shares, the
/// pair loop on each, the spills added by their owners after a barrier, the energy books summed
/// in thread order. Keeps the per-thread scratch from one evaluation to the next.
template <int dim, class Real, bool rotation>
class ThreadedPairLoop {
public:
    /// Adds the forces and torques of the candidates in `in` (`count` of them, on `particles`
    /// particles, ghosts from in.first_ghost on) into f and torque, and what they dissipate into
    /// `books` (half of a pair with a ghost).
    template <bool track, class Law, class History>
    void run(const ContactLoopInput<dim, Real, History>& in, std::size_t count, Index particles, int shares,
             const Domain<dim>& domain, const Law& law, double dt, Vec<dim>* f, Angular<dim>* torque,
             EnergyBooks& books) {
        const Index n = particles;
        thread_books_.assign(shares, EnergyBooks{});
        coincident_.assign(shares, IndexPair{0, 0});
        spills_.resize(shares);
        for (auto& list : spills_) list.clear();
        opened_.resize(shares);
        for (auto& list : opened_) list.clear();
        // Share t: candidates [begin, end), particles below owned_end its own. Without periodic
        // axes the separations need no minimum-image test; without ghosts (or books) no pair is
        // weighed for the books.
        const bool periodic = domain.any_periodic(), ghosts = track && in.first_ghost < particles;
        auto share = [&](std::size_t begin, std::size_t end, int t, Index owned_end) {
            auto loop = [&](auto periodic_box, auto weighed) {
                pair_loop<track, decltype(periodic_box)::value, rotation, decltype(weighed)::value>(
                    in, domain, law, dt, begin, end, f, torque, thread_books_[t], coincident_[t], owned_end, spills_[t], opened_[t]);
            };
            using Weighed = std::bool_constant<track>;  // false instantiates nothing new
            if (periodic) ghosts ? loop(std::true_type{}, Weighed{}) : loop(std::true_type{}, std::false_type{});
            else ghosts ? loop(std::false_type{}, Weighed{}) : loop(std::false_type{}, std::false_type{});
        };
        if (shares == 1) {
            share(0, count, 0, n);
        } else {
            const IndexPair* pair = in.pair;
            split_shares(pair, count, shares, share_start_);
            auto first_particle = [&](int t) { return share_start_[t] < count ? pair[share_start_[t]].i : n; };
            MICROMACRO_OMP(omp parallel num_threads(shares)) {
                const int t = thread_number();
                const Index owned_begin = t == 0 ? 0 : first_particle(t), owned_end = t + 1 == shares ? n : first_particle(t + 1);
                share(share_start_[t], share_start_[t + 1], t, owned_end);
                MICROMACRO_OMP(omp barrier)
                add_spills(spills_, t, owned_begin, owned_end, f, torque);
            }
        }
        for (const IndexPair& c : coincident_)
            if (c.i != c.j)
                throw_input_error("particles ", c.i, " and ", c.j, " have coincident centres (at distance 0), so their "
                                  "contact normal is undefined; move one of them");
        if constexpr (track)
            for (const EnergyBooks& b : thread_books_) books.add(b);  // in thread order
    }

    /// Bytes of the spill and opened-contact lists, capacities counted.
    std::size_t bytes() const {
        std::size_t b = 0;
        for (const auto& list : spills_) b += list.capacity() * sizeof(Spill<dim, rotation>);
        for (const auto& list : opened_) b += list.capacity() * sizeof(std::size_t);
        return b;
    }

private:
    std::vector<std::size_t> share_start_;
    std::vector<std::vector<Spill<dim, rotation>>> spills_;
    std::vector<std::vector<std::size_t>> opened_;  // each share's contacts found open (pair_loop)
    std::vector<EnergyBooks> thread_books_;
    std::vector<IndexPair> coincident_;
};

}  // namespace micromacro::detail
