#pragma once
// spatial::detail::reuse_or_grow — the one free-list rule of the library's index-based stores
// (kd_tree leaf buckets and node pairs, octree child blocks, bvh item blocks, quickhull facets
// and conflict lists): the most recently freed index is reused first (LIFO, so recently
// touched memory is reused while still in cache); only when none is free does the store grow.

#include <vector>

namespace spatial::detail {

// The last index of `free_list` (removed from it); when the list is empty, grow(), which
// makes room at the end of the store and returns the new index.
template <class Index, class Grow>
Index reuse_or_grow(std::vector<Index>& free_list, Grow&& grow) {
    if (free_list.empty()) return grow();
    const Index i = free_list.back();
    free_list.pop_back();
    return i;
}

}  // namespace spatial::detail
