#pragma once
// spatial::bvh — dynamic updates: insertion, erasure, motion (update, reinsert, batched
// moves), refitting and the rebuild policy. Complexities are stated at the declarations in
// bvh.hpp.
//  * insert: greedy descent to the child whose AABB surface area grows least (Goldsmith &
//    Salmon 1987, "Automatic creation of object hierarchies for ray tracing"), then the
//    object joins that leaf, or a full leaf is rebuilt with the builder into a subtree; the
//    path is refitted. O(depth) plus O(leaf_size) fits. Hinted insert starts from the hint's
//    leaf, climbing only until a node's box contains the new object.
//  * erase: the leaf entry is removed (swap with its last); an emptied leaf is removed and
//    its sibling takes its parent's place; the path is refitted. O(depth).
//  * rebuild policy: when inserts + erases since the last build exceed
//    rebuild_factor * max(size at that build, min_rebuild_updates), the whole tree is rebuilt
//    with the builder, so a tree grown one object at a time is rebuilt at geometrically
//    growing sizes (O(log n) amortised per update) and quality never drifts far.
//  * motion: update(pos, v) replaces an object and refits its leaf-to-root path; with
//    refit_path = false many objects can be replaced and ONE refit() (bottom-up over all
//    nodes, O(n)) restores the volumes; until then queries throw std::logic_error.

#include "spatial/bvh/bvh.hpp"

namespace spatial {

// ---- insertion -------------------------------------------------------------------
template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::insert(const_iterator hint, const O& x) -> iterator {
    detail::require_finite_object(x, site("insert(hint, x)"));
    ensure_fresh();
    if (hint == end() || !slots_.occupied(hint.slot())) return make(insert_from(root, x));
    node_index n = slots_.meta(hint.slot());
    const item it = item_of(x, 0);
    while (n != root && !box_contains(box_of(nodes_[n]), it)) n = nodes_[n].parent;
    return make(insert_from(n, x));
}

template <stored_object O, class BV, class Config>
template <class InputIt>
inline void bvh<O, BV, Config>::bulk_insert(InputIt first, InputIt last, bool parallel) {
    if constexpr (!std::random_access_iterator<InputIt>) {
        const std::vector<O> batch(first, last);
        bulk_insert(batch.begin(), batch.end(), parallel);
    } else {
        for (auto it = first; it != last; ++it) detail::require_finite_object(*it, site("insert(first, last)"));
        const auto m = static_cast<std::size_t>(last - first);
        if (m == 0) return;
        slots_.require_room_for(m, site("insert(first, last)"));
        ensure_fresh();
        slots_.reserve(slots_.capacity() + m);
        if (slots_.size() == 0 || m * 4 >= slots_.size()) {
            for (auto it = first; it != last; ++it) slots_.allocate(*it, 0);
            if (parallel) rebuild(par);
            else rebuild();
            return;
        }
        for (auto it = first; it != last; ++it) place(slots_.allocate(*it, 0), root);
        updates_since_build_ += m;
        if (needs_rebuild()) rebuild();
    }
}

// ---- erasure ---------------------------------------------------------------------
template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::erase(const_iterator pos) -> iterator {
    ensure_fresh();
    const slot_index s = pos.slot();
    remove_from_leaf(s);
    slots_.release(s);
    ++updates_since_build_;
    if (needs_rebuild()) rebuild();
    return make(slots_.next_occupied(s + 1));
}

template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::erase(const O& x) -> size_type {
    detail::require_finite_object(x, site("erase"));
    ensure_fresh();
    const std::vector<slot_index> hits = collect_equal(x, false);
    for (slot_index s : hits) {
        remove_from_leaf(s);
        slots_.release(s);
    }
    updates_since_build_ += hits.size();
    if (!hits.empty() && needs_rebuild()) rebuild();
    return hits.size();
}

template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::erase_slots(std::span<const slot_index> doomed) {
    ensure_fresh();
    for (slot_index s : doomed) {
        remove_from_leaf(s);
        slots_.release(s);
    }
    updates_since_build_ += doomed.size();
    if (needs_rebuild()) rebuild();
}

// ---- motion ------------------------------------------------------------------------
template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::update(const_iterator pos, const O& v, bool refit_path) -> iterator {
    detail::require_finite_object(v, site("update"));
    if (pos == end() || !slots_.occupied(pos.slot()))
        throw std::invalid_argument(detail::site_text(site("update")) + ": the iterator does not refer to a stored element");
    const slot_index s = pos.slot();
    const node_index leaf = slots_.meta(s);
    slots_.release(s);
    const slot_index s2 = slots_.allocate(v, leaf);  // the free list is LIFO: s2 == s
    if (s2 != s) replace_in_leaf(leaf, s, s2);
    if (refit_path) refit_upward(leaf);
    else stale_ = true;
    return make(s2);
}

template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::reinsert(const_iterator pos, const O& v) -> iterator {
    detail::require_finite_object(v, site("reinsert"));
    if (pos == end() || !slots_.occupied(pos.slot()))
        throw std::invalid_argument(detail::site_text(site("reinsert")) + ": the iterator does not refer to a stored element");
    ensure_fresh();
    const slot_index s = pos.slot();
    remove_from_leaf(s);
    slots_.release(s);
    const slot_index s2 = slots_.allocate(v, 0);  // LIFO free list: s2 == s
    place(s2, root);
    return make(s2);
}

template <stored_object O, class BV, class Config>
template <class PairIt>
inline motion_strategy bvh<O, BV, Config>::update(PairIt first, PairIt last, motion_strategy strategy) {
    std::size_t m = 0;
    for (auto it = first; it != last; ++it, ++m) {
        detail::require_finite_object(it->second, site("update(first, last)"));
        if (it->first == end() || !slots_.occupied(it->first.slot()))
            throw std::invalid_argument(detail::site_text(site("update(first, last)")) + ": an iterator does not refer to a stored element");
    }
    if (m == 0) return strategy == motion_strategy::automatic ? motion_strategy::refit : strategy;
    const bool automatic = strategy == motion_strategy::automatic;
    if (automatic)
        strategy = static_cast<double>(m) <= Config::reinsert_fraction * static_cast<double>(slots_.size())
                       ? motion_strategy::reinsert
                       : motion_strategy::refit;
    if (strategy == motion_strategy::reinsert) {
        for (auto it = first; it != last; ++it) reinsert(it->first, it->second);
        return strategy;
    }
    for (auto it = first; it != last; ++it) update(it->first, it->second, false);
    if (strategy == motion_strategy::rebuild) {
        rebuild();
        return strategy;
    }
    refit();
    if (automatic && quality() > Config::refit_quality_limit * quality_at_build_) {
        rebuild();
        return motion_strategy::rebuild;
    }
    return motion_strategy::refit;
}

template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::refit() {
    std::vector<node_index> order;
    preorder(order);
    for (auto i = order.size(); i-- > 0;) refit_node(order[i]);
    stale_ = false;
}

// ================= refitting ===========================================================
// Leaf: box = union of the objects' bounds, volume = fit to their hull points (for the
// aabb volume: the box itself). Inner: box = union, volume = BV::merged of the children.
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::refit_node(node_index n) {
    // Every change of the tree (build, insert, erase, update, refit) passes here.
    if constexpr (wide_rays) wide_.reset();
    node& nd = nodes_[n];
    if (nd.leaf) {
        box_type b = box_type::empty();
        for (std::uint32_t i = 0; i < nd.count; ++i) {
            const O& v = slots_.value(block(nd.first)[i]);
            for (std::size_t k = 0; k < D; ++k)
                b.lo[k] = std::min(b.lo[k], object_lower(v, k)), b.hi[k] = std::max(b.hi[k], object_upper(v, k));
        }
        if constexpr (volume_is_box) {
            nd.volume = b;
        } else {
            nd.own_box = b;
            scratch_.clear();
            for (std::uint32_t i = 0; i < nd.count; ++i) add_hull_points(slots_.value(block(nd.first)[i]));
            nodes_[n].volume = bvh_detail::fit_volume<BV>(scratch_);
        }
        return;
    }
    const node& l = nodes_[nd.first];
    const node& r = nodes_[nd.first + 1];
    BV merged = l.volume.merged(r.volume);
    box_type b = box_of(l).merged(box_of(r));
    node& m = nodes_[n];
    m.volume = std::move(merged);
    if constexpr (!volume_is_box) m.own_box = b;
}
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::refit_upward(node_index n) {
    for (; n != no_node; n = nodes_[n].parent) refit_node(n);
}

// ================= dynamic insertion and removal =======================================
template <stored_object O, class BV, class Config>
inline bool bvh<O, BV, Config>::needs_rebuild() const {
    const double base = static_cast<double>(std::max(size_at_build_, Config::min_rebuild_updates));
    return static_cast<double>(updates_since_build_) > Config::rebuild_factor * base;
}
template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::insert_from(node_index start, const O& x) -> slot_index {
    const slot_index s = slots_.allocate(x, 0);
    ++updates_since_build_;
    if (needs_rebuild()) {
        rebuild();
        return s;
    }
    place(s, start);
    return s;
}
// Goldsmith & Salmon (1987) greedy descent: into the child whose AABB surface area grows
// least (ties: the smaller resulting area), then into that leaf, splitting it with the
// builder when full; the path to the root is refitted.
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::place(slot_index s, node_index n) {
    const item it = item_of(slots_.value(s), s);
    while (!nodes_[n].leaf) {
        const node_index c = nodes_[n].first;
        double grow[2], area[2];
        for (int k = 0; k < 2; ++k) {
            bvh_detail::box_accumulator<T, D> acc;
            const box_type& b = box_of(nodes_[c + static_cast<node_index>(k)]);
            acc.add(b.lo.coords, b.hi.coords);
            const double before = acc.area();
            acc.add(it.lo, it.hi);
            area[k] = acc.area();
            grow[k] = area[k] - before;
        }
        n = (grow[1] < grow[0] || (grow[1] == grow[0] && area[1] < area[0])) ? c + 1 : c;
    }
    node& L = nodes_[n];
    if (L.count < leaf_size) {
        block(L.first)[L.count++] = s;
        slots_.set_meta(s, n);
        refit_upward(n);
        return;
    }
    std::vector<item> its;
    its.reserve(leaf_size + 1);
    for (std::uint32_t i = 0; i < L.count; ++i) {
        const slot_index t = block(L.first)[i];
        its.push_back(item_of(slots_.value(t), t));
    }
    its.push_back(it);
    free_blocks_.push_back(L.first);
    L.count = 0;
    build_subtree(n, its.data(), its.size());
    refit_upward(nodes_[n].parent);
}
// Removes slot s from its leaf (swap with the last entry); an emptied non-root leaf is
// removed and its sibling replaces the parent. Refits the path. Does not release s.
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::remove_from_leaf(slot_index s) {
    const node_index n = slots_.meta(s);
    node& L = nodes_[n];
    slot_index* b = block(L.first);
    std::uint32_t i = 0;
    while (i < L.count && b[i] != s) ++i;
    if (i == L.count) return;  // not found: cannot happen for a stored slot
    b[i] = b[--L.count];
    if (L.count > 0 || n == root) {
        refit_upward(n);
        return;
    }
    const node_index p = L.parent;
    const node_index pair = nodes_[p].first;
    const node_index sib = n == pair ? pair + 1 : pair;
    free_blocks_.push_back(L.first);
    const node_index grand = nodes_[p].parent;
    nodes_[p] = nodes_[sib];
    nodes_[p].parent = grand;
    if (nodes_[p].leaf) {
        for (std::uint32_t k = 0; k < nodes_[p].count; ++k) slots_.set_meta(block(nodes_[p].first)[k], p);
    } else {
        nodes_[nodes_[p].first].parent = p;
        nodes_[nodes_[p].first + 1].parent = p;
    }
    nodes_[pair] = node{};
    nodes_[pair + 1] = node{};
    free_pairs_.push_back(pair);
    refit_upward(grand);
}
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::replace_in_leaf(node_index leaf, slot_index from, slot_index to) {
    slot_index* b = block(nodes_[leaf].first);
    for (std::uint32_t i = 0; i < nodes_[leaf].count; ++i)
        if (b[i] == from) b[i] = to;
}

}  // namespace spatial
