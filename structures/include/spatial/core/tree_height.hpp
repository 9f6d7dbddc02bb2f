#pragma once
// spatial::detail::tree_height — the height of an index-based tree (levels below the root),
// by an explicit stack so that no tree depth can overflow the call stack; the bvh's and the
// octree's height() (diagnostics for tests and benchmarks, O(nodes)).

#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

namespace spatial::detail {

// for_each_child(n, push) calls push(c) for every child c of node n (none for a leaf).
// 0 for a lone root leaf.
template <class NodeIndex, class ForEachChild>
std::size_t tree_height(NodeIndex root, ForEachChild&& for_each_child) {
    std::size_t h = 0;
    std::vector<std::pair<NodeIndex, std::size_t>> stack{{root, 0}};
    while (!stack.empty()) {
        const auto [n, d] = stack.back();
        stack.pop_back();
        h = std::max(h, d);
        for_each_child(n, [&stack, below = d + 1](NodeIndex c) { stack.push_back({c, below}); });
    }
    return h;
}

}  // namespace spatial::detail
