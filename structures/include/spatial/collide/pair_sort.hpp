#pragma once
// spatial::collide::sort_unique_pairs — a pair set in its canonical form: sorted
// lexicographically, each pair once. Pair queries that stream their answer (collision_grid
// reports pairs in grid order) and every step of a moving scene (pair_changes.hpp) need it,
// so it is on the path of every simulation step.
//
// Unsigned ids below 2^32 (object indices, slots): each pair becomes one 64-bit key
// (first << b | second, b = the bits of the largest id) sorted by least-significant-digit
// radix sort (core/radix_sort.hpp; Knuth, TAOCP vol. 3, §5.2.5): stable counting passes over
// digits of at most 12 bits, so the counts (16 KB) stay in the L1 cache. O(p ceil(2b / 12))
// time and O(p) scratch for p pairs. Counting passes with the ids themselves as digits (two
// passes, counts the size of the id range) were slower at 1e6 pairs, where the counts left
// the caches (docs/experiments/collisions.md). Other ids (signed, wider, or fewer than 4096
// pairs): std::sort, O(p log p).

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>
#include <vector>

#include "spatial/core/radix_sort.hpp"

namespace spatial::collide {

// Scratch space of sort_unique_pairs, kept by a caller that sorts every step (pair_changes.hpp)
// so that the buffers are not allocated again each time.
struct pair_sort_buffers {
    std::vector<std::uint64_t> keys, scratch;
};

template <class Id>
void sort_unique_pairs(std::vector<std::pair<Id, Id>>& pairs, pair_sort_buffers& buffers) {
    // Already in order (a query answered from collision_grid's candidate list, a tracker fed
    // a sorted set): one O(p) look instead of the sort's passes.
    if (std::is_sorted(pairs.begin(), pairs.end())) {
        pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
        return;
    }
    bool sorted = false;
    if constexpr (std::is_unsigned_v<Id>) {
        Id top = 0;
        for (const auto& [a, b] : pairs) top = std::max({top, a, b});
        if (pairs.size() >= 4096 && static_cast<std::uint64_t>(top) <= 0xffffffffu) {
            const unsigned bits = spatial::detail::bits_below(static_cast<std::uint64_t>(top) + 1);
            std::vector<std::uint64_t>& keys = buffers.keys;
            keys.clear();
            keys.reserve(pairs.size());
            for (const auto& [a, b] : pairs) keys.push_back(static_cast<std::uint64_t>(a) << bits | static_cast<std::uint64_t>(b));
            spatial::detail::radix_sort_by(keys, buffers.scratch, 2 * bits, [](std::uint64_t k) { return k; }, 12);
            const std::uint64_t low = (std::uint64_t(1) << bits) - 1;
            for (std::size_t i = 0; i < keys.size(); ++i)
                pairs[i] = {static_cast<Id>(keys[i] >> bits), static_cast<Id>(keys[i] & low)};
            sorted = true;
        }
    }
    if (!sorted) std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
}

template <class Id>
void sort_unique_pairs(std::vector<std::pair<Id, Id>>& pairs) {
    pair_sort_buffers buffers;
    sort_unique_pairs(pairs, buffers);
}

}  // namespace spatial::collide
