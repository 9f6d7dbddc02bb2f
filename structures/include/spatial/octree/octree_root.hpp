#pragma once
// spatial::octree — the root cell: growing it outward one doubling at a time until its loose
// cell contains a new object, or rebuilding the whole tree around the bounding box of
// everything stored.

#include <new>

#include "spatial/octree/octree.hpp"

namespace spatial {

// Makes the root's loose cell contain e (growing or rebuilding); returns true if node
// indices changed (a rebuild), false if existing nodes kept their indices.
template <stored_object O, class Config>
inline bool octree<O, Config>::ensure_root_contains(const extent& e) {
    if (root_ == no_node || slots_.size() == 0) {
        rebuild_all(&e);
        return true;
    }
    if (loose_contains(nodes_[root_], e)) return false;
    if (nodes_[root_].is_leaf()) {
        rebuild_all(&e);
        return true;
    }
    for (int levels = 0; !loose_contains(nodes_[root_], e); ++levels) {
        if (levels == 8) {
            rebuild_all(&e);
            return true;
        }
        grow_once(e);
    }
    return false;
}

// Re-roots outward: a root of twice the size whose child on the far side from e is the
// old root (moved into the new child block; the root keeps its index).
template <stored_object O, class Config>
inline void octree<O, Config>::grow_once(const extent& e) {
    const node old = geometry_of(nodes_[root_]);
    std::size_t bit = 0;
    coords lo = old.lo;
    for (std::size_t i = 0; i < D; ++i)
        if (e.c[i] < mid(old, i)) {  // grow toward negative i: the old root is the upper half
            lo[i] = old.lo[i] - old.size;
            bit |= std::size_t(1) << i;
        }
    const node_index first = new_block();
    node& slot_for_old = nodes_[first + bit];
    slot_for_old = std::move(nodes_[root_]);
    const node_index moved = first + static_cast<node_index>(bit);
    node& nr = nodes_[root_];
    nr = node{};
    set_cell(nr, lo, old.size * 2);
    for (std::size_t i = 0; i < D; ++i) {  // contain the old root's loose cell exactly
        nr.llo[i] = std::min(nr.llo[i], old.llo[i]);
        nr.lhi[i] = std::max(nr.lhi[i], old.lhi[i]);
    }
    nr.first_child = first;
    node& mv = nodes_[moved];
    mv.parent = root_;
    for (slot_index s : mv.items) slots_.set_meta(s, moved);
    if (!mv.is_leaf())
        for (std::size_t b = 0; b < fanout; ++b) nodes_[mv.first_child + b].parent = moved;
    const node geo = geometry_of(nodes_[root_]);
    for (std::size_t b = 0; b < fanout; ++b) {
        if (b == bit) continue;
        node& c = nodes_[first + b];
        c = node{};
        c.parent = root_;
        set_child_cell(c, geo, b);
    }
}

// Rebuilds the whole tree around the bounding box of every stored object (and `extra`).
template <stored_object O, class Config>
inline void octree<O, Config>::rebuild_all(const extent* extra) {
    std::vector<slot_index> live;
    live.reserve(slots_.size());
    bool any = extra != nullptr;
    extent box{};
    if (extra) box = *extra;
    for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1)) {
        live.push_back(s);
        const extent e = extent_of(slots_.value(s));
        if (!any) box = e;
        any = true;
        merge_into(box, e);
    }
    // Strong guarantee: the old tree (nodes, positions, each slot's node) is set aside and put
    // back if the new one cannot be built. Moves of the vectors do not allocate.
    std::vector<node_index> old_meta;
    old_meta.reserve(live.size());
    for (slot_index s : live) old_meta.push_back(slots_.meta(s));
    std::vector<std::uint32_t> old_pos = pos_;
    std::vector<node> old_nodes = std::move(nodes_);
    std::vector<node_index> old_free = std::move(free_blocks_);
    const node_index old_root = root_;
    try {
        nodes_.reserve(old_nodes.capacity());  // the capacities the in-place rebuild kept
        free_blocks_.reserve(old_free.capacity());
        build_over(live, box, any);
    } catch (const std::bad_alloc&) {
        nodes_ = std::move(old_nodes);
        free_blocks_ = std::move(old_free);
        root_ = old_root;
        pos_ = std::move(old_pos);
        for (std::size_t i = 0; i < live.size(); ++i) slots_.set_meta(live[i], old_meta[i]);
        throw;
    }
}

// The tree over `live` in a cubic root around `box` (none if !any), into emptied nodes.
template <stored_object O, class Config>
inline void octree<O, Config>::build_over(const std::vector<slot_index>& live, const extent& box, bool any) {
    nodes_.clear();
    free_blocks_.clear();
    root_ = no_node;
    if (!any) return;
    T edge = 0, magnitude = 0;
    for (std::size_t i = 0; i < D; ++i) {
        edge = std::max(edge, box.hi[i] - box.lo[i]);
        magnitude = std::max({magnitude, std::abs(box.lo[i]), std::abs(box.hi[i])});
    }
    // Pad so that lo + edge >= hi after rounding; a degenerate box (one point, or all
    // objects identical) gets a cell a little larger than the ulps of its position.
    edge = edge * (1 + 8 * std::numeric_limits<T>::epsilon()) + 64 * std::numeric_limits<T>::epsilon() * magnitude;
    if (!(edge > 0)) edge = std::numeric_limits<T>::min() * T(1024);
    if (!std::isfinite(edge)) edge = std::numeric_limits<T>::max();
    nodes_.emplace_back();
    root_ = 0;
    set_cell(nodes_[root_], box.lo, edge);
    for (std::size_t i = 0; i < D; ++i) {  // contain the box exactly, whatever the rounding
        nodes_[root_].llo[i] = std::min(nodes_[root_].llo[i], box.lo[i]);
        nodes_[root_].lhi[i] = std::max(nodes_[root_].lhi[i], box.hi[i]);
    }
    // The subtree over every object, built top-down by array partition (octree_bulk.hpp).
    std::vector<record> recs;
    recs.reserve(live.size());
    for (slot_index s : live) recs.push_back(record_of(s));
    build_subtree(root_, recs);
}
}  // namespace spatial
