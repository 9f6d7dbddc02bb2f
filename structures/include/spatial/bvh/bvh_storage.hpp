#pragma once
// spatial::bvh — tree storage: the node array and the leaf blocks (see the layout in bvh.hpp).
// Inner nodes' children are allocated as a pair (first, first + 1) and a leaf owns one block
// of leaf_size entries of items_; freed pairs and blocks are recycled by later allocations.
// Also the bookkeeping of an empty tree, the member-wise swap behind the moves, and the
// preorder that refit(), the statistics and the checks walk. Included by bvh.hpp at its end
// (out-of-class definitions of members of the class template).

#include "spatial/bvh/bvh.hpp"

namespace spatial {

// ================= storage of nodes and leaf blocks =====================================
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::clear_nodes() noexcept {
    nodes_.clear();
    items_.clear();
    free_pairs_.clear();
    free_blocks_.clear();
}

// The unallocated empty tree (see has_root): no allocation, so the moves and clear() cannot
// throw. Capacities are kept; the build statistics (full_rebuilds, quality_at_build) too.
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::drop_tree() noexcept {
    clear_nodes();
    size_at_build_ = 0;
    updates_since_build_ = 0;
    stale_ = false;
    if constexpr (wide_rays) wide_.reset();
}

// Gives the unallocated tree its root: one empty leaf with its block, fitted to nothing.
// Strong guarantee: if that cannot allocate, the tree is the unallocated one again.
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::ensure_root() {
    if (has_root()) return;
    try {
        nodes_.push_back(node{});
        make_leaf(root, nullptr, 0);
    } catch (...) {
        clear_nodes();
        throw;
    }
}

// What refit_node fits to an empty leaf: the root volume of an empty tree.
template <stored_object O, class BV, class Config>
inline const BV& bvh<O, BV, Config>::empty_volume() {
    static const BV v = [] {
        if constexpr (volume_is_box) return box_type::empty();
        else return bvh_detail::fit_volume<BV>(std::span<const bv_point>{});
    }();
    return v;
}

// The moves' exchange. The fitting scratch travels with the tree, so a moved-from tree holds no
// heap memory at all.
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::swap_contents(bvh& o) noexcept {
    this->swap_with(o, &bvh::nodes_, &bvh::items_, &bvh::free_pairs_, &bvh::free_blocks_, &bvh::scratch_,
                    &bvh::size_at_build_, &bvh::updates_since_build_, &bvh::full_rebuilds_, &bvh::stale_,
                    &bvh::quality_at_build_);
    if constexpr (wide_rays) wide_.swap(o.wide_);
}

template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::alloc_block() -> node_index {
    return detail::reuse_or_grow(free_blocks_, [this] {
        items_.resize(items_.size() + leaf_size, no_slot);
        return static_cast<node_index>(items_.size() / leaf_size - 1);
    });
}

template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::alloc_pair() -> node_index {
    if (!free_pairs_.empty()) {
        const node_index p = free_pairs_.back();
        free_pairs_.pop_back();
        nodes_[p] = node{};
        nodes_[p + 1] = node{};
        return p;
    }
    if (nodes_.size() + 2 >= static_cast<std::size_t>(no_node)) throw std::length_error("bvh: too many nodes");
    const auto p = static_cast<node_index>(nodes_.size());
    nodes_.resize(nodes_.size() + 2);
    return p;
}

template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::preorder(std::vector<node_index>& order) const {
    order.clear();
    if (!has_root()) return;  // the unallocated tree: no nodes to visit
    order.reserve(nodes_.size());
    std::vector<node_index> st{root};
    while (!st.empty()) {
        const node_index n = st.back();
        st.pop_back();
        order.push_back(n);
        if (!nodes_[n].leaf) st.push_back(nodes_[n].first + 1), st.push_back(nodes_[n].first);
    }
}

}  // namespace spatial
