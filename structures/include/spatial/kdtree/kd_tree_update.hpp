#pragma once
// spatial::kd_tree — changing the tree in place: descending to a leaf, inserting into it (a
// full leaf is rebuilt as a small subtree), distributing a bulk batch down the tree, removing
// slots from their leaves, merging a leaf emptied by erasure with its sibling, and the rules
// that trigger a full rebuild after erasures.

#include <new>
#include <utility>

#include "spatial/core/reserve_for_push.hpp"
#include "spatial/kdtree/kd_tree.hpp"

namespace spatial {

template <stored_object O, class Config>
template <class InputIt>
inline void kd_tree<O, Config>::insert(InputIt first, InputIt last) {
    if constexpr (!std::random_access_iterator<InputIt>) {
        // Single-pass or list-like input: copy once so it can be validated first.
        const std::vector<O> batch(first, last);
        insert(batch.begin(), batch.end());
    } else {
        for (auto it = first; it != last; ++it) detail::require_finite_object(*it, site("insert(first, last)"));
        const auto m = static_cast<std::size_t>(last - first);
        if (m == 0) return;
        slots_.require_room_for(m, site("insert(first, last)"));
        if (slots_.size() == 0) {
            build_fresh(first, m);
            return;
        }
        const std::size_t old_size = slots_.size();
        slots_.reserve(slots_.capacity() + m);  // no reallocation failure half-way
        std::vector<entry> fresh;
        fresh.reserve(m);
        // Strong guarantee: if a leaf rebuild or the full rebuild cannot allocate (each undoes
        // itself), the batch's slots are taken out of the leaves they reached and given back,
        // latest first. Leaf rebuilds that succeeded stay (the tree is valid with them).
        std::vector<std::pair<slot_index, bool>> stored;  // allocation order, whether reused
        stored.reserve(m);
        const coords old_lo = bounds_lo_, old_hi = bounds_hi_;
        try {
            for (auto it = first; it != last; ++it) {
                const bool reused = slots_.reuses_a_slot();
                stored.emplace_back(slots_.allocate(*it, unplaced), reused);
                fresh.push_back(make_entry(*it, stored.back().first));
                grow_bounds(fresh.back().c);
            }
            if (m * 2 >= old_size) {
                rebuild_all();
                return;
            }
            std::uint16_t max_depth = 0;
            subtree_backup leaf_backup;
            distribute(root, fresh.data(), fresh.size(), max_depth, leaf_backup);
            if (max_depth > depth_limit() || needs_full_rebuild()) rebuild_all();
        } catch (const std::bad_alloc&) {
            for (auto it = stored.rbegin(); it != stored.rend(); ++it) {
                if (slots_.meta(it->first) != unplaced) take_out_of_leaf(it->first);
                slots_.undo_allocate(it->first, it->second);
            }
            bounds_lo_ = old_lo, bounds_hi_ = old_hi;
            throw;
        }
    }
}

template <stored_object O, class Config>
template <class InputIt>
inline void kd_tree<O, Config>::insert(InputIt first, InputIt last, parallel_policy) {
    if constexpr (!std::random_access_iterator<InputIt>) {
        const std::vector<O> batch(first, last);
        insert(batch.begin(), batch.end(), par);
    } else {
        const auto m = static_cast<std::size_t>(last - first);
        if (slots_.size() != 0 || m < 2 * parallel_grain) {
            insert(first, last);
            return;
        }
        for (auto it = first; it != last; ++it) detail::require_finite_object(*it, site("insert(first, last, par)"));
        slots_.require_room_for(m, site("insert(first, last, par)"));
        build_fresh(first, m, true);
    }
}

// Removes slot s from its leaf's bucket only (no merge, no release): the undo of a placement.
template <stored_object O, class Config>
inline void kd_tree<O, Config>::take_out_of_leaf(slot_index s) noexcept {
    const node_index b = slots_.meta(s);
    remove_from_leaf(nodes_[buckets_[b].owner], buckets_[b], s);
}

template <stored_object O, class Config>
inline void kd_tree<O, Config>::erase_slots(std::span<const slot_index> doomed) {
    std::vector<node_index> touched;
    touched.reserve(doomed.size());  // all allocation before the first release
    std::vector<char> marked(buckets_.size(), 0);  // O(buckets) bytes, cheaper than sorting
    for (slot_index s : doomed) {
        const node_index b = slots_.meta(s);
        if (!marked[b]) {
            marked[b] = 1;
            touched.push_back(b);
        }
        slots_.release(s);
    }
    for (node_index b : touched) {
        node& L = nodes_[buckets_[b].owner];
        auto& items = buckets_[b].items;
        std::uint32_t kept = 0;
        for (std::uint32_t i = 0; i < L.leaf.count; ++i)
            if (slots_.occupied(items[i])) items[kept++] = items[i];
        L.leaf.count = kept;
        L.leaf.run = run_of(items.data(), kept);
        if constexpr (has_extent) refit_leaf(buckets_[b].owner);
    }
    for (node_index b : touched) {  // merging may free buckets later in the list
        const node_index leaf = buckets_[b].owner;
        if (leaf == no_node || !nodes_[leaf].is_leaf || nodes_[leaf].first != b) continue;
        if (nodes_[leaf].leaf.count == 0 && leaf != root) try_merge_empty_leaf(leaf);
    }
    after_erase();
}

// ================= insertion ===========================================================
template <stored_object O, class Config>
inline auto kd_tree<O, Config>::descend(node_index n, const coords& c) const -> node_index {
    while (!nodes_[n].is_leaf) {
        if constexpr (Config::collect_stats) ++query_stats_.nodes_visited;
        const node& nd = nodes_[n];
        n = c[nd.dim] <= nd.split ? nd.first : nd.first + 1;
    }
    return n;
}

template <stored_object O, class Config>
inline auto kd_tree<O, Config>::insert_at(node_index leaf, const O& x, const coords& c) -> slot_index {
    // Strong guarantee. A leaf with room: the slot is the only allocation. A full leaf: its
    // records are copied aside first (O(leaf_capacity)), and if the split or the rebalancing
    // after it cannot allocate, the leaf is put back and the slot given back.
    const bool full = nodes_[leaf].leaf.count >= leaf_capacity;
    subtree_backup backup;
    if (full) backup = backup_subtree(leaf, leaf_capacity + 1);
    const bool reused = slots_.reuses_a_slot();
    const slot_index s = slots_.allocate(x, nodes_[leaf].first);
    grow_bounds(c);
    if constexpr (has_extent) grow_extents_upward(leaf, extent_of(x));  // looser is still sound
    widen_child_ranges(leaf, c);  // looser is still sound, so an undo below need not narrow
    node& L = nodes_[leaf];
    if (!full) {
        append_to_leaf(L, buckets_[L.first], s);
        return s;
    }
    try {
        // Full leaf: rebuild it as a small subtree over its points plus the new one. Its
        // cell is in its bucket (no walk from the root, which would cost a descent).
        const coords lo = buckets_[L.first].cell_lo, hi = buckets_[L.first].cell_hi;
        entry_buffer_.clear();
        gather(leaf, entry_buffer_);
        if constexpr (has_extent) entry_buffer_.push_back(make_entry(x, s));
        else entry_buffer_.push_back({c, s});
        ++maintenance_.subtree_rebuilds;
        const std::uint16_t deepest =
            build_node(leaf, entry_buffer_.data(), entry_buffer_.size(), lo, hi, nodes_[leaf].depth, false, 0).deepest;
        if (deepest > depth_limit()) rebalance_from(leaf);
    } catch (const std::bad_alloc&) {
        restore(backup);
        slots_.undo_allocate(s, reused);
        throw;
    }
    return s;
}

// Every ancestor of n widens the range of its child on n's path to hold key c: O(depth).
template <stored_object O, class Config>
inline void kd_tree<O, Config>::widen_child_ranges(node_index n, const coords& c) noexcept {
    while (n != root) {
        const node_index p = links_[n].parent;
        node& pn = nodes_[p];
        const bool left = n == pn.first;
        widen_range(left ? pn.ranges.left_lo : pn.ranges.right_lo, left ? pn.ranges.left_hi : pn.ranges.right_hi,
                    c[pn.dim]);
        n = p;
    }
}

// Batch distribution for bulk insert: partition [e, e+n) by each split on the way down.
template <stored_object O, class Config>
inline void kd_tree<O, Config>::distribute(node_index n, entry* e, std::size_t count, std::uint16_t& max_depth,
                                           subtree_backup& leaf_backup) {
    if (count == 0) return;
    if constexpr (has_extent) {
        // Every node on the batch's paths grows by the objects passing through it; a leaf
        // rebuilt below recomputes its own extent exactly.
        for (std::size_t i = 0; i < count; ++i) extents_[n].grow(e[i].bounds);
    }
    if (nodes_[n].is_leaf) {
        node& L = nodes_[n];
        if (L.leaf.count + count <= leaf_capacity) {
            bucket& b = buckets_[L.first];
            for (std::size_t i = 0; i < count; ++i) {
                append_to_leaf(L, b, e[i].slot);
                slots_.set_meta(e[i].slot, L.first);
            }
            max_depth = std::max(max_depth, L.depth);
            return;
        }
        const coords lo = buckets_[L.first].cell_lo, hi = buckets_[L.first].cell_hi;
        // The split's entries go to the buffer the single insertion's splits use too (no
        // allocation per leaf once it has grown).
        std::vector<entry>& es = entry_buffer_;
        es.clear();
        es.reserve(L.leaf.count + count);
        // All or nothing (the caller takes the batch out again): the leaf is put back, and
        // the batch's entries here are marked as not placed.
        backup_subtree(n, L.leaf.count + count, leaf_backup);
        try {
            gather(n, es);
            es.insert(es.end(), e, e + count);
            ++maintenance_.subtree_rebuilds;
            const built_subtree built = build_node(n, es.data(), es.size(), lo, hi, nodes_[n].depth, false, 0);
            max_depth = std::max(max_depth, built.deepest);
        } catch (const std::bad_alloc&) {
            restore(leaf_backup);
            for (std::size_t i = 0; i < count; ++i) slots_.set_meta(e[i].slot, unplaced);
            throw;
        }
        return;
    }
    const unsigned d = nodes_[n].dim;
    const T s = nodes_[n].split;
    entry* mid = std::partition(e, e + count, [d, s](const entry& a) { return a.c[d] <= s; });
    const node_index first = nodes_[n].first;
    const std::size_t left = static_cast<std::size_t>(mid - e);
    // The children's ranges widen before they are rebuilt (looser is still sound if one fails).
    child_ranges& r = nodes_[n].ranges;
    for (const entry* a = e; a != mid; ++a) widen_range(r.left_lo, r.left_hi, a->c[d]);
    for (const entry* a = mid; a != e + count; ++a) widen_range(r.right_lo, r.right_hi, a->c[d]);
    distribute(first, e, left, max_depth, leaf_backup);
    distribute(first + 1, mid, count - left, max_depth, leaf_backup);
}

// ================= erasure =============================================================
template <stored_object O, class Config>
inline void kd_tree<O, Config>::remove_slot(slot_index s, bool allow_merge) {
    const node_index b = slots_.meta(s);
    const node_index leaf = buckets_[b].owner;
    node& L = nodes_[leaf];
    remove_from_leaf(L, buckets_[b], s);
    slots_.release(s);
    if constexpr (has_extent) refit_leaf(leaf);
    if (allow_merge && L.leaf.count == 0 && leaf != root) try_merge_empty_leaf(leaf);
}

// Merging is best-effort: without room on the free lists the empty leaf stays (a valid tree),
// so that erasure never fails for it.
template <stored_object O, class Config>
inline void kd_tree<O, Config>::try_merge_empty_leaf(node_index leaf) noexcept {
    try {
        merge_empty_leaf(leaf);
    } catch (const std::bad_alloc&) {
    }
}

// An empty leaf whose sibling is a leaf: the parent becomes a leaf holding the sibling's
// bucket, whose cell widens to the parent's cell (the union of the two children's cells).
template <stored_object O, class Config>
inline void kd_tree<O, Config>::merge_empty_leaf(node_index leaf) {
    const node_index p = links_[leaf].parent;
    const node_index first = nodes_[p].first;
    const node_index sib = leaf == first ? first + 1 : first;
    if (!nodes_[sib].is_leaf) return;
    // Room on the free lists first (as their push_backs below would grow them), so that the
    // merge cannot fail half-way.
    detail::reserve_for_push(free_buckets_, 1);
    detail::reserve_for_push(free_pairs_, 1);
    const unsigned d = nodes_[p].dim;
    const node_index eb = nodes_[leaf].first, sb = nodes_[sib].first;
    bucket& keep = buckets_[sb];
    keep.cell_lo[d] = std::min(keep.cell_lo[d], buckets_[eb].cell_lo[d]);
    keep.cell_hi[d] = std::max(keep.cell_hi[d], buckets_[eb].cell_hi[d]);
    keep.owner = p;
    node& P_ = nodes_[p];
    P_.is_leaf = 1;
    P_.first = sb;
    P_.leaf = nodes_[sib].leaf;
    if constexpr (has_extent) extents_[p] = extents_[sib];  // the empty leaf held nothing
    buckets_[eb].owner = no_node;
    free_buckets_.push_back(eb);
    free_pairs_.push_back(first);
    --leaves_;
}

template <stored_object O, class Config>
inline void kd_tree<O, Config>::after_erase() {
    // Best-effort: without memory for the rebuild (which then undoes itself) the erase still
    // succeeds, and the tree, valid but less balanced, is rebuilt by a later erase.
    if (!needs_full_rebuild()) return;
    try {
        rebuild_all();
    } catch (const std::bad_alloc&) {
    }
}

// Galperin & Rivest's deletion rule, plus a leaf-occupancy rule that bounds the garbage
// left by splits and erasures under long churn.
template <stored_object O, class Config>
inline bool kd_tree<O, Config>::needs_full_rebuild() const {
    const std::size_t n = slots_.size();
    if (n == 0) return leaves_ > 1;
    if (static_cast<double>(n) < Config::balance_alpha * static_cast<double>(size_at_rebuild_) &&
        size_at_rebuild_ > 4 * leaf_capacity)
        return true;
    return leaves_ > 16 && leaves_ * leaf_capacity > 4 * n + 4 * leaf_capacity;
}
}  // namespace spatial
