#pragma once
// spatial::octree — changing the tree: slots and their positions in node item lists, child
// blocks (freed ones reused), splitting a leaf over capacity (or refusing, for duplicates),
// placing an object at the deepest node whose loose cell contains it, distributing a bulk
// batch top-down, collapsing nodes after erasure.

#include "spatial/octree/octree.hpp"

namespace spatial {

template <stored_object O, class Config>
template <class InputIt>
inline void octree<O, Config>::insert(InputIt first, InputIt last) {
    std::vector<O> batch(first, last);
    for (const O& x : batch) detail::require_finite_object(x, site("insert(first, last)"));
    if (batch.empty()) return;
    slots_.require_room_for(batch.size(), site("insert(first, last)"));
    slots_.reserve(slots_.capacity() + batch.size());
    const bool rebuild = slots_.size() == 0 || batch.size() >= slots_.size();
    extent box = extent_of(batch.front());
    for (const O& x : batch) merge_into(box, extent_of(x));
    for (std::size_t i = 0; i < D; ++i) box.c[i] = box.lo[i] + (box.hi[i] - box.lo[i]) / 2;
    if (!rebuild) ensure_root_contains(box);
    std::vector<slot_index> fresh;
    fresh.reserve(batch.size());
    for (const O& x : batch) fresh.push_back(allocate(x));
    if (rebuild) {
        rebuild_all();
        return;
    }
    distribute(root_, fresh);
}

template <stored_object O, class Config>
inline void octree<O, Config>::swap_contents(octree& o) {
    this->swap_with(o, &octree::pos_, &octree::nodes_, &octree::free_blocks_, &octree::root_);
}

// ================= node and item bookkeeping ==========================================
template <stored_object O, class Config>
inline auto octree<O, Config>::allocate(const O& x) -> slot_index {
    const slot_index s = slots_.allocate(x, 0);
    if (pos_.size() <= s) pos_.resize(std::max<std::size_t>(s + 1, slots_.capacity()));
    return s;
}

template <stored_object O, class Config>
inline void octree<O, Config>::add_item(node_index n, slot_index s) {
    pos_[s] = static_cast<std::uint32_t>(nodes_[n].items.size());
    nodes_[n].items.push_back(s);
    slots_.set_meta(s, n);
}

template <stored_object O, class Config>
inline void octree<O, Config>::remove_item(node_index n, slot_index s) {
    auto& items = nodes_[n].items;
    const std::uint32_t i = pos_[s];
    items[i] = items.back();
    pos_[items[i]] = i;
    items.pop_back();
}

template <stored_object O, class Config>
inline auto octree<O, Config>::new_block() -> node_index {
    return detail::reuse_or_grow(free_blocks_, [this] {
        if (nodes_.size() + fanout >= static_cast<std::size_t>(no_node))
            throw std::length_error("octree: too many nodes");
        const node_index b = static_cast<node_index>(nodes_.size());
        nodes_.resize(nodes_.size() + fanout);
        return b;
    });
}

// Creates n's children; their loose cells are clipped to n's so that they nest exactly.
template <stored_object O, class Config>
inline void octree<O, Config>::make_children(node_index n) {
    const node_index first = new_block();
    const node parent_copy_geometry = geometry_of(nodes_[n]);
    for (std::size_t b = 0; b < fanout; ++b) {
        node& c = nodes_[first + b];
        c.items.clear();
        c.first_child = no_node;
        c.parent = n;
        c.split_retry = 0;
        set_child_cell(c, parent_copy_geometry, b);
    }
    nodes_[n].first_child = first;
}

// Splits leaf n if useful (see the header comment); returns whether it split.
template <stored_object O, class Config>
inline bool octree<O, Config>::split(node_index n) {
    node& nd = nodes_[n];
    const std::size_t m = nd.items.size();
    if (m <= leaf_capacity || m < nd.split_retry || !may_split(nd)) return false;
    bool moves = false, distinct = false;
    const extent first = extent_of(slots_.value(nd.items[0]));
    std::vector<std::uint8_t> target(m);
    for (std::size_t i = 0; i < m; ++i) {
        const extent e = extent_of(slots_.value(nd.items[i]));
        const std::size_t t = target_of(nd, e);
        target[i] = static_cast<std::uint8_t>(t);
        moves |= t != fanout;
        distinct |= e.c != first.c;
    }
    if (!moves || !distinct) {
        nd.split_retry = 2 * m;  // retry only after doubling: O(1) amortised per insert
        return false;
    }
    make_children(n);
    node& me = nodes_[n];  // make_children may have reallocated nodes_
    std::vector<slot_index> keep;
    for (std::size_t i = 0; i < m; ++i) {
        const slot_index s = me.items[i];
        if (target[i] == fanout) keep.push_back(s);
        else add_item(me.first_child + target[i], s);
    }
    nodes_[n].items = std::move(keep);
    for (std::size_t i = 0; i < nodes_[n].items.size(); ++i) pos_[nodes_[n].items[i]] = static_cast<std::uint32_t>(i);
    nodes_[n].split_retry = 0;
    return true;
}

template <stored_object O, class Config>
inline void octree<O, Config>::split_recursive(node_index n) {
    std::vector<node_index> work{n};
    while (!work.empty()) {
        const node_index x = work.back();
        work.pop_back();
        if (!split(x)) continue;
        for (std::size_t b = 0; b < fanout; ++b) {
            const node_index c = nodes_[x].first_child + static_cast<node_index>(b);
            if (nodes_[c].items.size() > leaf_capacity) work.push_back(c);
        }
    }
}

// Descends from `start` (whose loose cell contains e) to the deepest node that takes x.
template <stored_object O, class Config>
inline auto octree<O, Config>::place(node_index start, const O& x, const extent& e) -> slot_index {
    const slot_index s = allocate(x);
    node_index n = start;
    while (!nodes_[n].is_leaf()) {
        const std::size_t b = child_bits(nodes_[n], e.c);
        const node_index c = nodes_[n].first_child + static_cast<node_index>(b);
        if (!loose_contains(nodes_[c], e)) break;
        n = c;
    }
    add_item(n, s);
    if (nodes_[n].is_leaf() && nodes_[n].items.size() > leaf_capacity) split_recursive(n);
    return s;
}

// Top-down distribution of fresh slots below n (bulk insert).
template <stored_object O, class Config>
inline void octree<O, Config>::distribute(node_index n, std::vector<slot_index>& batch) {
    if (batch.empty()) return;
    if (nodes_[n].is_leaf()) {
        for (slot_index s : batch) add_item(n, s);
        if (nodes_[n].items.size() > leaf_capacity) split_recursive(n);
        return;
    }
    std::array<std::vector<slot_index>, fanout> parts;
    for (slot_index s : batch) {
        const extent e = extent_of(slots_.value(s));
        const std::size_t b = child_bits(nodes_[n], e.c);
        const node_index c = nodes_[n].first_child + static_cast<node_index>(b);
        if (loose_contains(nodes_[c], e)) parts[b].push_back(s);
        else add_item(n, s);
    }
    batch.clear();
    batch.shrink_to_fit();
    for (std::size_t b = 0; b < fanout; ++b) distribute(nodes_[n].first_child + static_cast<node_index>(b), parts[b]);
}

// A node whose children are all leaves and whose subtree fits in one leaf absorbs them.
template <stored_object O, class Config>
inline bool octree<O, Config>::try_collapse(node_index x) {
    node& nd = nodes_[x];
    if (nd.is_leaf()) return false;
    std::size_t total = nd.items.size();
    for (std::size_t b = 0; b < fanout; ++b) {
        const node& c = nodes_[nd.first_child + b];
        if (!c.is_leaf()) return false;
        total += c.items.size();
    }
    if (total > leaf_capacity) return false;
    const node_index first = nd.first_child;
    for (std::size_t b = 0; b < fanout; ++b) {
        node& c = nodes_[first + b];
        for (slot_index s : c.items) add_item(x, s);
        c.items.clear();
        c.items.shrink_to_fit();
        c.parent = no_node;
    }
    nodes_[x].first_child = no_node;
    nodes_[x].split_retry = 0;
    free_blocks_.push_back(first);
    return true;
}

template <stored_object O, class Config>
inline void octree<O, Config>::collapse_from(node_index n) {
    node_index x = nodes_[n].is_leaf() ? nodes_[n].parent : n;
    while (x != no_node && try_collapse(x)) x = nodes_[x].parent;
}

// The range-erase hooks of container_base: a range under a quarter of the tree is erased
// one by one; a larger one rebuilds the survivors once (O(n depth)).
template <stored_object O, class Config>
inline void octree<O, Config>::erase_slots(std::span<const slot_index> doomed) {
    for (slot_index s : doomed) erase(make(s));
}
}  // namespace spatial
