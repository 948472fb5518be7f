#pragma once
// Candidate contacts (pairs within reach after the last neighbour search) with their typed
// per-contact history. Pairs are kept sorted by (i, j) so a rebuild can carry each surviving
// pair's history over by one merge pass; a pair that leaves the list loses its history.
#include <cstdint>
#include <type_traits>
#include <vector>

#include "micromacro/contact/tangential.hpp"

namespace micromacro {

using Index = std::uint32_t;

struct IndexPair {
    Index i, j;  ///< particle i and partner j (a particle with j > i, or a wall number)
    friend bool operator<(const IndexPair& a, const IndexPair& b) { return a.i != b.i ? a.i < b.i : a.j < b.j; }
    friend bool operator==(const IndexPair&, const IndexPair&) = default;
};

template <class History>
class ContactList {
public:
    static constexpr bool has_history = !std::is_same_v<History, NoHistory>;

    std::size_t size() const { return pairs_.size(); }
    const std::vector<IndexPair>& pairs() const { return pairs_; }
    std::vector<IndexPair>& scratch() { return next_; }

    History& history(std::size_t c) requires has_history { return history_[c]; }
    const History& history(std::size_t c) const requires has_history { return history_[c]; }
    History* history_data() requires has_history { return history_.data(); }

    /// Replaces the pairs by the sorted list in scratch(), keeping the history of every pair
    /// present in both lists.
    void commit_scratch() {
        if constexpr (has_history) {
            std::vector<History> carried(next_.size());
            std::size_t old = 0;
            for (std::size_t c = 0; c < next_.size(); ++c) {
                while (old < pairs_.size() && pairs_[old] < next_[c]) ++old;
                if (old < pairs_.size() && pairs_[old] == next_[c]) carried[c] = history_[old];
            }
            history_.swap(carried);
        }
        pairs_.swap(next_);
        next_.clear();
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
    std::vector<IndexPair> pairs_, next_;
    [[no_unique_address]] std::conditional_t<has_history, std::vector<History>, NoHistory> history_;
};

}  // namespace micromacro
