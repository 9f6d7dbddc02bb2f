#pragma once
// spatial::kd_tree — undoing a change that ran out of memory half-way (the strong guarantee of
// docs/contract.md, "Exception safety"). Before a subtree is rebuilt (a leaf split, a scapegoat
// rebuild), the records it may overwrite are copied aside: every node, node link, extent and bucket of
// the subtree, the free lists' tails and the counters, O(subtree). New nodes and buckets
// only ever grow the arrays at their ends, so truncating them and writing the copies back
// restores the tree exactly, with the slots' bucket words. A full rebuild instead moves the
// whole tree aside (backup_all).

#include <utility>
#include <vector>

#include "spatial/core/free_list.hpp"
#include "spatial/kdtree/kd_tree.hpp"

namespace spatial {

template <stored_object O, class Config>
struct kd_tree<O, Config>::subtree_backup {
    std::vector<std::pair<node_index, node>> nodes;
    std::vector<std::pair<node_index, node_link>> links;
    std::vector<std::pair<node_index, extent>> extents;  // objects only
    std::vector<std::pair<node_index, bucket>> buckets;
    detail::free_list_tail<node_index> free_pairs, free_buckets;
    std::size_t node_count = 0, bucket_count = 0, leaves = 0;
    coords bounds_lo{}, bounds_hi{};
    kd_tree_maintenance_stats maintenance{};
};

// `entries`: how many points the rebuild will place. A build over e points makes at most e
// leaves and e - 1 pairs, so it takes at most e indices from each free list.
template <stored_object O, class Config>
inline auto kd_tree<O, Config>::backup_subtree(node_index n, std::size_t entries) const -> subtree_backup {
    subtree_backup b;
    backup_subtree(n, entries, b);
    return b;
}

// The same into `b`, whose vectors keep their storage: a bulk insertion backs up every leaf it
// splits through one backup, so a split costs no allocation (a leaf's backup is one record of
// each kind).
template <stored_object O, class Config>
inline void kd_tree<O, Config>::backup_subtree(node_index n, std::size_t entries, subtree_backup& b) const {
    b.node_count = nodes_.size();
    b.bucket_count = buckets_.size();
    b.leaves = leaves_;
    b.bounds_lo = bounds_lo_, b.bounds_hi = bounds_hi_;
    b.maintenance = maintenance_;
    b.free_pairs.assign(free_pairs_, entries + 1);
    b.free_buckets.assign(free_buckets_, entries + 1);
    b.nodes.clear();
    b.links.clear();
    b.extents.clear();
    b.buckets.clear();
    // b.nodes is the worklist too: the subtree's nodes in breadth-first order.
    b.nodes.emplace_back(n, nodes_[n]);
    for (std::size_t i = 0; i < b.nodes.size(); ++i) {
        const node_index x = b.nodes[i].first;
        const node_index first = b.nodes[i].second.first;  // copied: emplace_back may move b.nodes
        b.links.emplace_back(x, links_[x]);
        if constexpr (has_extent) b.extents.emplace_back(x, extents_[x]);
        if (b.nodes[i].second.is_leaf) {
            b.buckets.emplace_back(first, buckets_[first]);
        } else {
            b.nodes.emplace_back(first, nodes_[first]);
            b.nodes.emplace_back(first + 1, nodes_[first + 1]);
        }
    }
}

// Cannot fail: the arrays only shrink (to sizes they had) and records are copied into place.
template <stored_object O, class Config>
inline void kd_tree<O, Config>::restore(subtree_backup& b) noexcept {
    nodes_.resize(b.node_count);
    links_.resize(b.node_count);
    if constexpr (has_extent) extents_.resize(b.node_count);
    buckets_.resize(b.bucket_count);
    for (const auto& [i, nd] : b.nodes) nodes_[i] = nd;
    for (const auto& [i, link] : b.links) links_[i] = link;
    if constexpr (has_extent)
        for (const auto& [i, ex] : b.extents) extents_[i] = ex;
    for (const auto& [i, bk] : b.buckets) {
        buckets_[i] = bk;
        const node& leaf = nodes_[bk.owner];
        for (std::uint32_t k = 0; k < leaf.leaf.count; ++k) slots_.set_meta(bk.items[k], i);
    }
    b.free_pairs.restore(free_pairs_);
    b.free_buckets.restore(free_buckets_);
    leaves_ = b.leaves;
    bounds_lo_ = b.bounds_lo, bounds_hi_ = b.bounds_hi;
    maintenance_ = b.maintenance;
}

template <stored_object O, class Config>
struct kd_tree<O, Config>::tree_backup {
    std::vector<node> nodes;
    std::vector<node_link> links;
    std::vector<extent> extents;
    std::vector<bucket> buckets;
    std::vector<node_index> free_pairs, free_buckets;
    std::vector<std::pair<slot_index, node_index>> metas;  // every live slot's bucket
    std::size_t leaves = 0, size_at_rebuild = 0;
    coords bounds_lo{}, bounds_hi{};
    kd_tree_maintenance_stats maintenance{};
};

// Moves the tree aside (the live slots' bucket words are copied: O(n)); the arrays are left
// empty with their old capacities reserved, so a rebuild into them uses as much memory as one
// in place would have.
template <stored_object O, class Config>
inline auto kd_tree<O, Config>::backup_all() -> tree_backup {
    tree_backup b;
    b.metas.reserve(slots_.size());
    for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1))
        b.metas.emplace_back(s, slots_.meta(s));
    std::vector<node> nodes;
    std::vector<node_link> links;
    std::vector<extent> extents;
    std::vector<bucket> buckets;
    std::vector<node_index> free_pairs, free_buckets;
    nodes.reserve(nodes_.capacity());
    links.reserve(links_.capacity());
    if constexpr (has_extent) extents.reserve(extents_.capacity());
    buckets.reserve(buckets_.capacity());
    free_pairs.reserve(free_pairs_.capacity());
    free_buckets.reserve(free_buckets_.capacity());
    // Nothing has changed yet; from here on nothing can fail.
    b.nodes = std::exchange(nodes_, std::move(nodes));
    b.links = std::exchange(links_, std::move(links));
    b.extents = std::exchange(extents_, std::move(extents));
    b.buckets = std::exchange(buckets_, std::move(buckets));
    b.free_pairs = std::exchange(free_pairs_, std::move(free_pairs));
    b.free_buckets = std::exchange(free_buckets_, std::move(free_buckets));
    b.leaves = leaves_, b.size_at_rebuild = size_at_rebuild_;
    b.bounds_lo = bounds_lo_, b.bounds_hi = bounds_hi_;
    b.maintenance = maintenance_;
    return b;
}

template <stored_object O, class Config>
inline void kd_tree<O, Config>::restore(tree_backup& b) noexcept {
    nodes_ = std::move(b.nodes);
    links_ = std::move(b.links);
    extents_ = std::move(b.extents);
    buckets_ = std::move(b.buckets);
    free_pairs_ = std::move(b.free_pairs);
    free_buckets_ = std::move(b.free_buckets);
    for (const auto& [s, m] : b.metas) slots_.set_meta(s, m);
    leaves_ = b.leaves, size_at_rebuild_ = b.size_at_rebuild;
    bounds_lo_ = b.bounds_lo, bounds_hi_ = b.bounds_hi;
    maintenance_ = b.maintenance;
}

}  // namespace spatial
