#pragma once
// spatial::octree — the queries other than rays: best-first kNN over loose cells (Hjaltason &
// Samet 1999) with (1+eps) pruning, ball and box ranges and equality lookup pruned by loose
// cells, all with explicit stacks.

#include "spatial/octree/octree.hpp"

namespace spatial {

template <stored_object O, class Config>
inline auto octree<O, Config>::find_nearest(const point_type& x, size_type k, scalar_type eps) const
    -> std::vector<iterator> {
    detail::require_finite(x, site("find_nearest"), "query point");
    detail::require_nonnegative(eps, site("find_nearest"), "eps");
    std::vector<iterator> out;
    if (k == 0 || slots_.size() == 0) return out;
    const coords q = point_coords(x);
    const T factor = (1 + eps) * (1 + eps);
    knn_result_set<T> best(std::min<std::size_t>(k, slots_.size()));
    using entry = std::pair<T, node_index>;
    std::priority_queue<entry, std::vector<entry>, std::greater<entry>> frontier;
    frontier.push({cell_distance2(nodes_[root_], q), root_});
    while (!frontier.empty()) {
        const auto [lb, n] = frontier.top();
        frontier.pop();
        if (!(lb * bound_slack * factor < best.worst())) break;
        const node& nd = nodes_[n];
        for (slot_index s : nd.items) best.add(object_squared_distance(slots_.value(s), x), s);
        if (nd.is_leaf()) continue;
        for (std::size_t b = 0; b < fanout; ++b) {
            const node_index c = nd.first_child + static_cast<node_index>(b);
            if (nodes_[c].is_leaf() && nodes_[c].items.empty()) continue;
            const T d2 = cell_distance2(nodes_[c], q);
            if (d2 * bound_slack * factor < best.worst()) frontier.push({d2, c});
        }
    }
    for (const auto& c : best.finish()) out.push_back(make(c.slot));
    return out;
}

template <stored_object O, class Config>
inline auto octree<O, Config>::find_in_ball(const point_type& center, scalar_type radius) const
    -> std::vector<iterator> {
    detail::require_finite(center, site("find_in_ball"), "center");
    detail::require_nonnegative(radius, site("find_in_ball"), "radius");
    std::vector<iterator> out;
    if (slots_.size() == 0) return out;
    const coords q = point_coords(center);
    const T r2 = radius * radius;
    std::vector<node_index> stack{root_};
    while (!stack.empty()) {
        const node& nd = nodes_[stack.back()];
        stack.pop_back();
        if (!(cell_distance2(nd, q) * bound_slack <= r2)) continue;
        for (slot_index s : nd.items)
            if (object_squared_distance(slots_.value(s), center) <= r2) out.push_back(make(s));
        if (!nd.is_leaf())
            for (std::size_t b = 0; b < fanout; ++b) stack.push_back(nd.first_child + static_cast<node_index>(b));
    }
    return out;
}

template <stored_object O, class Config>
inline auto octree<O, Config>::find_in_box(const point_type& lo, const point_type& hi) const -> std::vector<iterator> {
    detail::require_finite(lo, site("find_in_box"), "box corner lo");
    detail::require_finite(hi, site("find_in_box"), "box corner hi");
    std::vector<iterator> out;
    if (slots_.size() == 0) return out;
    std::vector<node_index> stack{root_};
    while (!stack.empty()) {
        const node& nd = nodes_[stack.back()];
        stack.pop_back();
        bool overlaps = true;
        // Same comparison form as object_box_overlaps_box, so an object inside the
        // loose cell that passes it implies the cell passes it (even for lo > hi).
        for (std::size_t i = 0; i < D && overlaps; ++i) overlaps = !(nd.lhi[i] < lo[i] || nd.llo[i] > hi[i]);
        if (!overlaps) continue;
        for (slot_index s : nd.items)
            if (object_overlaps_box(slots_.value(s), lo, hi)) out.push_back(make(s));
        if (!nd.is_leaf())
            for (std::size_t b = 0; b < fanout; ++b) stack.push_back(nd.first_child + static_cast<node_index>(b));
    }
    return out;
}

// ================= lookup ==============================================================
template <stored_object O, class Config>
inline void octree<O, Config>::collect_equal(const O& x, std::vector<slot_index>& out, bool first_only) const {
    if (root_ == no_node || slots_.size() == 0) return;
    const extent e = extent_of(x);
    std::vector<node_index> stack{root_};
    while (!stack.empty()) {
        const node& nd = nodes_[stack.back()];
        stack.pop_back();
        if (!loose_contains(nd, e)) continue;
        for (slot_index s : nd.items)
            if (slots_.value(s) == x) {
                out.push_back(s);
                if (first_only) return;
            }
        if (!nd.is_leaf())
            for (std::size_t b = 0; b < fanout; ++b) stack.push_back(nd.first_child + static_cast<node_index>(b));
    }
}
}  // namespace spatial
