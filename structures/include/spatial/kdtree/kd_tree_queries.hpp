#pragma once
// spatial::kd_tree — the point and object queries other than rays: kNN with Arya & Mount's
// incremental cell distance and (1+eps) pruning, ball and box ranges, equality lookup, and,
// for objects with extent, the same queries pruned by node extents with a rounding slack.

#include "spatial/kdtree/kd_tree.hpp"

namespace spatial {

template <stored_object O, class Config>
inline void kd_tree<O, Config>::run_knn(const P& x, scalar_type eps, knn_result_set<T>& best) const {
    if constexpr (has_extent) {
        knn_object_query q{x, (1 + eps) * (1 + eps), knn_slack(x), best};
        knn_objects(root, q);
    } else {
        knn_query q{point_coords(x), (1 + eps) * (1 + eps), best};
        coords offset{};
        knn(root, T(0), offset, q);
    }
}

// Arya & Mount's cell distance: `rd` is the squared distance from x to the cell, `offset[d]`
// the per-dimension component of it; entering the far child changes one. The far child's
// distance is summed again from the offsets (far_cell_distance), not updated as
// rd - old^2 + diff^2: with coordinates near 1e30 that difference cancels, rounds above the
// distance of a point in the cell, and pruned it (a kNN missed a nearer point; soak finding).
// The squared distance from x to the far child's cell: the offsets with offset[d] = diff,
// squared and summed in the order squared_distance sums a point's coordinate differences.
// Each |offset| is at most the rounded |difference| of a point in the cell (rounding is
// monotone), so the sum is at most the point's squared distance, bit for bit: no point is pruned.
template <stored_object O, class Config>
inline auto kd_tree<O, Config>::far_cell_distance(const coords& offset, unsigned d, T diff) -> T {
    T sum = 0;
    for (unsigned i = 0; i < D; ++i) {
        const T o = i == d ? diff : offset[i];
        sum += o * o;
    }
    return sum;
}

template <stored_object O, class Config>
inline void kd_tree<O, Config>::knn(node_index n, T rd, coords& offset, knn_query& q) const {
    const node& nd = nodes_[n];
    if constexpr (Config::collect_stats) ++query_stats_.nodes_visited;
    if (nd.is_leaf) {
        const bucket& b = buckets_[nd.first];
        for (std::uint32_t i = 0; i < nd.count; ++i) {
            const slot_index s = b.items[i];
            if constexpr (Config::collect_stats) ++query_stats_.objects_tested;
            const T d2 = squared_distance(slots_.value(s), q.x);
            if (d2 < q.best.worst()) q.best.add(d2, s);
        }
        return;
    }
    const unsigned d = nd.dim;
    const T diff = q.x[d] - nd.split;
    const node_index near = diff <= 0 ? nd.first : nd.first + 1;
    knn(near, rd, offset, q);
    const T old = offset[d];
    const T far_rd = far_cell_distance(offset, d, diff);
    if (far_rd * q.eps_factor < q.best.worst()) {
        offset[d] = diff;
        knn(near == nd.first ? nd.first + 1 : nd.first, far_rd, offset, q);
        offset[d] = old;
    }
}

template <stored_object O, class Config>
inline void kd_tree<O, Config>::ball(node_index n, T rd, coords& offset, const coords& x, T r2,
                                     std::vector<iterator>& out) const {
    const node& nd = nodes_[n];
    if constexpr (Config::collect_stats) ++query_stats_.nodes_visited;
    if (nd.is_leaf) {
        const bucket& b = buckets_[nd.first];
        for (std::uint32_t i = 0; i < nd.count; ++i)
            if (squared_distance(slots_.value(b.items[i]), x) <= r2) out.push_back(make(b.items[i]));
        return;
    }
    const unsigned d = nd.dim;
    const T diff = x[d] - nd.split;
    const node_index near = diff <= 0 ? nd.first : nd.first + 1;
    ball(near, rd, offset, x, r2, out);
    const T old = offset[d];
    const T far_rd = far_cell_distance(offset, d, diff);
    if (far_rd <= r2) {
        offset[d] = diff;
        ball(near == nd.first ? nd.first + 1 : nd.first, far_rd, offset, x, r2, out);
        offset[d] = old;
    }
}

template <stored_object O, class Config>
inline void kd_tree<O, Config>::box(node_index n, const P& lo, const P& hi, std::vector<iterator>& out) const {
    const node& nd = nodes_[n];
    if constexpr (Config::collect_stats) ++query_stats_.nodes_visited;
    if (nd.is_leaf) {
        const bucket& b = buckets_[nd.first];
        for (std::uint32_t i = 0; i < nd.count; ++i)
            if (object_overlaps_box(slots_.value(b.items[i]), lo, hi)) out.push_back(make(b.items[i]));
        return;
    }
    if constexpr (has_extent) {
        // An object overlapping the box has a bounding box overlapping it (the exact test
        // of object_overlaps_box runs only after the box test), so extents prune exactly.
        for (node_index c = nd.first; c <= nd.first + 1; ++c)
            if (extent_overlaps(extents_[c], lo, hi)) box(c, lo, hi, out);
    } else {
        if (lo[nd.dim] <= nd.split) box(nd.first, lo, hi, out);
        if (hi[nd.dim] >= nd.split) box(nd.first + 1, lo, hi, out);
    }
}

// Equal objects have equal coordinates, so only cells containing x are searched; on a
// split plane both sides may hold copies.
template <stored_object O, class Config>
inline void kd_tree<O, Config>::collect_equal(node_index n, const coords& c, const O& x, std::vector<slot_index>& out,
                                              bool first_only) const {
    const node& nd = nodes_[n];
    if (nd.is_leaf) {
        const bucket& b = buckets_[nd.first];
        for (std::uint32_t i = 0; i < nd.count; ++i)
            if (slots_.value(b.items[i]) == x) {
                out.push_back(b.items[i]);
                if (first_only) return;
            }
        return;
    }
    if (c[nd.dim] <= nd.split) collect_equal(nd.first, c, x, out, first_only);
    if (first_only && !out.empty()) return;
    if (c[nd.dim] >= nd.split) collect_equal(nd.first + 1, c, x, out, first_only);
}

// ---- objects: queries pruned by node extents (skd-tree) ----
template <stored_object O, class Config>
inline bool kd_tree<O, Config>::extent_overlaps(const extent& ex, const P& lo, const P& hi) {
    for (std::size_t i = 0; i < D; ++i)
        if (ex.hi[i] < lo[i] || ex.lo[i] > hi[i]) return false;  // also false when empty
    return true;
}

// Squared distance from x to a closed box (+inf when the box is empty).
template <stored_object O, class Config>
inline auto kd_tree<O, Config>::extent_squared_distance(const extent& ex, const P& x) -> T {
    return box_squared_distance<T, D>(x, ex.lo, ex.hi);
}

// Rounding slack for distance lower bounds at query x: an object's own distance routine
// (a triangle's Voronoi-region projection, a sphere's |x - c| - r) may round below the
// distance to its bounding box. Its error is a few eps times the magnitudes involved, so
// 16 eps (|x|_inf + |scene|_inf), the bound the bvh uses too, keeps every lower bound
// conservative (PBRT 3e sec. 3.9 style error bounds).
template <stored_object O, class Config>
inline auto kd_tree<O, Config>::knn_slack(const P& x) const -> T {
    T m = 0;
    for (std::size_t i = 0; i < D; ++i) m = std::max(m, std::abs(x[i]));
    const extent& r = extents_[root];
    if (!r.is_empty())
        for (std::size_t i = 0; i < D; ++i) m = std::max({m, std::abs(r.lo[i]), std::abs(r.hi[i])});
    return gamma * (2 * m) + underflow_slack<T>;
}

// Lower bound on the squared distance from x to anything below node n.
template <stored_object O, class Config>
inline auto kd_tree<O, Config>::extent_lower_bound(node_index n, const P& x, T slack) const -> T {
    const T d2 = extent_squared_distance(extents_[n], x);
    if (d2 == 0) return 0;
    const T d = std::sqrt(d2) - slack;
    return d > 0 ? d * d : T(0);
}

// Depth-first, nearer extent first; a child is entered only while its extent's distance
// times (1 + eps) is below the current k-th distance (Arya et al. 1998, on extents instead
// of cells). The objects' distances are exact, so with eps = 0 the answer is exact.
template <stored_object O, class Config>
inline void kd_tree<O, Config>::knn_objects(node_index n, knn_object_query& q) const {
    const node& nd = nodes_[n];
    if constexpr (Config::collect_stats) ++query_stats_.nodes_visited;
    if (nd.is_leaf) {
        const bucket& b = buckets_[nd.first];
        for (std::uint32_t i = 0; i < nd.count; ++i) {
            const slot_index s = b.items[i];
            if constexpr (Config::collect_stats) ++query_stats_.objects_tested;
            const T d2 = object_squared_distance(slots_.value(s), q.x);
            if (d2 < q.best.worst()) q.best.add(d2, s);
        }
        return;
    }
    const T la = extent_lower_bound(nd.first, q.x, q.slack), lb = extent_lower_bound(nd.first + 1, q.x, q.slack);
    const bool left_first = la <= lb;
    const node_index near = left_first ? nd.first : nd.first + 1;
    const T near_bound = left_first ? la : lb, far_bound = left_first ? lb : la;
    if (near_bound * q.eps_factor < q.best.worst()) knn_objects(near, q);
    if (far_bound * q.eps_factor < q.best.worst()) knn_objects(near == nd.first ? nd.first + 1 : nd.first, q);
}

// reach: the radius plus the rounding slack, compared with extent distances.
template <stored_object O, class Config>
inline void kd_tree<O, Config>::ball_objects(node_index n, const P& center, T reach, T r2,
                                             std::vector<iterator>& out) const {
    const node& nd = nodes_[n];
    if constexpr (Config::collect_stats) ++query_stats_.nodes_visited;
    if (nd.is_leaf) {
        const bucket& b = buckets_[nd.first];
        for (std::uint32_t i = 0; i < nd.count; ++i)
            if (object_squared_distance(slots_.value(b.items[i]), center) <= r2) out.push_back(make(b.items[i]));
        return;
    }
    for (node_index c = nd.first; c <= nd.first + 1; ++c) {
        const T d2 = extent_squared_distance(extents_[c], center);
        if (d2 == 0 || std::sqrt(d2) <= reach) ball_objects(c, center, reach, r2, out);
    }
}
}  // namespace spatial
