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
        coords offset = root_offsets(q.x);
        knn(root, offset, q);
    }
}

// The query's per-dimension offsets from the box of all keys (zero inside it): the cell
// offsets a search starts from, so a query off the data prunes from the first split on.
template <stored_object O, class Config>
inline auto kd_tree<O, Config>::root_offsets(const coords& x) const -> coords {
    coords offset;
    for (std::size_t d = 0; d < D; ++d)
        offset[d] = x[d] < bounds_lo_[d] ? x[d] - bounds_lo_[d] : (x[d] > bounds_hi_[d] ? x[d] - bounds_hi_[d] : T(0));
    return offset;
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
inline void kd_tree<O, Config>::knn(node_index n, coords& offset, knn_query& q) const {
    const node& nd = nodes_[n];
    if constexpr (Config::collect_stats) ++query_stats_.nodes_visited;
    if (nd.is_leaf) {
        knn_leaf(nd, q);
        return;
    }
    // The near child first: with its offset unchanged its cell distance is the parent's,
    // below the bound when the parent was entered (nothing was searched since).
    const unsigned d = nd.dim;
    const T old = offset[d];
    const side_offsets so = child_offsets(nd, q.x[d], old);
    if (so.near_offset == old) {
        knn(so.near, offset, q);
    } else if (far_cell_distance(offset, d, so.near_offset) * q.eps_factor < q.best.worst()) {
        offset[d] = so.near_offset;
        knn(so.near, offset, q);
        offset[d] = old;
    }
    if (far_cell_distance(offset, d, so.far_offset) * q.eps_factor < q.best.worst()) {
        offset[d] = so.far_offset;
        knn(so.far, offset, q);
        offset[d] = old;
    }
}

// A leaf whose points are a run (contiguous values) computes all their squared distances
// first, in a loop without branches that the compiler vectorises (4 or 8 points per SIMD
// step: the same subtractions, products and sums per point in the same order, and no
// contraction into fused multiply-adds, so the values are those of the scalar loop bit for
// bit). One vectorised comparison then tells whether any is below the result set's bound
// (most leaves after the first have none); if so they are offered in leaf order, so the same
// points are added in the same order as by the scalar scan and answers are unchanged. A
// leaf of scattered slots takes the scalar scan. The figures, with the result set's inline
// storage: results/checks/knn_leaf_distances.
template <stored_object O, class Config>
inline void kd_tree<O, Config>::knn_leaf(const node& nd, knn_query& q) const {
    const std::uint32_t count = nd.leaf.count;
    if constexpr (Config::collect_stats) query_stats_.objects_tested += count;
    const slot_index run = nd.leaf.run;
    if (run == no_slot) {
        scan_leaf(nd, [&](slot_index s) {
            const T d2 = squared_distance(slots_.value(s), q.x);
            if (d2 < q.best.worst()) q.best.add(d2, s);
        });
        return;
    }
    const O* values = prefetch_run(run, count);
    T d2[leaf_capacity];
    for (std::uint32_t i = 0; i < count; ++i) d2[i] = squared_distance(values[i], q.x);
    const T bound = q.best.worst();
    int below = 0;
    for (std::uint32_t i = 0; i < count; ++i) below |= d2[i] < bound;
    if (!below) return;
    for (std::uint32_t i = 0; i < count; ++i)
        if (d2[i] < q.best.worst()) q.best.add(d2[i], static_cast<slot_index>(run + i));
}

// The query's offset along the cut to each child of inner node nd: the near child (the side
// of the split plane x lies on, searched first) and the far one. Each is the larger of the
// inherited offset `old` and x's offset from the child's key range: both bound |x - p| along
// the cut from below for every point p of the child, so the larger does too, and rounding
// keeps it so (see far_cell_distance).
template <stored_object O, class Config>
inline auto kd_tree<O, Config>::child_offsets(const node& nd, T x, T old) -> side_offsets {
    const auto offset_from = [x, old](T lo, T hi) {
        const T gap = x < lo ? x - lo : (x > hi ? x - hi : T(0));
        return std::abs(gap) > std::abs(old) ? gap : old;
    };
    const auto [left_lo, left_hi] = left_range(nd);
    const auto [right_lo, right_hi] = right_range(nd);
    const T to_left = offset_from(left_lo, left_hi), to_right = offset_from(right_lo, right_hi);
    if (x - nd.split <= 0) return {nd.first, nd.first + 1, to_left, to_right};
    return {nd.first + 1, nd.first, to_right, to_left};
}

template <stored_object O, class Config>
template <class Emit>
inline void kd_tree<O, Config>::ball(node_index n, coords& offset, const coords& x, T r2, Emit& emit) const {
    const node& nd = nodes_[n];
    if constexpr (Config::collect_stats) ++query_stats_.nodes_visited;
    if (nd.is_leaf) {
        scan_leaf(nd, [&](slot_index s) {
            const T d2 = squared_distance(slots_.value(s), x);
            if (d2 <= r2) emit(s, d2);
        });
        return;
    }
    const unsigned d = nd.dim;
    const T old = offset[d];
    const side_offsets so = child_offsets(nd, x[d], old);
    for (const auto& [child, child_offset] : {std::pair{so.near, so.near_offset}, std::pair{so.far, so.far_offset}}) {
        if (!(far_cell_distance(offset, d, child_offset) <= r2)) continue;
        offset[d] = child_offset;
        ball(child, offset, x, r2, emit);
        offset[d] = old;
    }
}

template <stored_object O, class Config>
inline void kd_tree<O, Config>::box(node_index n, const P& lo, const P& hi, std::vector<iterator>& out) const {
    const node& nd = nodes_[n];
    if constexpr (Config::collect_stats) ++query_stats_.nodes_visited;
    if (nd.is_leaf) {
        scan_leaf(nd, [&](slot_index s) {
            if (object_overlaps_box(slots_.value(s), lo, hi)) out.push_back(make(s));
        });
        return;
    }
    if constexpr (has_extent) {
        // An object overlapping the box has a bounding box overlapping it (the exact test
        // of object_overlaps_box runs only after the box test), so extents prune exactly.
        for (node_index c = nd.first; c <= nd.first + 1; ++c)
            if (extent_overlaps(extents_[c], lo, hi)) box(c, lo, hi, out);
    } else {
        const auto [left_lo, left_hi] = left_range(nd);
        const auto [right_lo, right_hi] = right_range(nd);
        if (lo[nd.dim] <= left_hi && hi[nd.dim] >= left_lo) box(nd.first, lo, hi, out);
        if (lo[nd.dim] <= right_hi && hi[nd.dim] >= right_lo) box(nd.first + 1, lo, hi, out);
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
        for (std::uint32_t i = 0; i < nd.leaf.count; ++i)
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
        scan_leaf(nd, [&](slot_index s) {
            if constexpr (Config::collect_stats) ++query_stats_.objects_tested;
            const T d2 = object_squared_distance(slots_.value(s), q.x);
            if (d2 < q.best.worst()) q.best.add(d2, s);
        });
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
template <class Emit>
inline void kd_tree<O, Config>::ball_objects(node_index n, const P& center, T reach, T r2, Emit& emit) const {
    const node& nd = nodes_[n];
    if constexpr (Config::collect_stats) ++query_stats_.nodes_visited;
    if (nd.is_leaf) {
        scan_leaf(nd, [&](slot_index s) {
            const T d2 = object_squared_distance(slots_.value(s), center);
            if (d2 <= r2) emit(s, d2);
        });
        return;
    }
    for (node_index c = nd.first; c <= nd.first + 1; ++c) {
        const T d2 = extent_squared_distance(extents_[c], center);
        if (d2 == 0 || std::sqrt(d2) <= reach) ball_objects(c, center, reach, r2, emit);
    }
}
}  // namespace spatial
