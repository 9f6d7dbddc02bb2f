#pragma once
// spatial::kd_tree_config — the kd-tree's compile-time configuration (leaf capacity, splitter,
// statistics, the scapegoat balance parameter alpha) with commented defaults. Separate so
// that a configuration can be named without the tree.

#include <cstddef>

#include "spatial/kdtree/splitters.hpp"

namespace spatial {

// Compile-time configuration with commented defaults.
template <std::size_t LeafCapacity = 32, class Splitter = median_of_widest_spread,
          bool CollectStats = false>
struct kd_tree_config {
    // Points per leaf bucket. 32 (two cache lines of slot indices) was the best general
    // capacity of the tuning sweep (8, 16, 32, 64; docs/structures/kd-tree.md, "Why 32"):
    // a leaf scan of contiguous points is cheaper than the extra level of descent, and
    // fuller leaves mean fewer nodes and buckets.
    static constexpr std::size_t leaf_capacity = LeafCapacity;
    // How a node's points are divided (see splitters.hpp).
    using splitter = Splitter;
    // When true, queries count visited nodes and tested objects (kd_tree::last_query_stats()).
    static constexpr bool collect_stats = CollectStats;
    // Weight-balance parameter alpha of the scapegoat rule, in (0.5, 1).
    static constexpr double balance_alpha = 0.75;
};

}  // namespace spatial
