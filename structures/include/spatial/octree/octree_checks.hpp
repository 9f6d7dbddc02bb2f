#pragma once
// spatial::octree — diagnostics for tests: the structural invariant check (back-links, loose
// containment, nesting of loose cells, counts) and the height.

#include "spatial/octree/octree.hpp"
#include "spatial/core/tree_height.hpp"

namespace spatial {

template <stored_object O, class Config>
inline std::string octree<O, Config>::check_invariants() const {
    if (root_ == no_node) return slots_.size() == 0 ? "" : "no root but size() > 0";
    std::size_t seen = 0;
    std::vector<node_index> stack{root_};
    while (!stack.empty()) {
        const node_index n = stack.back();
        stack.pop_back();
        const node& nd = nodes_[n];
        for (std::size_t i = 0; i < nd.items.size(); ++i) {
            const slot_index s = nd.items[i];
            if (!slots_.occupied(s) || slots_.meta(s) != n || pos_[s] != i)
                return "back-link broken at node " + std::to_string(n);
            if (!loose_contains(nd, extent_of(slots_.value(s))))
                return "object outside its node's loose cell at node " + std::to_string(n);
        }
        seen += nd.items.size();
        if (nd.is_leaf()) continue;
        for (std::size_t b = 0; b < fanout; ++b) {
            const node_index c = nd.first_child + static_cast<node_index>(b);
            const node& cn = nodes_[c];
            if (cn.parent != n) return "parent link broken below node " + std::to_string(n);
            for (std::size_t i = 0; i < D; ++i)
                if (cn.llo[i] < nd.llo[i] || cn.lhi[i] > nd.lhi[i]) return "loose cells do not nest";
            stack.push_back(c);
        }
    }
    if (seen != slots_.size())
        return "tree holds " + std::to_string(seen) + " objects but size() is " + std::to_string(slots_.size());
    return "";
}

template <stored_object O, class Config>
inline std::size_t octree<O, Config>::height() const {
    if (root_ == no_node) return 0;
    return detail::tree_height(root_, [this](node_index n, auto&& push) {
        if (!nodes_[n].is_leaf())
            for (std::size_t b = 0; b < fanout; ++b) push(nodes_[n].first_child + static_cast<node_index>(b));
    });
}
}  // namespace spatial
