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

#include <algorithm>
#include <new>
#include <utility>

#include "spatial/core/morton_order.hpp"
#include "spatial/core/reserve_for_push.hpp"
#include "spatial/bvh/bvh.hpp"

namespace spatial {

// ---- insertion -------------------------------------------------------------------
template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::insert(const_iterator hint, const O& x) -> iterator {
    detail::require_finite_object(x, site("insert(hint, x)"));
    ensure_fresh();
    ensure_root();
    if (hint == end() || !slots_.occupied(hint.slot())) return make(insert_from(root, x));
    return make(insert_from(lowest_holder(slots_.meta(hint.slot()), item_of(x, 0)), x));
}

template <stored_object O, class BV, class Config>
template <class InputIt>
inline void bvh<O, BV, Config>::bulk_insert(InputIt first, InputIt last, bool parallel) {
    if constexpr (!std::random_access_iterator<InputIt>) {
        const std::vector<O> batch(first, last);
        bulk_insert(batch.begin(), batch.end(), parallel);
    } else {
        const auto m = static_cast<std::size_t>(last - first);
        if (m == 0) return;
        slots_.require_room_for(m, site("insert(first, last)"));
        const bool builds_anew = slots_.size() == 0 || m * 4 >= slots_.size();
        if (builds_anew && !slots_.reuses_a_slot()) {
            // Every object takes a new slot: each is checked and stored in one pass over the
            // batch (on every core for par), then the whole tree is built. Strong guarantee: a
            // rejected object stores nothing, and a build that cannot allocate puts the old
            // tree back (rebuild) and the new slots are taken out.
            const std::size_t before = slots_.capacity();
            const std::size_t bad =
                slots_.append(first, m, 0, parallel, [](const O& x) { return detail::is_finite_object(x); });
            if (bad != m) detail::require_finite_object(first[static_cast<std::ptrdiff_t>(bad)], site("insert(first, last)"));
            try {
                if (parallel) rebuild(par);
                else rebuild();
            } catch (const std::bad_alloc&) {
                slots_.truncate(before);
                throw;
            }
            // Only a layout that tests leaves in place needs leaf order; every other bvh keeps
            // insertion order, so slot i of a bulk-built tree is the i-th object of the batch.
            if constexpr (ray_leaves == bvh_ray_leaves::in_place)
                if (before == 0) store_in_leaf_order(parallel);
            return;
        }
        for (auto it = first; it != last; ++it) detail::require_finite_object(*it, site("insert(first, last)"));
        ensure_fresh();
        slots_.reserve(slots_.capacity() + m);
        // Strong guarantee: a rebuild or a placement that cannot allocate undoes itself, and
        // the objects already stored are taken out again, latest first (their removals cannot
        // fail: reserve_removals).
        std::vector<std::pair<slot_index, bool>> stored;  // allocation order, whether reused
        stored.reserve(m);
        auto allocate = [&](const O& x) {
            const bool reused = slots_.reuses_a_slot();
            stored.emplace_back(slots_.allocate(x, 0), reused);
            return stored.back().first;
        };
        if (builds_anew) {  // some objects reuse free slots
            try {
                for (auto it = first; it != last; ++it) allocate(*it);
                if (parallel) rebuild(par);
                else rebuild();
            } catch (const std::bad_alloc&) {
                for (auto it = stored.rbegin(); it != stored.rend(); ++it) slots_.undo_allocate(it->first, it->second);
                throw;
            }
            return;
        }
        reserve_removals(m);
        // Placed in Morton order of their centres: consecutive objects are close, so each
        // descent starts where the previous object landed, at the deepest node on its leaf's
        // path to the root whose box contains the new object (as a hinted insert does), instead
        // of at the root. The greedy descent from the root would pass through that node too
        // unless a box on the way overlaps it, so the trees are those of placements from the
        // root in this order, less the upper levels' area comparisons: the climb and the
        // rest of the descent touch nodes still in cache.
        std::vector<point<T, D>> centres(m);
        for (std::size_t i = 0; i < m; ++i)
            for (std::size_t d = 0; d < D; ++d) centres[i][d] = object_center(first[static_cast<std::ptrdiff_t>(i)], d);
        const std::vector<std::uint32_t> order = morton_order(std::span<const point<T, D>>(centres));
        const std::size_t before = updates_since_build_;
        try {
            node_index from = root;
            for (std::uint32_t i : order) {
                const slot_index s = allocate(first[static_cast<std::ptrdiff_t>(i)]);
                place(s, lowest_holder(from, item_of(slots_.value(s), s)));
                from = slots_.meta(s);
            }
        } catch (const std::bad_alloc&) {
            // The failed placement undid itself (its slot is not in the tree).
            slots_.undo_allocate(stored.back().first, stored.back().second);
            stored.pop_back();
            for (auto it = stored.rbegin(); it != stored.rend(); ++it) {
                remove_from_leaf(it->first);
                slots_.undo_allocate(it->first, it->second);
            }
            updates_since_build_ = before;
            throw;
        }
        updates_since_build_ += m;
        if (needs_rebuild()) rebuild_if_possible();
    }
}

// Room on the free lists for m removals of emptied leaves, so that they cannot fail.
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::reserve_removals(std::size_t m) {
    detail::reserve_for_push(free_blocks_, m);
    detail::reserve_for_push(free_pairs_, m);
}

// ---- erasure ---------------------------------------------------------------------
template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::erase(const_iterator pos) -> iterator {
    ensure_fresh();
    const slot_index s = pos.slot();
    // Cannot fail past here: room is reserved first; refits and the rebuild are best-effort.
    slots_.reserve_releases(1);
    reserve_removals(1);
    remove_from_leaf(s);
    slots_.release(s);
    ++updates_since_build_;
    if (needs_rebuild()) rebuild_if_possible();
    return make(slots_.next_occupied(s + 1));
}

template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::erase(const O& x) -> size_type {
    detail::require_finite_object(x, site("erase"));
    ensure_fresh();
    const std::vector<slot_index> hits = collect_equal(x, false);
    slots_.reserve_releases(hits.size());
    reserve_removals(hits.size());
    for (slot_index s : hits) {
        remove_from_leaf(s);
        slots_.release(s);
    }
    updates_since_build_ += hits.size();
    if (!hits.empty() && needs_rebuild()) rebuild_if_possible();
    return hits.size();
}

template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::erase_slots(std::span<const slot_index> doomed) {
    ensure_fresh();
    reserve_removals(doomed.size());  // the free-list room for releases is container_base's
    for (slot_index s : doomed) {
        remove_from_leaf(s);
        slots_.release(s);
    }
    updates_since_build_ += doomed.size();
    if (needs_rebuild()) rebuild_if_possible();
}

// ---- motion ------------------------------------------------------------------------
template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::update(const_iterator pos, const O& v, bool refit_path) -> iterator {
    detail::require_finite_object(v, site("update"));
    if (pos == end() || !slots_.occupied(pos.slot()))
        throw std::invalid_argument(detail::site_text(site("update")) + ": the iterator does not refer to a stored element");
    const slot_index s = pos.slot();
    const node_index leaf = slots_.meta(s);
    // Strong guarantee: the value is replaced in its slot (no allocation), and put back if the
    // path's volumes cannot be refitted (which then keep their old values).
    const O old = slots_.value(s);
    slots_.replace(s, v);
    if (!refit_path) {
        stale_ = true;
        return make(s);
    }
    try {
        refit_upward_or_undo(leaf);
    } catch (const std::bad_alloc&) {
        slots_.replace(s, old);
        throw;
    }
    return make(s);
}

template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::reinsert(const_iterator pos, const O& v) -> iterator {
    detail::require_finite_object(v, site("reinsert"));
    if (pos == end() || !slots_.occupied(pos.slot()))
        throw std::invalid_argument(detail::site_text(site("reinsert")) + ": the iterator does not refer to a stored element");
    ensure_fresh();
    const slot_index s = pos.slot();
    // The object leaves its old leaf first (the path refitted, an emptied leaf removed), so
    // that its new place is chosen against the volumes as they are without it. (Placing it
    // while still counted in its old leaf's stale volumes, as a version of 2026-11-26 did for
    // the strong guarantee, made trees of moving boxes ~8% worse in SAH cost.)
    // Guarantee: a placement that cannot allocate undoes itself; the old value is then placed
    // back (strong: same contents, the iterator stays valid). Only if that placement fails too
    // is the element erased (basic), which docs/contract.md states.
    const O old = slots_.value(s);
    reserve_removals(1);
    slots_.reserve_releases(1);
    remove_from_leaf(s);
    slots_.replace(s, v);
    try {
        place(s, root);
    } catch (const std::bad_alloc&) {
        slots_.replace(s, old);
        try {
            place(s, root);
        } catch (const std::bad_alloc&) {
            slots_.release(s);
        }
        throw;
    }
    return make(s);
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
        // Basic guarantee: each reinsert is all or nothing, so a failure leaves the objects
        // before it moved and the others where they were, each stored once.
        for (auto it = first; it != last; ++it) reinsert(it->first, it->second);
        return strategy;
    }
    // Strong guarantee for refit and rebuild: the old values are kept aside and put back if
    // the refit or rebuild (which undoes itself) cannot allocate.
    std::vector<std::pair<slot_index, O>> old;
    old.reserve(m);
    for (auto it = first; it != last; ++it) old.emplace_back(it->first.slot(), slots_.value(it->first.slot()));
    for (auto it = first; it != last; ++it) slots_.replace(it->first.slot(), it->second);
    try {
        if (strategy == motion_strategy::rebuild) rebuild();
        else refit();
    } catch (const std::bad_alloc&) {
        for (auto it = old.rbegin(); it != old.rend(); ++it) slots_.replace(it->first, it->second);
        throw;
    }
    if (strategy == motion_strategy::rebuild) return strategy;
    if (automatic && quality() > Config::refit_quality_limit * quality_at_build_) {
        // Only quality is at stake: without memory for the rebuild the refitted tree stays.
        try {
            rebuild();
            return motion_strategy::rebuild;
        } catch (const std::bad_alloc&) {
        }
    }
    return motion_strategy::refit;
}

template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::refit() {
    std::vector<node_index> order;
    preorder(order);
    std::reverse(order.begin(), order.end());  // children before parents
    refit_or_undo(order);  // strong guarantee (bvh_backup.hpp)
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
        const box_type b = objects_box(nd);
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
inline auto bvh<O, BV, Config>::objects_box(const node& leaf) const -> box_type {
    box_type b = box_type::empty();
    for (std::uint32_t i = 0; i < leaf.count; ++i) {
        const O& v = slots_.value(block(leaf.first)[i]);
        for (std::size_t k = 0; k < D; ++k)
            b.lo[k] = std::min(b.lo[k], object_lower(v, k)), b.hi[k] = std::max(b.hi[k], object_upper(v, k));
    }
    return b;
}
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::refit_upward(node_index n) {
    // Box volumes stop at the first node whose box comes out unchanged: a box is the exact
    // union of its children's (or its objects'), so the boxes above it, which contain it, are
    // still right. An insertion inside its leaf's box, or near a box it has already grown,
    // then refits a few levels instead of the whole path. Other volumes are not compared (a
    // merge of spheres or hulls depends on more than the child that changed).
    for (; n != no_node; n = nodes_[n].parent) {
        if constexpr (volume_is_box) {
            const box_type before = nodes_[n].volume;
            refit_node(n);
            if (nodes_[n].volume == before) return;
        } else {
            refit_node(n);
        }
    }
}

// ================= dynamic insertion and removal =======================================
template <stored_object O, class BV, class Config>
inline bool bvh<O, BV, Config>::needs_rebuild() const {
    const double base = static_cast<double>(std::max(size_at_build_, Config::min_rebuild_updates));
    return static_cast<double>(updates_since_build_) > Config::rebuild_factor * base;
}
template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::insert_from(node_index start, const O& x) -> slot_index {
    // Strong guarantee: the rebuild and the placement undo themselves; then the slot is given
    // back.
    const bool reused = slots_.reuses_a_slot();
    const slot_index s = slots_.allocate(x, 0);
    ++updates_since_build_;
    try {
        if (needs_rebuild()) rebuild();
        else place(s, start);
    } catch (const std::bad_alloc&) {
        --updates_since_build_;
        slots_.undo_allocate(s, reused);
        throw;
    }
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
            // The child's box area before and after taking the object (no accumulator: this
            // runs twice per level of every insertion, and was most of a bulk insertion's work).
            const box_type& b = box_of(nodes_[c + static_cast<node_index>(k)]);
            std::array<T, D> lo = b.lo.coords, hi = b.hi.coords;
            bvh_detail::extend_box(lo, hi, it.lo, it.hi);
            const double before = bvh_detail::box_area<T, D>(b.lo.coords, b.hi.coords);
            area[k] = bvh_detail::box_area<T, D>(lo, hi);
            grow[k] = area[k] - before;
        }
        n = (grow[1] < grow[0] || (grow[1] == grow[0] && area[1] < area[0])) ? c + 1 : c;
    }
    // All or nothing: a std::bad_alloc leaves the tree as it was (s in no leaf).
    node& L = nodes_[n];
    if (L.count < leaf_size) {
        block(L.first)[L.count++] = s;
        slots_.set_meta(s, n);
        if constexpr (volume_is_box) {
            grow_upward(n, it);
            return;
        }
        try {
            refit_upward_or_undo(n);
        } catch (const std::bad_alloc&) {
            --nodes_[n].count;  // s is the last entry
            throw;
        }
        return;
    }
    std::vector<item> its;
    its.reserve(leaf_size + 1);
    for (std::uint32_t i = 0; i < L.count; ++i) {
        const slot_index t = block(L.first)[i];
        its.push_back(item_of(slots_.value(t), t));
    }
    its.push_back(it);
    leaf_backup backup = backup_leaf(n);
    try {
        free_blocks_.push_back(nodes_[n].first);
        nodes_[n].count = 0;
        build_subtree(n, its.data(), its.size());
        refit_upward_or_undo(nodes_[n].parent);
    } catch (const std::bad_alloc&) {
        restore(backup);
        throw;
    }
}
// The first node on n's path to the root whose box holds `it` (the root if none does): where
// a placement near n starts (hinted and batched insertion).
template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::lowest_holder(node_index n, const item& it) const -> node_index {
    while (n != root && !box_contains(box_of(nodes_[n]), it)) n = nodes_[n].parent;
    return n;
}
// The path's boxes after object `it` joined leaf n: each box is the exact union of its
// children's (or its objects'), so it becomes itself extended by the object, up to the first box
// that already holds it. The same boxes as refit_upward(n) (the leaf's union is taken in the
// same order, the new object last), without reading the leaf's other objects or the siblings,
// which a batch of placements in Morton order spent most of its time waiting for.
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::grow_upward(node_index n, const item& it) noexcept {
    static_assert(volume_is_box);
    if constexpr (wide_rays) wide_.reset();  // the wide layout copies the leaves' objects
    for (; n != no_node && !box_contains(nodes_[n].volume, it); n = nodes_[n].parent)
        bvh_detail::extend_box(nodes_[n].volume.lo.coords, nodes_[n].volume.hi.coords, it.lo, it.hi);
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
        refit_upward_if_possible(n);
        return;
    }
    remove_empty_leaf(n);
}
// An emptied non-root leaf is removed and its sibling takes its parent's place. Cannot fail:
// the callers reserved the free-list room (reserve_removals), the refit is best-effort.
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::remove_empty_leaf(node_index n) noexcept {
    const node& L = nodes_[n];
    const node_index p = L.parent;
    const node_index pair = nodes_[p].first;
    const node_index sib = n == pair ? pair + 1 : pair;
    free_blocks_.push_back(L.first);
    const node_index grand = nodes_[p].parent;
    nodes_[p] = std::move(nodes_[sib]);  // sib is reset below
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
    refit_upward_if_possible(grand);
}
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::replace_in_leaf(node_index leaf, slot_index from, slot_index to) {
    slot_index* b = block(nodes_[leaf].first);
    for (std::uint32_t i = 0; i < nodes_[leaf].count; ++i)
        if (b[i] == from) b[i] = to;
}

}  // namespace spatial
