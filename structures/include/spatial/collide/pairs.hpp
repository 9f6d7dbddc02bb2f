#pragma once
// Collision pairs: the result type of every structure's pair queries, and the generic
// bipartite query that works between ANY two containers.
//
//   c.self_pairs(filter)          pairs of distinct stored objects of c that intersect
//   c.pairs_with(other, filter)   pairs (object of c, object of other) that intersect
// filter = pair_filter::candidates: the broad phase only — every pair whose bounding volumes
// the structure could not separate (a superset of the intersecting pairs; how large depends
// on the structure and its bounding volumes: that is what the collide benchmark measures);
// pair_filter::exact: the narrow phase as well (collide/narrow_phase.hpp), so every structure
// reports the SAME set, equal to brute force's.
// Each pair is reported once; self pairs as (lower slot, higher slot). Results are sorted by
// the iterators' slots (the containers' stable handles): a deterministic order, and the
// stable comparison that makes pair sets of different runs and structures comparable.

#include <algorithm>
#include <utility>
#include <vector>

#include "spatial/collide/narrow_phase.hpp"
#include "spatial/core/object_geometry.hpp"

namespace spatial {

enum class pair_filter { candidates, exact };

template <class ItA, class ItB>
void sort_pairs(std::vector<std::pair<ItA, ItB>>& pairs) {
    std::sort(pairs.begin(), pairs.end(), [](const auto& x, const auto& y) {
        return x.first.slot() != y.first.slot() ? x.first.slot() < y.first.slot() : x.second.slot() < y.second.slot();
    });
}

namespace detail {
// f(it, hit) for every object `it` of b and every iterator `hit` of a that a's box query over
// it's bounding box reports (find_in_box: the object overlaps the box).
template <class A, class B, class F>
void for_each_box_query_hit(const A& a, const B& b, F&& f) {
    using PA = typename A::point_type;
    for (auto it = b.begin(); it != b.end(); ++it) {
        PA lo, hi;
        for (std::size_t i = 0; i < A::dimension; ++i) lo[i] = object_lower(*it, i), hi[i] = object_upper(*it, i);
        for (const auto& hit : a.find_in_box(lo, hi)) f(it, hit);
    }
}
}  // namespace detail

// Bipartite pairs between any two containers: for each object of b, the objects of a whose
// intersection with its bounding box a's own box query reports (find_in_box: the object
// overlaps the box), then the narrow phase when asked. O(|b| * (box query of a)).
// Candidates here are the pairs whose object overlaps the other's bounding box.
template <class A, class B>
std::vector<std::pair<typename A::iterator, typename B::iterator>> pairs_between(const A& a, const B& b,
                                                                                 pair_filter filter) {
    std::vector<std::pair<typename A::iterator, typename B::iterator>> out;
    detail::for_each_box_query_hit(a, b, [&](const auto& it, const auto& ia) {
        if (filter == pair_filter::candidates || collide::narrow_phase(*ia, *it)) out.emplace_back(ia, it);
    });
    sort_pairs(out);
    return out;
}

// Self pairs of any container through its own box queries: for each object a, the objects
// its box query reports (they overlap a's bounding box) with a higher slot, then the narrow
// phase when asked. Complete for the exact pairs: an object that meets a meets a's box.
// Candidates here: pairs (a, b), slot(a) < slot(b), where b overlaps a's box. O(n box queries).
template <class C>
std::vector<std::pair<typename C::iterator, typename C::iterator>> self_pairs_by_queries(const C& c,
                                                                                         pair_filter filter) {
    std::vector<std::pair<typename C::iterator, typename C::iterator>> out;
    detail::for_each_box_query_hit(c, c, [&](const auto& it, const auto& other) {
        if (other.slot() > it.slot() && (filter == pair_filter::candidates || collide::narrow_phase(*it, *other)))
            out.emplace_back(it, other);
    });
    sort_pairs(out);
    return out;
}

}  // namespace spatial
