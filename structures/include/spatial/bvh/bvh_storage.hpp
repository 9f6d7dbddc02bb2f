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
inline void bvh<O, BV, Config>::clear_nodes() {
    nodes_.clear();
    items_.clear();
    free_pairs_.clear();
    free_blocks_.clear();
}

template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::reset_to_empty() {
    clear_nodes();
    nodes_.push_back(node{});
    make_leaf(root, nullptr, 0);
    size_at_build_ = 0;
    updates_since_build_ = 0;
    stale_ = false;
}

template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::swap_contents(bvh& o) {
    this->swap_with(o, &bvh::nodes_, &bvh::items_, &bvh::free_pairs_, &bvh::free_blocks_, &bvh::size_at_build_,
                    &bvh::updates_since_build_, &bvh::full_rebuilds_, &bvh::stale_, &bvh::quality_at_build_);
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
