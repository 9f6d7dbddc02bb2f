#pragma once
// Compile-time settings of spatial::octree (octree.hpp), with commented defaults.

#include <cstddef>
#include <ratio>

namespace spatial {

// The loose factor is a std::ratio, not a double: a floating-point template argument is C++20
// that GCC 12 accepts but clang before 18 does not ("not yet supported").
template <std::size_t LeafCapacity = 8, std::size_t MaxDepth = 32, class LooseFactor = std::ratio<2>>
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
    static constexpr double loose_factor = static_cast<double>(LooseFactor::num) / static_cast<double>(LooseFactor::den);
};

using loose_octree_config = octree_config<>;
using classic_octree_config = octree_config<8, 32, std::ratio<1>>;

}  // namespace spatial
