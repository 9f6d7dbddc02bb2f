#pragma once
// spatial::kd_tree — diagnostics for tests: the structural invariant check (split bounds,
// child ranges, cells, restore bounds, bucket back-links, extents, counts, depths), the count of points
// lying on split planes, subtree visiting and the height.

#include "spatial/kdtree/kd_tree.hpp"

namespace spatial {

template <stored_object O, class Config>
inline std::string kd_tree<O, Config>::check_invariants() const {
    if (!has_root()) {  // the unallocated empty tree: nothing may refer to a node
        if (slots_.size() != 0) return "no root but size() is " + std::to_string(slots_.size());
        if (leaves_ != 0 || !buckets_.empty() || !extents_.empty() || !free_pairs_.empty() || !free_buckets_.empty())
            return "no root but leaves, buckets, extents or free lists left";
        return {};
    }
    std::string err;
    coords lo, hi;
    lo.fill(-std::numeric_limits<T>::infinity());
    hi.fill(std::numeric_limits<T>::infinity());
    std::size_t seen = 0;
    extent keys;
    check_node(root, lo, hi, 0, seen, keys, err);
    if (err.empty() && seen != slots_.size())
        err = "tree holds " + std::to_string(seen) + " points but size() is " + std::to_string(slots_.size());
    return err;
}

// ---- invariant checking ----
// Also returns the bounding box of the subtree's keys in `keys` (empty when it holds none),
// against which the parent checks its child ranges.
template <stored_object O, class Config>
inline void kd_tree<O, Config>::check_node(node_index n, const coords& lo, const coords& hi, std::uint16_t depth,
                                           std::size_t& seen, extent& keys, std::string& err) const {
    keys = extent::empty();
    if (!err.empty()) return;
    const node& nd = nodes_[n];
    if (nd.depth != depth) err = "node " + std::to_string(n) + " has a wrong depth";
    if (nd.is_leaf) {
        const bucket& b = buckets_[nd.first];
        if (b.owner != n) err = "bucket owner mismatch at node " + std::to_string(n);
        if (b.cell_lo != lo || b.cell_hi != hi) err = "stale cell at leaf " + std::to_string(n);
        if (nd.leaf.run != no_slot && nd.leaf.run != run_of(b.items.data(), nd.leaf.count))
            err = "leaf " + std::to_string(n) + "'s run does not match its bucket";
        for (std::uint32_t i = 0; i < nd.leaf.count; ++i) {
            const slot_index s = b.items[i];
            if (!slots_.occupied(s) || slots_.meta(s) != nd.first) {
                err = "slot back-link broken";
                continue;
            }
            const coords c = key_of(slots_.value(s));
            keys.grow(c);
            if (!in_cell(c, lo, hi)) err = "point outside its leaf cell";
            else if constexpr (has_extent) {
                if (!extents_[n].contains(extent_of(slots_.value(s))))
                    err = "object outside its leaf's extent at node " + std::to_string(n);
            }
        }
        seen += nd.leaf.count;
        return;
    }
    if (links_[nd.first].parent != n || links_[nd.first + 1].parent != n) err = "parent link broken";
    if constexpr (has_extent) {
        for (node_index c = nd.first; c <= nd.first + 1; ++c)
            if (!extents_[c].is_empty() && !extents_[n].contains(extents_[c]))
                err = "extent of node " + std::to_string(c) + " not inside its parent's";
    }
    if (links_[nd.first].restore != hi[nd.dim] || links_[nd.first + 1].restore != lo[nd.dim])
        err = "restore bound broken below node " + std::to_string(n);
    coords lhi = hi, rlo = lo;
    lhi[nd.dim] = nd.split;
    rlo[nd.dim] = nd.split;
    extent left, right;
    check_node(nd.first, lo, lhi, static_cast<std::uint16_t>(depth + 1), seen, left, err);
    check_node(nd.first + 1, rlo, hi, static_cast<std::uint16_t>(depth + 1), seen, right, err);
    const unsigned d = nd.dim;
    const child_ranges& r = nd.ranges;
    if (err.empty() && (left.lo[d] < r.left_lo || left.hi[d] > r.left_hi || right.lo[d] < r.right_lo ||
                        right.hi[d] > r.right_hi))
        err = "a key outside its child's range at node " + std::to_string(n);
    keys = left;
    keys.grow(right);
}

template <stored_object O, class Config>
inline std::size_t kd_tree<O, Config>::on_planes(node_index n) const {
    const node& nd = nodes_[n];
    if (nd.is_leaf) return 0;
    std::size_t here = 0;
    for_each_slot(n, [&](slot_index s) { here += object_center(slots_.value(s), nd.dim) == nd.split; });
    return here + on_planes(nd.first) + on_planes(nd.first + 1);
}

template <stored_object O, class Config>
template <class F>
inline void kd_tree<O, Config>::for_each_slot(node_index n, F&& f) const {
    const node& nd = nodes_[n];
    if (nd.is_leaf) {
        scan_leaf(nd, f);
        return;
    }
    for_each_slot(nd.first, f);
    for_each_slot(nd.first + 1, f);
}

template <stored_object O, class Config>
inline std::size_t kd_tree<O, Config>::height_of(node_index n) const {
    if (nodes_[n].is_leaf) return 0;
    return 1 + std::max(height_of(nodes_[n].first), height_of(nodes_[n].first + 1));
}
}  // namespace spatial
