#pragma once
// Splitting rules for kd_tree construction, chosen by kd_tree_config::splitter.
//
// A splitter receives n > leaf_capacity build entries (each with coordinates `c`) and their
// bounding box, partitions them in place and returns (dim, value, left): afterwards entries
// [0, left) have c[dim] <= value and [left, n) have c[dim] >= value, with 0 < left < n.
// Both rules below are O(n) per node (nth_element / partition), O(n log n) per build.

#include <algorithm>
#include <array>
#include <cstddef>

namespace spatial {

template <class T>
struct split_choice {
    unsigned dim;
    T value;
    std::size_t left;
};

namespace detail {
template <class T, std::size_t D>
unsigned widest_dimension(const std::array<T, D>& lo, const std::array<T, D>& hi) {
    unsigned best = 0;
    for (unsigned d = 1; d < D; ++d)
        if (hi[d] - lo[d] > hi[best] - lo[best]) best = d;
    return best;
}

template <class Entry>
auto median_partition(Entry* e, std::size_t n, unsigned dim, std::size_t m) {
    std::nth_element(e, e + m, e + n, [dim](const Entry& a, const Entry& b) { return a.c[dim] < b.c[dim]; });
    return e[m].c[dim];  // the right side's minimum; everything left of m is <= it
}
}  // namespace detail

// Default. Median along the dimension of widest spread (Friedman, Bentley & Finkel 1977),
// with the left count rounded up to a multiple of the leaf capacity so that leaves come out
// full (less memory, fewer nodes). Depth is log2(n / leaf_capacity) + O(1) on ANY input,
// including duplicates and degenerate (collinear, coplanar) sets.
struct median_of_widest_spread {
    template <class Entry, class T, std::size_t D>
    split_choice<T> operator()(Entry* e, std::size_t n, const std::array<T, D>& lo,
                               const std::array<T, D>& hi, std::size_t leaf_capacity) const {
        const unsigned dim = detail::widest_dimension(lo, hi);
        std::size_t m = n / 2;
        if (n > 2 * leaf_capacity) m = (m + leaf_capacity - 1) / leaf_capacity * leaf_capacity;
        m = std::clamp<std::size_t>(m, 1, n - 1);
        return {dim, detail::median_partition(e, n, dim, m), m};
    }
};

// Sliding midpoint (Maneewongvatana & Mount 1999): cut the widest side of the points' box at
// its middle; cells stay fat, which helps approximate search on clustered data. If the cut
// leaves fewer than a quarter of the points on one side, fall back to the median so that
// depth stays O(log n) — the kd_tree's balance rule relies on it.
struct sliding_midpoint {
    template <class Entry, class T, std::size_t D>
    split_choice<T> operator()(Entry* e, std::size_t n, const std::array<T, D>& lo,
                               const std::array<T, D>& hi, std::size_t) const {
        const unsigned dim = detail::widest_dimension(lo, hi);
        const T mid = lo[dim] + (hi[dim] - lo[dim]) / 2;
        Entry* cut = std::partition(e, e + n, [dim, mid](const Entry& a) { return a.c[dim] < mid; });
        const std::size_t left = static_cast<std::size_t>(cut - e);
        if (left >= n / 4 && n - left >= n / 4 && left > 0 && left < n) return {dim, mid, left};
        const std::size_t m = n / 2;
        return {dim, detail::median_partition(e, n, dim, m), m};
    }
};

}  // namespace spatial
