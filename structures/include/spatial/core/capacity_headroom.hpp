#pragma once
// spatial::detail::capacity_with_headroom and set_capacity — after a full build, an array's
// capacity set to its size plus one eighth: neither the doubling's spare half (up to 50 % more memory than the tree needs)
// nor an exact fit, with which the first insertion that adds one node copies the whole array
// (on a bvh of 1e6 points, about 130 MB copied and page-faulted for a split that adds two
// nodes: it made a batch of n/10 insertions after a build cost half again as much). With an
// eighth spare, the tree takes updates in proportion to its size before it first grows, and
// growth then doubles as usual (amortised O(1) per insertion). Best-effort: without memory for
// the new array the old one, with its elements, is kept. O(size) element moves. A tree built
// to be read rather than updated may ask for the exact fit instead (bvh_config::build_headroom).

#include <cstddef>
#include <iterator>
#include <new>
#include <type_traits>
#include <vector>

namespace spatial::detail {

// The capacity a full build leaves an array of n elements (a builder that knows n in advance
// reserves it at once, and set_capacity then has nothing to move).
constexpr std::size_t capacity_with_headroom(std::size_t n) { return n + n / 8; }

// The array's capacity set to `want` (>= its size) by one allocation and a move of its
// elements; without memory for it the array is left as it was.
template <class T, class A>
void set_capacity(std::vector<T, A>& v, std::size_t want) noexcept {
    static_assert(std::is_nothrow_move_constructible_v<T>, "the elements are moved after the one allocation");
    if (v.capacity() == want) return;
    try {
        std::vector<T, A> moved(v.get_allocator());
        moved.reserve(want);
        std::move(v.begin(), v.end(), std::back_inserter(moved));
        v.swap(moved);
    } catch (const std::bad_alloc&) {
    }
}

}  // namespace spatial::detail
