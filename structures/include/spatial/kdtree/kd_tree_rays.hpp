#pragma once
// spatial::kd_tree — thick-ray casting: front-to-back traversal of ray-parameter intervals,
// clipped against split planes (points) or node extents (objects), with the rounding pads
// that keep every clip conservative (PBRT 3e sec. 3.9).

#include "spatial/kdtree/kd_tree.hpp"
#include "spatial/octree/ray_cell_clip.hpp"

namespace spatial {

template <stored_object O, class Config>
inline auto kd_tree<O, Config>::intersect_object(const P& origin, const P& direction, scalar_type thickness,
                                                 info_type& info) const -> iterator {
    begin_query();
    detail::require_finite(origin, site("intersect"), "ray origin");
    detail::require_nonzero_direction(direction, site("intersect"));
    detail::require_nonnegative(thickness, site("intersect"), "ray thickness");
    if (slots_.size() == 0) return end();
    ray_query q{point_coords(origin), point_coords(direction), thickness, origin, direction, info};
    T t0 = 0, t1 = info.hit_time;
    if constexpr (has_extent) {
        // Objects: every node is clipped against its subtree's padded extent.
        if (clip_to_extent(q, extents_[root], t0, t1)) cast_objects(root, t0, t1, q);
    } else {
        for (unsigned d = 0; d < D && t0 <= t1; ++d) {
            clip_below(q, d, bounds_hi_[d] + pad(q, d, bounds_hi_[d]), t0, t1);
            clip_above(q, d, bounds_lo_[d] - pad(q, d, bounds_lo_[d]), t0, t1);
        }
        if (t0 <= t1) cast(root, t0, t1, q);
    }
    return q.hit == no_slot ? end() : make(q.hit);
}

template <stored_object O, class Config>
inline auto kd_tree<O, Config>::pad(const ray_query& q, unsigned d, T bound) -> T {
    return detail::ray_clip_params<T>::pad(q.r, bound, q.o[d]);
}

// Restrict [t0, t1] to the parameters where o_d + t v_d <= b.
template <stored_object O, class Config>
inline void kd_tree<O, Config>::clip_below(const ray_query& q, unsigned d, T b, T& t0, T& t1) {
    const T v = q.v[d];
    if (v == 0) {
        if (!(q.o[d] <= b)) t1 = -1, t0 = 1;
        return;
    }
    const T t = (b - q.o[d]) / v;
    if (v > 0) t1 = std::min(t1, t + gamma * std::abs(t));
    else t0 = std::max(t0, t - gamma * std::abs(t));
}

// Restrict [t0, t1] to the parameters where o_d + t v_d >= a.
template <stored_object O, class Config>
inline void kd_tree<O, Config>::clip_above(const ray_query& q, unsigned d, T a, T& t0, T& t1) {
    const T v = q.v[d];
    if (v == 0) {
        if (!(q.o[d] >= a)) t1 = -1, t0 = 1;
        return;
    }
    const T t = (a - q.o[d]) / v;
    if (v > 0) t0 = std::max(t0, t - gamma * std::abs(t));
    else t1 = std::min(t1, t + gamma * std::abs(t));
}

template <stored_object O, class Config>
inline void kd_tree<O, Config>::cast(node_index n, T t0, T t1, ray_query& q) const {
    if (!(t0 < q.info.hit_time) || t0 > t1) return;
    const node& nd = nodes_[n];
    if constexpr (Config::collect_stats) ++query_stats_.nodes_visited;
    if (nd.is_leaf) {
        scan_leaf(nd, [&](slot_index s) {
            if constexpr (Config::collect_stats) ++query_stats_.objects_tested;
            if (slots_.value(s).intersect(q.origin, q.direction, q.r, q.info)) q.hit = s;
        });
        return;
    }
    const unsigned d = nd.dim;
    T l0 = t0, l1 = t1, r0 = t0, r1 = t1;
    clip_below(q, d, nd.split + pad(q, d, nd.split), l0, l1);
    clip_above(q, d, nd.split - pad(q, d, nd.split), r0, r1);
    // Front to back: the child the ray enters first.
    const bool left_first = q.v[d] > 0 || (q.v[d] == 0 && q.o[d] <= nd.split);
    if (left_first) {
        cast(nd.first, l0, l1, q);
        cast(nd.first + 1, r0, r1, q);
    } else {
        cast(nd.first + 1, r0, r1, q);
        cast(nd.first, l0, l1, q);
    }
}

// Restrict [t0, t1] to the parameters where the thick ray can touch the (padded) box;
// false when nothing is left. Same padding argument as the cell planes (sec. 5.10): an
// object hit at t* has its contact point within r of its bounding box, hence of ex.
template <stored_object O, class Config>
inline bool kd_tree<O, Config>::clip_to_extent(const ray_query& q, const extent& ex, T& t0, T& t1) {
    if (ex.is_empty()) return false;
    for (unsigned d = 0; d < D && t0 <= t1; ++d) {
        clip_below(q, d, ex.hi[d] + pad(q, d, ex.hi[d]), t0, t1);
        clip_above(q, d, ex.lo[d] - pad(q, d, ex.lo[d]), t0, t1);
    }
    return t0 <= t1;
}

// [t0, t1]: the ray interval already clipped to n's extent. Children are clipped to their
// own extents and visited in order of entry; a child entered at or after the best hit so
// far cannot hold a strictly earlier one and is skipped.
template <stored_object O, class Config>
inline void kd_tree<O, Config>::cast_objects(node_index n, T t0, T t1, ray_query& q) const {
    if (!(t0 < q.info.hit_time)) return;
    const node& nd = nodes_[n];
    if constexpr (Config::collect_stats) ++query_stats_.nodes_visited;
    if (nd.is_leaf) {
        scan_leaf(nd, [&](slot_index s) {
            if constexpr (Config::collect_stats) ++query_stats_.objects_tested;
            if (slots_.value(s).intersect(q.origin, q.direction, q.r, q.info)) q.hit = s;
        });
        return;
    }
    T a0 = t0, a1 = t1, b0 = t0, b1 = t1;
    const bool hit_a = clip_to_extent(q, extents_[nd.first], a0, a1);
    const bool hit_b = clip_to_extent(q, extents_[nd.first + 1], b0, b1);
    if (hit_a && hit_b) {
        if (a0 <= b0) {
            cast_objects(nd.first, a0, a1, q);
            cast_objects(nd.first + 1, b0, b1, q);
        } else {
            cast_objects(nd.first + 1, b0, b1, q);
            cast_objects(nd.first, a0, a1, q);
        }
    } else if (hit_a) {
        cast_objects(nd.first, a0, a1, q);
    } else if (hit_b) {
        cast_objects(nd.first + 1, b0, b1, q);
    }
}
}  // namespace spatial
