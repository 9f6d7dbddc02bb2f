#pragma once
// spatial::collide::sort_unique_pairs — a pair set in its canonical form: sorted
// lexicographically, each pair once. Pair queries that stream their answer (collision_grid
// reports pairs in grid order) and every step of a moving scene (pair_changes.hpp) need it,
// so it is on the path of every simulation step.
//
// For unsigned ids that are small relative to the pair count (object indices: ids below
// m <= 4 p + 65536 for p pairs) a least-significant-digit radix sort with the ids as digits:
// two stable counting passes, by the second id and then by the first (Knuth, TAOCP vol. 3,
// §5.2.5), O(p + m) time and O(p + m) scratch. Otherwise std::sort, O(p log p).

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>
#include <vector>

namespace spatial::collide {

template <class Id>
void sort_unique_pairs(std::vector<std::pair<Id, Id>>& pairs) {
    using pair_type = std::pair<Id, Id>;
    bool radix = false;
    std::size_t m = 0;
    if constexpr (std::is_unsigned_v<Id>) {
        Id top = 0;
        for (const auto& [a, b] : pairs) top = std::max({top, a, b});
        const std::size_t limit = 4 * pairs.size() + 65536;
        radix = pairs.size() >= 4096 && static_cast<std::uint64_t>(top) < limit;
        m = radix ? static_cast<std::size_t>(top) + 1 : 0;
    }
    if (!radix) {
        std::sort(pairs.begin(), pairs.end());
    } else {
        std::vector<pair_type> scratch(pairs.size());
        std::vector<std::size_t> start(m + 1);
        auto pass = [&](const std::vector<pair_type>& from, std::vector<pair_type>& to, auto key) {
            std::fill(start.begin(), start.end(), 0);
            for (const auto& p : from) ++start[static_cast<std::size_t>(key(p)) + 1];
            for (std::size_t k = 0; k < m; ++k) start[k + 1] += start[k];
            for (const auto& p : from) to[start[static_cast<std::size_t>(key(p))]++] = p;
        };
        pass(pairs, scratch, [](const pair_type& p) { return p.second; });
        pass(scratch, pairs, [](const pair_type& p) { return p.first; });
    }
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
}

}  // namespace spatial::collide
