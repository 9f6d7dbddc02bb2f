#pragma once
// spatial::detail::reuse_or_grow — the one free-list rule of the library's index-based stores
// (kd_tree leaf buckets and node pairs, octree child blocks, bvh item blocks, quickhull facets
// and conflict lists): the most recently freed index is reused first (LIFO, so recently
// touched memory is reused while still in cache); only when none is free does the store grow.
// free_list_tail keeps the part of a free list an operation can change, to undo it.

#include <algorithm>
#include <cstddef>
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

namespace spatial::detail {

// The part of a free list that an operation can change, kept to undo it (the structures'
// strong guarantee under std::bad_alloc): an operation that takes at most k indices from the
// list (and pushes any number) leaves all but its last k entries as they were, so the size and
// those k entries restore it. O(k), where copying the list would cost O(list).
template <class Index>
struct free_list_tail {
    std::size_t size = 0;
    std::vector<Index> tail;

    free_list_tail() = default;
    free_list_tail(const std::vector<Index>& list, std::size_t k) { assign(list, k); }
    // Keeps the tail's storage, so a backup reused for many small operations allocates once.
    void assign(const std::vector<Index>& list, std::size_t k) {
        size = list.size();
        tail.assign(list.end() - static_cast<std::ptrdiff_t>(std::min(k, list.size())), list.end());
    }
    // Cannot fail: the list held `size` entries before, so its capacity suffices.
    void restore(std::vector<Index>& list) const noexcept {
        list.resize(size);
        std::copy(tail.begin(), tail.end(), list.end() - static_cast<std::ptrdiff_t>(tail.size()));
    }
};

}  // namespace spatial::detail
