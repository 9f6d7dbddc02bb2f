#pragma once
// spatial::collide::pair_set_tracker<Id> — the pair set of a moving scene kept from step to
// step, with the pairs that appeared and disappeared this step (what a simulation reacts
// to: contact begin / contact end).
//
// The tracker stores the current set sorted; each step's new set (from any structure's
// self_pairs / pairs_with, mapped to ids the caller keeps stable for an object's life) is
// sorted and merged against it: added = new \ old, removed = old \ new, O(p log p + p_old)
// for p pairs; O(p + p_old) for small unsigned ids such as object indices (radix sort,
// pair_sort.hpp). Ids must not be reused while a pair holding them is in the set: a
// structure's slot index is NOT such an id once objects are erased and inserted (a new
// object may take an erased object's slot), so the scene runner uses its own object ids.

#include <cstdint>
#include <type_traits>
#include <utility>
#include <vector>

#include "spatial/collide/pair_sort.hpp"

namespace spatial::collide {

template <class Id>
class pair_set_tracker {
public:
    using pair_type = std::pair<Id, Id>;

    // Replaces the current set by `pairs` (any order; (a, b) and (b, a) are the same pair
    // for self pairs only if the caller normalises them — self_pairs() already reports
    // (lower, higher)). Returns the number of pairs that changed (added + removed).
    // The step's set is copied into a buffer kept from step to step (as are the sort's and
    // the differences'), so a simulation loop allocates nothing once the sets stop growing:
    // taking the set by value had cost a fresh allocation, and its first-touch page faults,
    // every step.
    std::size_t step(const std::vector<pair_type>& pairs) {
        // A set given in canonical form (strictly increasing: what collision_grid's candidate
        // list reports) is merged where it is and copied once, after: the copy, the sort's
        // look and the duplicates' pass of the general path were three more passes over it.
        if (strictly_increasing(pairs)) {
            merge(pairs);
            current_.assign(pairs.begin(), pairs.end());
        } else {
            next_.assign(pairs.begin(), pairs.end());
            sort_unique_pairs(next_, buffers_);
            merge(next_);
            current_.swap(next_);
        }
        return added_.size() + removed_.size();
    }
    void clear() {
        current_.clear();
        added_.clear();
        removed_.clear();
    }
    // The current set, sorted.
    const std::vector<pair_type>& pairs() const { return current_; }
    // Pairs in the current set that were not in the previous one, and the reverse; sorted.
    const std::vector<pair_type>& added() const { return added_; }
    const std::vector<pair_type>& removed() const { return removed_; }

private:
    static bool strictly_increasing(const std::vector<pair_type>& pairs) {
        bool increasing = true;  // one pass without an early exit: the common answer is yes
        for (std::size_t i = 1; i < pairs.size(); ++i) increasing &= key(pairs[i - 1]) < key(pairs[i]);
        return increasing;
    }
    // added_ = next \ current_, removed_ = current_ \ next, for a strictly increasing next.
    // Both differences in one merge of the two sorted sets (two std::set_difference calls
    // made the comparisons twice). Most pairs persist from step to step, so the equal case is
    // the predictable branch.
    void merge(const std::vector<pair_type>& next) {
        added_.clear();
        removed_.clear();
        auto n = next.cbegin(), c = current_.cbegin();
        const auto n_end = next.cend(), c_end = current_.cend();
        while (n != n_end && c != c_end) {
            const auto x = key(*n), y = key(*c);
            if (x < y) {
                added_.push_back(*n++);
            } else if (y < x) {
                removed_.push_back(*c++);
            } else {
                ++n;
                ++c;
            }
        }
        added_.insert(added_.end(), n, n_end);
        removed_.insert(removed_.end(), c, c_end);
    }
    // The lexicographic order of pairs as one comparison: 32-bit unsigned ids packed into a
    // 64-bit word, other ids as the pair itself.
    static auto key(const pair_type& p) {
        if constexpr (std::is_unsigned_v<Id> && sizeof(Id) <= 4)
            return static_cast<std::uint64_t>(p.first) << 32 | static_cast<std::uint64_t>(p.second);
        else
            return p;
    }

    std::vector<pair_type> current_, next_, added_, removed_;
    pair_sort_buffers buffers_;  // the sort's scratch, reused step after step
};

}  // namespace spatial::collide
