#pragma once
// spatial::bvh — introspection: tree quality and node surface areas (the SAH's measure,
// MacDonald & Booth 1990), height, memory, and the structural invariant check the tests run.

#include "spatial/bvh/bvh.hpp"
#include "spatial/core/tree_height.hpp"

namespace spatial {

template <stored_object O, class BV, class Config>
inline double bvh<O, BV, Config>::quality() const {
    // Boxes only: a k-DOP's or hull's own area needs its vertices (kdop::measures), and
    // every full build and automatic refit asks for the quality (20 s of a 26-DOP build of
    // 1e5 triangles went to areas this sum never read).
    std::vector<node_index> order;
    preorder(order);
    double boxes = 0;
    for (node_index n : order) boxes += static_cast<double>(box_of(nodes_[n]).surface_area());
    return quality_from(boxes);
}
// The sum of the nodes' box areas, in preorder, over the root's (1 without a root area: an
// unallocated tree, as for an empty root leaf, or one whose boxes are all points).
template <stored_object O, class BV, class Config>
inline double bvh<O, BV, Config>::quality_from(double preorder_area_sum) const {
    const double root_area = has_root() ? static_cast<double>(box_of(nodes_[root]).surface_area()) : 0;
    return root_area > 0 ? preorder_area_sum / root_area : 1;
}

template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::node_surface_areas() const -> std::pair<double, double> {
    std::vector<node_index> order;
    preorder(order);
    double volumes = 0, boxes = 0;
    for (node_index n : order) {
        volumes += static_cast<double>(nodes_[n].volume.surface_area());
        boxes += static_cast<double>(box_of(nodes_[n]).surface_area());
    }
    return {volumes, boxes};
}

template <stored_object O, class BV, class Config>
inline std::size_t bvh<O, BV, Config>::height() const {
    if (!has_root()) return 0;
    return detail::tree_height(root, [this](node_index n, auto&& push) {
        if (!nodes_[n].leaf) push(nodes_[n].first), push(nodes_[n].first + 1);
    });
}

template <stored_object O, class BV, class Config>
inline std::size_t bvh<O, BV, Config>::memory_bytes() const {
    std::size_t b = sizeof(*this) + slots_.memory_bytes() + nodes_.capacity() * sizeof(node) +
                    items_.capacity() * sizeof(slot_index) +
                    (free_pairs_.capacity() + free_blocks_.capacity()) * sizeof(node_index);
    if constexpr (!std::is_trivially_copyable_v<BV>)
        for (const node& n : nodes_) b += bvh_detail::volume_heap_bytes(n.volume);
    if constexpr (wide_rays)
        if (const wide_layout* w = wide_.peek()) b += sizeof(*w) + w->memory_bytes();
    return b;
}

template <stored_object O, class BV, class Config>
inline std::string bvh<O, BV, Config>::check_invariants() const {
    if (!has_root()) {  // the unallocated empty tree: nothing may refer to a node or block
        if (slots_.size() != 0) return "no root but size() is " + std::to_string(slots_.size());
        if (!items_.empty() || !free_pairs_.empty() || !free_blocks_.empty())
            return "no root but leaf blocks or free lists left";
        return {};
    }
    std::vector<node_index> order;
    preorder(order);
    std::size_t seen = 0;
    for (node_index n : order) {
        const node& nd = nodes_[n];
        if (n != root && (nd.parent == no_node || (nodes_[nd.parent].first != n && nodes_[nd.parent].first + 1 != n)))
            return "parent link broken at node " + std::to_string(n);
        if constexpr (volume_is_box) {
            // Every aabb is the exact union of its children's (a leaf's: of its objects'):
            // path refits stop at the first unchanged box, which is right only if so.
            const box_type exact =
                nd.leaf ? objects_box(nd) : nodes_[nd.first].volume.merged(nodes_[nd.first + 1].volume);
            if (!(nd.count == 0 && nd.leaf) && !(exact == nd.volume))
                return "box of node " + std::to_string(n) + " is not the union of what it holds";
        }
        if (!nd.leaf) continue;
        if (nd.count > leaf_size) return "leaf " + std::to_string(n) + " over capacity";
        if (nd.count == 0 && n != root) return "empty non-root leaf " + std::to_string(n);
        seen += nd.count;
        for (std::uint32_t i = 0; i < nd.count; ++i) {
            const slot_index s = block(nd.first)[i];
            if (!slots_.occupied(s)) return "leaf holds a vacant slot";
            if (slots_.meta(s) != n) return "slot back-link broken";
            const O& v = slots_.value(s);
            for (node_index a = n; a != no_node; a = nodes_[a].parent) {
                const box_type& b = box_of(nodes_[a]);
                for (std::size_t k = 0; k < D; ++k)
                    if (object_lower(v, k) < b.lo[k] || object_upper(v, k) > b.hi[k])
                        return "node box misses an object";
                bool ok = true;
                object_hull_points(v, [&](const auto& hp) {
                    const bv_point p = to_bv(hp);
                    if (!(nodes_[a].volume.distance_lower_bound(p) <= slack_of(p))) ok = false;
                });
                if (!ok) return "volume of node " + std::to_string(a) + " misses a hull point";
            }
        }
    }
    if (seen != slots_.size())
        return "leaves hold " + std::to_string(seen) + " objects but size() is " + std::to_string(slots_.size());
    return {};
}

}  // namespace spatial
