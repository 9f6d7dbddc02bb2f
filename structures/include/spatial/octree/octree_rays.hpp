#pragma once
// spatial::octree — thick-ray casting front to back over loose cells, children visited in
// order of slab entry time (an ordered variant of Revelles, Urena & Lastra 2000).

#include "spatial/octree/octree.hpp"

namespace spatial {

template <stored_object O, class Config>
inline auto octree<O, Config>::intersect_object(const point_type& origin, const point_type& direction,
                                                scalar_type thickness, info_type& info) const -> iterator {
    detail::require_finite(origin, site("intersect"), "ray origin");
    detail::require_nonzero_direction(direction, site("intersect"));
    detail::require_nonnegative(thickness, site("intersect"), "ray thickness");
    if (slots_.size() == 0) return end();
    const coords o = point_coords(origin), v = point_coords(direction);
    slot_index hit = no_slot;
    struct pending {
        node_index n;
        T t_enter;
    };
    std::vector<pending> stack;
    {
        T t0 = 0, t1 = info.hit_time;
        const node& r = nodes_[root_];
        if (!detail::clip_box<T, D>(o, v, r.llo, r.lhi, thickness, t0, t1)) return end();
        stack.push_back({root_, t0});
    }
    std::array<pending, fanout> kids;
    while (!stack.empty()) {
        const pending p = stack.back();
        stack.pop_back();
        if (!(p.t_enter < info.hit_time)) continue;
        const node& nd = nodes_[p.n];
        for (slot_index s : nd.items)
            if (slots_.value(s).intersect(origin, direction, thickness, info)) hit = s;
        if (nd.is_leaf()) continue;
        std::size_t m = 0;
        for (std::size_t b = 0; b < fanout; ++b) {
            const node_index c = nd.first_child + static_cast<node_index>(b);
            const node& cn = nodes_[c];
            if (cn.is_leaf() && cn.items.empty()) continue;
            T t0 = 0, t1 = info.hit_time;
            if (detail::clip_box<T, D>(o, v, cn.llo, cn.lhi, thickness, t0, t1) && t0 < info.hit_time)
                kids[m++] = {c, t0};
        }
        // Insertion sort (at most 2^D entries) by decreasing entry time, then push: the
        // earliest entry ends on top of the stack and is visited first.
        for (std::size_t i = 1; i < m; ++i)
            for (std::size_t j = i; j > 0 && kids[j - 1].t_enter < kids[j].t_enter; --j)
                std::swap(kids[j - 1], kids[j]);
        for (std::size_t i = 0; i < m; ++i) stack.push_back(kids[i]);
    }
    return hit == no_slot ? end() : make(hit);
}
}  // namespace spatial
