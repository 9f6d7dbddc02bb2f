#pragma once
// spatial::octree — changing the tree: slots and their positions in node item lists, child
// blocks (freed ones reused), splitting a leaf over capacity (or refusing, for duplicates),
// placing an object at the deepest node whose loose cell contains it, distributing a bulk
// batch top-down, collapsing nodes after erasure.

#include <new>

#include "spatial/core/reserve_for_push.hpp"
#include "spatial/octree/octree.hpp"

namespace spatial {

template <stored_object O, class Config>
template <class InputIt>
inline void octree<O, Config>::insert(InputIt first, InputIt last) {
    if constexpr (!std::random_access_iterator<InputIt>) {
        // Single-pass or list-like input (a container's own range too): copy once so that it
        // can be validated first and read again.
        const std::vector<O> batch(first, last);
        insert(batch.begin(), batch.end());
    } else {
        for (auto it = first; it != last; ++it) detail::require_finite_object(*it, site("insert(first, last)"));
        const auto m = static_cast<std::size_t>(last - first);
        if (m == 0) return;
        slots_.require_room_for(m, site("insert(first, last)"));
        slots_.reserve(slots_.capacity() + m);
        const bool rebuild = slots_.size() == 0 || m >= slots_.size();
        extent box = extent_of(*first);
        for (auto it = first; it != last; ++it) merge_into(box, extent_of(*it));
        for (std::size_t i = 0; i < D; ++i) box.c[i] = box.lo[i] + (box.hi[i] - box.lo[i]) / 2;
        if (!rebuild) ensure_root_contains(box);  // a grown root holds the same objects
        // Strong guarantee: if anything below cannot allocate, the batch's objects are taken
        // out of the nodes they reached and their slots given back, latest first. Splits
        // already made stay (the tree is valid with them).
        std::vector<std::pair<slot_index, bool>> fresh;  // slot, whether it was a reused one
        fresh.reserve(m);
        try {
            for (auto it = first; it != last; ++it) {
                const bool reused = slots_.reuses_a_slot();
                fresh.emplace_back(allocate(*it), reused);
            }
            if (rebuild) {
                rebuild_all();
            } else {
                std::vector<record> recs;
                recs.reserve(m);
                for (const auto& f : fresh) recs.push_back(record_of(f.first));
                merge_batch(recs);
            }
        } catch (const std::bad_alloc&) {
            for (auto it = fresh.rbegin(); it != fresh.rend(); ++it) {
                if (slots_.meta(it->first) != unplaced) remove_item(slots_.meta(it->first), it->first);
                slots_.undo_allocate(it->first, it->second);
            }
            throw;
        }
    }
}

template <stored_object O, class Config>
inline void octree<O, Config>::swap_contents(octree& o) {
    this->swap_with(o, &octree::pos_, &octree::nodes_, &octree::free_blocks_, &octree::root_);
}

// ================= node and item bookkeeping ==========================================
template <stored_object O, class Config>
inline auto octree<O, Config>::allocate(const O& x) -> slot_index {
    // pos_ grows first: a slot must never exist without its position entry.
    if (!slots_.reuses_a_slot() && pos_.size() <= slots_.capacity()) pos_.resize(slots_.capacity() + 1);
    return slots_.allocate(x, unplaced);
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
    // Strong guarantee: the children's lists and the kept list are filled aside, and the
    // child block taken, before the node changes; the commit below cannot fail. (The lists
    // get the capacity their push_backs would have given.)
    std::array<std::vector<slot_index>, fanout + 1> lists;  // [fanout]: the objects that stay
    {
        std::array<std::size_t, fanout + 1> counts{};
        for (std::size_t i = 0; i < m; ++i) ++counts[target[i]];
        for (std::size_t b = 0; b <= fanout; ++b) detail::reserve_for_push(lists[b], counts[b]);
        for (std::size_t i = 0; i < m; ++i) lists[target[i]].push_back(nd.items[i]);
    }
    make_children(n);
    const node_index first_child = nodes_[n].first_child;  // make_children may have reallocated nodes_
    for (std::size_t b = 0; b <= fanout; ++b) {
        const node_index c = b == fanout ? n : first_child + static_cast<node_index>(b);
        nodes_[c].items = std::move(lists[b]);
        const auto& items = nodes_[c].items;
        for (std::size_t i = 0; i < items.size(); ++i) {
            pos_[items[i]] = static_cast<std::uint32_t>(i);
            slots_.set_meta(items[i], c);
        }
    }
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
    const bool reused = slots_.reuses_a_slot();
    const slot_index s = allocate(x);
    node_index n = start;
    while (!nodes_[n].is_leaf()) {
        const std::size_t b = child_bits(nodes_[n], e.c);
        const node_index c = nodes_[n].first_child + static_cast<node_index>(b);
        if (!loose_contains(nodes_[c], e)) break;
        n = c;
    }
    // Strong guarantee: if the node's list or a split cannot allocate, x is taken out again
    // (each split is all-or-nothing, so the tree is valid whichever split failed).
    try {
        add_item(n, s);
        if (nodes_[n].is_leaf() && nodes_[n].items.size() > leaf_capacity) split_recursive(n);
    } catch (const std::bad_alloc&) {
        if (slots_.meta(s) != unplaced) remove_item(slots_.meta(s), s);
        slots_.undo_allocate(s, reused);
        throw;
    }
    return s;
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
    // Room first (the node's list, the free block entry), so the merge cannot fail half-way.
    detail::reserve_for_push(nd.items, total - nd.items.size());
    detail::reserve_for_push(free_blocks_, 1);
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
    // Merging is best-effort: without memory for a merged list the tree keeps its (valid)
    // children, and an erase never fails for it.
    try {
        node_index x = nodes_[n].is_leaf() ? nodes_[n].parent : n;
        while (x != no_node && try_collapse(x)) x = nodes_[x].parent;
    } catch (const std::bad_alloc&) {
    }
}

// The range-erase hooks of container_base: a range under a quarter of the tree is erased
// one by one; a larger one rebuilds the survivors once (O(n depth)).
template <stored_object O, class Config>
inline void octree<O, Config>::erase_slots(std::span<const slot_index> doomed) {
    for (slot_index s : doomed) erase(make(s));
}
}  // namespace spatial
