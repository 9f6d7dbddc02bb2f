#pragma once
// Compile-time settings of spatial::octree (octree.hpp), with commented defaults.

#include <cstddef>

namespace spatial {

template <std::size_t LeafCapacity = 8, std::size_t MaxDepth = 32, double LooseFactor = 2.0>
struct octree_config {
    // Objects a leaf holds before it is split into 2^D children. 8 keeps a leaf's slot list
    // within one cache line (8 x 4 bytes) and its scan cheaper than another level.
    static constexpr std::size_t leaf_capacity = LeafCapacity;
    // No cell is split below root_size / 2^max_depth (nor below a few ulps of its own
    // coordinates): bounds the height when many objects coincide, whatever their number.
    static constexpr std::size_t max_depth = MaxDepth;
    // k of Ulrich's loose octree (Ulrich 2000): a node's loose cell is its cell scaled by k
    // about its centre. k = 2 lets every object whose size is at most the cell size sink to
    // the depth matching its size (it always fits the loose cell of the child holding its
    // centre); k = 1 is the classic octree, where an object straddling a split plane stays in
    // the inner node.
    static constexpr double loose_factor = LooseFactor;
};

using loose_octree_config = octree_config<>;
using classic_octree_config = octree_config<8, 32, 1.0>;

}  // namespace spatial
