#pragma once
// spatial::bvh — the queries other than rays (those are in bvh_rays.hpp) and the traversal
// skeleton they share. Iterative traversal with a small-buffer stack that spills to the heap
// (bvh/traversal_stack.hpp) — never a fixed-size stack.
//  * visit(keep, leaf_fn): depth-first, left child first, into every node keep() accepts;
//    equality lookup (find, count, erase(x)), ball and box queries run on it. Ball:
//    distance_lower_bound; box: node AABBs.
//  * kNN: best-first over a binary heap keyed by the volumes' distance_lower_bound, with
//    (1+eps) pruning (Arya et al. 1998); its order is the heap's, so it keeps its own loop.
// Every node test is conservative: the volume is grown by the ray thickness plus a rounding
// slack of 16 eps (|query|_inf + |scene|_inf) (see node_volume.hpp), distance lower bounds are
// reduced by that slack, so an object the exact test reports is never pruned. Statistics of
// the last query: last_query_stats() (not thread-safe: concurrent const queries race on these
// counters only).

#include "spatial/bvh/bvh.hpp"
#include "spatial/core/distance.hpp"
#include "spatial/core/knn_result_set.hpp"

namespace spatial {

// Depth-first traversal: descend into nodes for which keep(node) holds, call leaf_fn on
// every slot of a kept leaf.
template <stored_object O, class BV, class Config>
template <class Keep, class LeafFn>
inline void bvh<O, BV, Config>::visit(Keep&& keep, LeafFn&& leaf_fn) const {
    bvh_detail::traversal_stack<node_index> stack;
    if (keep(nodes_[root])) stack.push(root);
    while (!stack.empty()) {
        const node& nd = nodes_[stack.pop()];
        ++stats_.nodes_visited;
        if (nd.leaf) {
            const slot_index* b = block(nd.first);
            for (std::uint32_t i = 0; i < nd.count; ++i) {
                ++stats_.objects_tested;
                leaf_fn(b[i]);
            }
            continue;
        }
        if (keep(nodes_[nd.first + 1])) stack.push(nd.first + 1);
        if (keep(nodes_[nd.first])) stack.push(nd.first);
    }
}

template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::collect_equal(const O& x, bool first_only) const -> std::vector<slot_index> {
    std::vector<slot_index> hits;
    if (slots_.size() == 0) return hits;
    const item it = item_of(x, 0);
    visit(
        [&](const node& nd) {
            const box_type& b = box_of(nd);
            for (std::size_t i = 0; i < D; ++i)
                if (b.hi[i] < it.lo[i] || b.lo[i] > it.hi[i]) return false;
            return !(first_only && !hits.empty());
        },
        [&](slot_index s) {
            if (!(first_only && !hits.empty()) && slots_.value(s) == x) hits.push_back(s);
        });
    return hits;
}

// Rounding slack of a query at p: 16 eps (|p|_inf + |scene|_inf), plus the smallest
// normal number so that it is never 0. Rounding errors of the BV tests are a few eps
// times the magnitudes involved, which this bounds.
template <stored_object O, class BV, class Config>
template <class P>
inline auto bvh<O, BV, Config>::slack(const P& p) const -> T {
    return slack_of(to_bv(p));
}
template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::slack_of(const bv_point& p) const -> T {
    T m = 0;
    for (std::size_t i = 0; i < D; ++i) m = std::max(m, std::abs(p[i]));
    if (has_root()) {  // the queries return before this on the unallocated tree; kept safe
        const box_type& b = box_of(nodes_[root]);
        if (!b.is_empty())
            for (std::size_t i = 0; i < D; ++i) m = std::max({m, std::abs(b.lo[i]), std::abs(b.hi[i])});
    }
    return slack_for_magnitude(m);
}

// ---- lookup ----------------------------------------------------------------------
template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::find(const O& x) -> iterator {
    detail::require_finite_object(x, site("find"));
    require_fresh(site("find"));
    const auto hits = collect_equal(x, true);
    return hits.empty() ? end() : make(hits.front());
}
template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::count(const O& x) const -> size_type {
    detail::require_finite_object(x, site("count"));
    require_fresh(site("count"));
    return collect_equal(x, false).size();
}

// ---- nearest neighbours and ranges ---------------------------------------------------
template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::find_nearest(const point_type& x, size_type k, scalar_type eps_factor) const
    -> std::vector<iterator> {
    detail::require_finite(x, site("find_nearest"), "query point");
    detail::require_nonnegative(eps_factor, site("find_nearest"), "eps");
    require_fresh(site("find_nearest"));
    stats_ = {};
    std::vector<iterator> out;
    if (k == 0 || slots_.size() == 0) return out;
    knn_result_set<T> best(std::min(k, slots_.size()));
    const T f = (1 + eps_factor) * (1 + eps_factor);
    const bv_point q = to_bv(x);
    const T sl = slack(x);
    struct entry {
        T key;
        node_index n;
        bool operator<(const entry& o) const { return key > o.key; }  // min-heap
    };
    std::vector<entry> heap;
    heap.push_back({0, root});
    auto prunable = [&](T key) {
        const T w = best.worst();
        return key > 0 && w < std::numeric_limits<T>::infinity() && key * f >= w;
    };
    while (!heap.empty()) {
        std::pop_heap(heap.begin(), heap.end());
        const entry e = heap.back();
        heap.pop_back();
        if (prunable(e.key)) break;  // every remaining key is at least as large
        ++stats_.nodes_visited;
        const node& nd = nodes_[e.n];
        if (nd.leaf) {
            const slot_index* b = block(nd.first);
            for (std::uint32_t i = 0; i < nd.count; ++i) {
                ++stats_.objects_tested;
                best.add(object_squared_distance(slots_.value(b[i]), x), b[i]);
            }
            continue;
        }
        for (node_index c = nd.first; c <= nd.first + 1; ++c) {
            const T lb = std::max(T(0), static_cast<T>(nodes_[c].volume.distance_lower_bound(q)) - sl);
            const T key = lb * lb;
            if (prunable(key)) continue;
            heap.push_back({key, c});
            std::push_heap(heap.begin(), heap.end());
        }
    }
    for (const auto& c : best.finish()) out.push_back(make(c.slot));
    return out;
}
template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::find_in_ball(const point_type& center, scalar_type radius) const -> std::vector<iterator> {
    detail::require_finite(center, site("find_in_ball"), "center");
    detail::require_nonnegative(radius, site("find_in_ball"), "radius");
    require_fresh(site("find_in_ball"));
    stats_ = {};
    std::vector<iterator> out;
    if (slots_.size() == 0) return out;
    const bv_point q = to_bv(center);
    const T sl = slack(center) + radius * 16 * eps;
    const T r2 = radius * radius;
    visit([&](const node& nd) { return nd.volume.distance_lower_bound(q) - sl <= radius; },
          [&](slot_index s) {
              if (object_squared_distance(slots_.value(s), center) <= r2) out.push_back(make(s));
          });
    return out;
}
template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::find_in_box(const point_type& lo, const point_type& hi) const -> std::vector<iterator> {
    detail::require_finite(lo, site("find_in_box"), "box corner lo");
    detail::require_finite(hi, site("find_in_box"), "box corner hi");
    require_fresh(site("find_in_box"));
    stats_ = {};
    std::vector<iterator> out;
    if (slots_.size() == 0) return out;
    visit(
        [&](const node& nd) {
            const box_type& b = box_of(nd);
            for (std::size_t i = 0; i < D; ++i)
                if (b.hi[i] < lo[i] || b.lo[i] > hi[i]) return false;
            return true;
        },
        [&](slot_index s) {
            if (object_overlaps_box(slots_.value(s), lo, hi)) out.push_back(make(s));
        });
    return out;
}

}  // namespace spatial
