#pragma once
// Candidate contacts (pairs within reach after the last neighbour search) with their typed
// per-contact history. Pairs are kept sorted by (i, j) so a rebuild can carry each surviving
// pair's history over by one merge pass; a pair that leaves the list loses its history. "Sorted"
// is by an order of the particles, the index order unless the engine gives another
// (PairOrder): each pair's i comes before its j, and the pairs go by i, then by j.
#include <algorithm>
#include <cstdint>
#include <functional>
#include <utility>
#include <type_traits>
#include <vector>

#include "micromacro/contact/tangential.hpp"
#include "micromacro/core/index.hpp"

namespace micromacro {

/// An order of the particles for the pairs of a ContactList: by index (`key` empty) or by a
/// key per particle (distinct keys). `before(a, b)`: whether particle a comes before b; `less`:
/// the pairs' order, by i and then by j.
struct PairOrder {
    const std::vector<std::uint64_t>* key = nullptr;

    bool before(Index a, Index b) const { return key ? (*key)[a] < (*key)[b] : a < b; }
    bool less(const IndexPair& p, const IndexPair& q) const {
        return p.i != q.i ? before(p.i, q.i) : before(p.j, q.j);
    }
    /// The pair turned so that its i comes first.
    IndexPair oriented(IndexPair p) const { return before(p.j, p.i) ? IndexPair{p.j, p.i} : p; }
};

template <class History>
class ContactList {
public:
    static constexpr bool has_history = !std::is_same_v<History, NoHistory>;

    std::size_t size() const { return pairs_.size(); }
    /// Whether there is one history per pair (after restoring a file).
    bool consistent() const {
        if constexpr (has_history) return history_.size() == pairs_.size();
        else return true;
    }
    const std::vector<IndexPair>& pairs() const { return pairs_; }
    std::vector<IndexPair>& scratch() { return next_; }

    History& history(std::size_t c) requires has_history { return history_[c]; }
    const History& history(std::size_t c) const requires has_history { return history_[c]; }
    History* history_data() requires has_history { return history_.data(); }
    /// Calls f(i, j, history) for every pair.
    template <class F>
    void visit(F& f) requires has_history {
        for (std::size_t c = 0; c < pairs_.size(); ++c) f(pairs_[c].i, pairs_[c].j, history_[c]);
    }
    template <class F>
    void visit(F& f) const requires has_history {
        for (std::size_t c = 0; c < pairs_.size(); ++c) f(pairs_[c].i, pairs_[c].j, history_[c]);
    }

    /// Replaces the pairs by the list in scratch(), sorted in `order` as the present list is,
    /// keeping the history of every pair present in both lists.
    void commit_scratch(PairOrder order = {}) {
        if constexpr (has_history) {
            if (order.key) carry_histories([&](const IndexPair& p, const IndexPair& q) { return order.less(p, q); });
            else carry_histories(std::less<IndexPair>{});  // the index order, without the test per comparison
        }
        pairs_.swap(next_);
        next_.clear();
    }

    /// Renumbers the particles: particle i becomes new_index[i], in the partner too when the
    /// partners are particles. A pair whose order flips is turned round (i before j again, in
    /// `order` of the new numbers) with its history seen from the other partner; the list is
    /// sorted again.
    void renumber(const std::vector<Index>& new_index, bool partners_are_particles, PairOrder order = {}) {
        std::vector<std::pair<IndexPair, std::size_t>> moved(pairs_.size());  // new pair, old slot
        std::vector<bool> turned(pairs_.size(), false);
        for (std::size_t c = 0; c < pairs_.size(); ++c) {
            IndexPair p{new_index[pairs_[c].i], partners_are_particles ? new_index[pairs_[c].j] : pairs_[c].j};
            if (partners_are_particles && order.before(p.j, p.i)) {
                std::swap(p.i, p.j);
                turned[c] = true;
            }
            moved[c] = {p, c};
        }
        if (partners_are_particles)
            std::sort(moved.begin(), moved.end(), [&](const auto& a, const auto& b) { return order.less(a.first, b.first); });
        else  // (particle, wall): by index
            std::sort(moved.begin(), moved.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        if constexpr (has_history) {
            std::vector<History> history(pairs_.size());
            for (std::size_t c = 0; c < moved.size(); ++c) {
                const std::size_t old = moved[c].second;
                history[c] = turned[old] ? seen_from_partner(history_[old]) : history_[old];
            }
            history_.swap(history);
        }
        for (std::size_t c = 0; c < moved.size(); ++c) pairs_[c] = moved[c].first;
    }

    template <class Archive>
    void serialize(Archive& ar) {
        ar.array(pairs_);
        if constexpr (has_history) ar.array(history_);
    }

    std::size_t bytes() const {
        std::size_t b = pairs_.capacity() * sizeof(IndexPair) + next_.capacity() * sizeof(IndexPair);
        if constexpr (has_history) b += history_.capacity() * sizeof(History);
        return b;
    }

private:
    // The history of every pair of next_ that the present list holds, both sorted by `less`.
    template <class Less>
    void carry_histories(Less less) {
        std::vector<History> carried(next_.size());
        std::size_t old = 0;
        for (std::size_t c = 0; c < next_.size(); ++c) {
            while (old < pairs_.size() && less(pairs_[old], next_[c])) ++old;
            if (old < pairs_.size() && pairs_[old] == next_[c]) carried[c] = history_[old];
        }
        history_.swap(carried);
    }

    std::vector<IndexPair> pairs_, next_;
    [[no_unique_address]] std::conditional_t<has_history, std::vector<History>, NoHistory> history_;
};

}  // namespace micromacro
