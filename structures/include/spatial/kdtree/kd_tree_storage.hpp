#pragma once
// spatial::kd_tree — the stored layout and its bookkeeping: coordinates and partitioning keys
// of stored objects, build entries, the node extents of objects with extent (grown on
// insertion, refit on erasure), the tree's key bounds, the allocation of leaf buckets and
// child node pairs (freed ones reused), and resetting or swapping a whole tree.

#include "spatial/kdtree/kd_tree.hpp"

namespace spatial {

// The moves' exchange. The split buffer travels with the tree, so a moved-from tree holds no
// heap memory at all.
template <stored_object O, class Config>
inline void kd_tree<O, Config>::swap_contents(kd_tree& o) noexcept {
    this->swap_with(o, &kd_tree::nodes_, &kd_tree::links_, &kd_tree::extents_, &kd_tree::buckets_,
                    &kd_tree::free_pairs_, &kd_tree::free_buckets_, &kd_tree::leaves_, &kd_tree::bounds_lo_,
                    &kd_tree::bounds_hi_, &kd_tree::size_at_rebuild_, &kd_tree::entry_buffer_);
}

// The partitioning key of a stored value: the point itself, or the centre of an object's
// bounding box (object_center never rounds outside the box).
template <stored_object O, class Config>
inline auto kd_tree<O, Config>::key_of(const O& x) -> coords {
    coords c;
    for (std::size_t i = 0; i < D; ++i) c[i] = object_center(x, i);
    return c;
}

template <stored_object O, class Config>
inline auto kd_tree<O, Config>::extent_of(const O& x) -> extent {
    extent e;
    for (std::size_t i = 0; i < D; ++i) e.lo[i] = object_lower(x, i), e.hi[i] = object_upper(x, i);
    return e;
}

template <stored_object O, class Config>
inline auto kd_tree<O, Config>::make_entry(const O& x, slot_index s) -> entry {
    entry e{key_of(x), s};
    if constexpr (has_extent) e.bounds = extent_of(x);
    return e;
}

// ---- objects: keeping node extents conservative ----
// Insertion grows the extents from the leaf upwards and stops at the first node that
// already contains the object's box: every ancestor's extent contains its descendants',
// so the nodes above contain it too. O(1) when the object fits its leaf's extent (the
// usual case), O(depth) at worst.
template <stored_object O, class Config>
inline void kd_tree<O, Config>::grow_extents_upward(node_index n, const extent& box) {
    while (!extents_[n].contains(box)) {
        extents_[n].grow(box);
        if (n == root) return;
        n = links_[n].parent;
    }
}

// Erasure tightens only the leaf (O(leaf_capacity)); its ancestors keep their extents,
// which stay conservative (they contain everything below, and more) until the subtree
// is rebuilt. Loose extents cost pruning power, never correctness.
template <stored_object O, class Config>
inline void kd_tree<O, Config>::refit_leaf(node_index leaf) {
    const node& L = nodes_[leaf];
    const bucket& b = buckets_[L.first];
    extent ex = extent::empty();
    for (std::uint32_t i = 0; i < L.leaf.count; ++i) ex.grow(extent_of(slots_.value(b.items[i])));
    extents_[leaf] = ex;
}

// ---- leaves: scanning and changing a bucket's slots (see leaf_slots::run) ----
template <stored_object O, class Config>
template <class F>
inline void kd_tree<O, Config>::scan_leaf(const node& nd, F&& f) const {
    const std::uint32_t count = nd.leaf.count;
    if (const slot_index run = nd.leaf.run; run != no_slot) {
        prefetch_run(run, count);
        for (std::uint32_t i = 0; i < count; ++i) f(static_cast<slot_index>(run + i));
        return;
    }
    const bucket& b = buckets_[nd.first];
    for (std::uint32_t i = 0; i < count; ++i) f(b.items[i]);
}

// A run's values are contiguous: ask for all their cache lines at once (12 lines at b = 32
// for 3D double), so the misses overlap instead of waiting for the hardware prefetcher to
// ramp up along the scan. results/checks/leaf_prefetch has the figures.
template <stored_object O, class Config>
inline const O* kd_tree<O, Config>::prefetch_run(slot_index run, std::uint32_t count) const {
    const O* values = &slots_.value(run);
    const char* first = reinterpret_cast<const char*>(values);
    for (std::size_t b = 0; b < count * sizeof(O); b += 64) __builtin_prefetch(first + b);
    return values;
}

template <stored_object O, class Config>
inline slot_index kd_tree<O, Config>::run_of(const slot_index* items, std::uint32_t count) noexcept {
    for (std::uint32_t i = 1; i < count; ++i)
        if (items[i] != items[0] + i) return no_slot;
    return count == 0 ? no_slot : items[0];
}

template <stored_object O, class Config>
inline void kd_tree<O, Config>::append_to_leaf(node& L, bucket& b, slot_index s) noexcept {
    if (L.leaf.run != no_slot && s != L.leaf.run + L.leaf.count) L.leaf.run = no_slot;
    b.items[L.leaf.count++] = s;
}

template <stored_object O, class Config>
inline void kd_tree<O, Config>::remove_from_leaf(node& L, bucket& b, slot_index s) noexcept {
    for (std::uint32_t i = 0; i < L.leaf.count; ++i)
        if (b.items[i] == s) {
            b.items[i] = b.items[--L.leaf.count];
            L.leaf.run = run_of(b.items.data(), L.leaf.count);
            return;
        }
}

template <stored_object O, class Config>
inline bool kd_tree<O, Config>::in_cell(const coords& c, const coords& lo, const coords& hi) {
    for (std::size_t i = 0; i < D; ++i)
        if (c[i] < lo[i] || c[i] > hi[i]) return false;
    return true;
}

template <stored_object O, class Config>
inline void kd_tree<O, Config>::grow_bounds(const coords& c) {
    for (std::size_t i = 0; i < D; ++i) {
        bounds_lo_[i] = std::min(bounds_lo_[i], c[i]);
        bounds_hi_[i] = std::max(bounds_hi_[i], c[i]);
    }
}

// The unallocated empty tree (see has_root): no allocation, so the default constructor, the
// moves and clear() cannot throw. Capacities are kept.
template <stored_object O, class Config>
inline void kd_tree<O, Config>::drop_tree() noexcept {
    nodes_.clear();
    links_.clear();
    extents_.clear();
    buckets_.clear();
    free_pairs_.clear();
    free_buckets_.clear();
    leaves_ = 0;
    bounds_lo_.fill(std::numeric_limits<T>::infinity());
    bounds_hi_.fill(-std::numeric_limits<T>::infinity());
    size_at_rebuild_ = 0;
}

// Gives the unallocated tree its root: one empty leaf whose cell is all of space, as
// reset_to_empty makes it. Strong guarantee: if that cannot allocate, the tree is the
// unallocated one again.
template <stored_object O, class Config>
inline void kd_tree<O, Config>::ensure_root() {
    if (has_root()) return;
    try {
        reset_to_empty();
    } catch (...) {
        drop_tree();
        throw;
    }
}

// The empty tree with its root leaf (allocates: the node, its extent, its bucket).
template <stored_object O, class Config>
inline void kd_tree<O, Config>::reset_to_empty() {
    links_.assign(1, node_link{});
    nodes_.assign(1, node{});
    if constexpr (has_extent) extents_.assign(1, extent::empty());
    buckets_.clear();
    free_pairs_.clear();
    free_buckets_.clear();
    coords lo, hi;
    lo.fill(-std::numeric_limits<T>::infinity());
    hi.fill(std::numeric_limits<T>::infinity());
    nodes_[root].first = new_bucket(root, lo, hi);
    leaves_ = 1;
    bounds_lo_.fill(std::numeric_limits<T>::infinity());
    bounds_hi_.fill(-std::numeric_limits<T>::infinity());
    size_at_rebuild_ = 0;
}

template <stored_object O, class Config>
inline auto kd_tree<O, Config>::new_bucket(node_index owner, const coords& lo, const coords& hi) -> node_index {
    const node_index b = detail::reuse_or_grow(free_buckets_, [this] {
        buckets_.emplace_back();
        return static_cast<node_index>(buckets_.size() - 1);
    });
    buckets_[b].cell_lo = lo;
    buckets_[b].cell_hi = hi;
    buckets_[b].owner = owner;
    return b;
}

template <stored_object O, class Config>
inline auto kd_tree<O, Config>::new_pair() -> node_index {
    return detail::reuse_or_grow(free_pairs_, [this] {
        const node_index p = static_cast<node_index>(nodes_.size());
        links_.resize(nodes_.size() + 2);  // first: if nodes_ cannot grow, the sizes still agree on p
        nodes_.resize(nodes_.size() + 2);
        if constexpr (has_extent) extents_.resize(nodes_.size(), extent::empty());
        return p;
    });
}
}  // namespace spatial
