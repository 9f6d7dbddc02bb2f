#pragma once
// spatial::bvh — undoing a change that ran out of memory half-way (the strong guarantee of
// docs/contract.md, "Exception safety"). Three scopes, each copying aside only what the change
// may overwrite:
//  * refits (after an insertion or a move, of a path; of everything): each node's volume is
//    moved aside just before it is refitted, and moved back if a fit cannot allocate;
//  * a leaf split (an insertion into a full leaf): the leaf, its block and the free lists'
//    tails; the node and block arrays only grow at their ends, so truncating them undoes the
//    rest;
//  * the whole tree (rebuild, refit of everything): the arrays are moved aside, their
//    capacities reserved again for the new tree (the same memory as a rebuild in place), and
//    the live slots' leaf words copied, O(n).
// For BV = aabb a refit computes boxes only and cannot fail, so the path scope costs nothing.

#include <iterator>
#include <new>
#include <utility>
#include <vector>

#include "spatial/bvh/bvh.hpp"
#include "spatial/core/free_list.hpp"

namespace spatial {

// Refits the nodes of `order`, in that order, all or nothing. A node's refit reads its
// objects or its children, never its own volume, so the old one can be moved out first.
template <stored_object O, class BV, class Config>
template <class Nodes>
inline void bvh<O, BV, Config>::refit_or_undo(const Nodes& order) {
    if constexpr (volume_is_box) {
        for (node_index x : order) refit_node(x);  // boxes only: cannot fail
    } else {
        std::vector<std::pair<node_index, node>> saved;  // volume and own box only
        saved.reserve(std::size(order));
        try {
            for (node_index x : order) {
                saved.emplace_back(x, node{});
                saved.back().second.volume = std::move(nodes_[x].volume);
                saved.back().second.own_box = nodes_[x].own_box;
                refit_node(x);
            }
        } catch (const std::bad_alloc&) {
            for (auto it = saved.rbegin(); it != saved.rend(); ++it) {
                nodes_[it->first].volume = std::move(it->second.volume);
                nodes_[it->first].own_box = it->second.own_box;
            }
            if constexpr (wide_rays) wide_.reset();
            throw;
        }
    }
}

template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::refit_upward_or_undo(node_index n) {
    if constexpr (volume_is_box) {
        refit_upward(n);
    } else {
        std::vector<node_index> path;
        for (node_index x = n; x != no_node; x = nodes_[x].parent) path.push_back(x);
        refit_or_undo(path);
    }
}

template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::refit_upward_if_possible(node_index n) noexcept {
    // A volume that is not refitted after a removal still contains everything below it.
    try {
        refit_upward(n);
    } catch (const std::bad_alloc&) {
    }
}

template <stored_object O, class BV, class Config>
struct bvh<O, BV, Config>::leaf_backup {
    node_index at = 0;
    node leaf{};
    std::vector<slot_index> items;
    std::size_t node_count = 0, item_count = 0;
    detail::free_list_tail<node_index> free_pairs, free_blocks;
};

template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::backup_leaf(node_index n) const -> leaf_backup {
    leaf_backup b;
    b.at = n;
    b.leaf = nodes_[n];
    b.items.assign(block(nodes_[n].first), block(nodes_[n].first) + nodes_[n].count);
    b.node_count = nodes_.size();
    b.item_count = items_.size();
    // The split builds over leaf_size + 1 items: at most that many leaves (blocks) and pairs,
    // plus the leaf's own block pushed first.
    b.free_pairs = detail::free_list_tail<node_index>(free_pairs_, leaf_size + 2);
    b.free_blocks = detail::free_list_tail<node_index>(free_blocks_, leaf_size + 2);
    return b;
}

template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::restore(leaf_backup& b) noexcept {
    nodes_.resize(b.node_count);  // only shrinks: no allocation
    items_.resize(b.item_count);
    nodes_[b.at] = std::move(b.leaf);
    slot_index* block_items = block(nodes_[b.at].first);
    for (std::size_t i = 0; i < b.items.size(); ++i) {
        block_items[i] = b.items[i];
        slots_.set_meta(b.items[i], b.at);
    }
    b.free_pairs.restore(free_pairs_);
    b.free_blocks.restore(free_blocks_);
    if constexpr (wide_rays) wide_.reset();
}

template <stored_object O, class BV, class Config>
struct bvh<O, BV, Config>::tree_backup {
    std::vector<node> nodes;
    std::vector<slot_index> items;
    std::vector<node_index> free_pairs, free_blocks;
    std::vector<std::pair<slot_index, node_index>> metas;
    std::size_t size_at_build = 0, updates_since_build = 0, full_rebuilds = 0;
    bool stale = false;
    double quality_at_build = 1;
};

template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::backup_all() -> tree_backup {
    tree_backup b;
    b.metas.reserve(slots_.size());
    for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1))
        b.metas.emplace_back(s, slots_.meta(s));
    std::vector<node> nodes;
    std::vector<slot_index> items;
    std::vector<node_index> free_pairs, free_blocks;
    nodes.reserve(nodes_.capacity());
    items.reserve(items_.capacity());
    free_pairs.reserve(free_pairs_.capacity());
    free_blocks.reserve(free_blocks_.capacity());
    // Nothing has changed yet; from here on nothing can fail.
    b.nodes = std::exchange(nodes_, std::move(nodes));
    b.items = std::exchange(items_, std::move(items));
    b.free_pairs = std::exchange(free_pairs_, std::move(free_pairs));
    b.free_blocks = std::exchange(free_blocks_, std::move(free_blocks));
    b.size_at_build = size_at_build_, b.updates_since_build = updates_since_build_;
    b.full_rebuilds = full_rebuilds_, b.stale = stale_, b.quality_at_build = quality_at_build_;
    return b;
}

template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::restore(tree_backup& b) noexcept {
    nodes_ = std::move(b.nodes);
    items_ = std::move(b.items);
    free_pairs_ = std::move(b.free_pairs);
    free_blocks_ = std::move(b.free_blocks);
    for (const auto& [s, m] : b.metas) slots_.set_meta(s, m);
    size_at_build_ = b.size_at_build, updates_since_build_ = b.updates_since_build;
    full_rebuilds_ = b.full_rebuilds, stale_ = b.stale, quality_at_build_ = b.quality_at_build;
    if constexpr (wide_rays) wide_.reset();
}

}  // namespace spatial
