#pragma once
// Splitting rules for kd_tree construction, chosen by kd_tree_config::splitter.
//
// A splitter receives n > leaf_capacity build entries (each with coordinates `c`),
// partitions them in place and returns (dim, value, left): afterwards entries [0, left) have
// c[dim] <= value and [left, n) have c[dim] >= value, with 0 < left < n.
// Both rules below are O(n) expected per node, O(n log n) per build.

#include <algorithm>
#include <array>
#include <cstddef>
#include <limits>
#include <tuple>
#include <type_traits>

#include "spatial/kdtree/select.hpp"

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

// Bounding box of the entries; for large nodes, of a strided sample of about 4096 of them
// (the widest side is what matters, and a sample estimates it well at 1/stride the cost).
template <class T, std::size_t D, class Entry>
void bounding_box(const Entry* e, std::size_t n, std::array<T, D>& lo, std::array<T, D>& hi) {
    const std::size_t stride = n > 65536 ? n / 4096 : 1;
    lo = e[0].c;
    hi = e[0].c;
    for (std::size_t i = 0; i < n; i += stride)
        for (std::size_t d = 0; d < D; ++d) {
            lo[d] = e[i].c[d] < lo[d] ? e[i].c[d] : lo[d];
            hi[d] = e[i].c[d] > hi[d] ? e[i].c[d] : hi[d];
        }
}

// Whether a cut leaving `cut` of n entries on the left keeps depth O(log n): within
// [2n/5, 3n/5]. A splitter's n exceeds the leaf capacity (at least 2), so n >= 3 and the
// band never holds 0 or n.
inline bool in_balance_band(std::size_t cut, std::size_t n) { return cut >= n * 2 / 5 && cut <= n * 3 / 5; }

template <class Entry>
auto median_partition(Entry* e, std::size_t n, unsigned dim, std::size_t m) {
    floyd_rivest_select(e, 0, static_cast<std::ptrdiff_t>(n) - 1, static_cast<std::ptrdiff_t>(m),
                        [dim](const Entry& a) { return a.c[dim]; });
    return e[m].c[dim];  // the right side's minimum; everything left of m is <= it
}
// Move the split value off the data. Given entries partitioned at m (every key in [0, m) <=
// every key in [m, n), and min_right the smallest key of [m, n)): when no tie spans the
// cut, the split value becomes the middle of the gap between the largest left key and
// min_right, so no point lies ON the splitting plane and queries near it prune better.
//
// When a run of equal keys spans the cut, both children hold points of its plane and their
// key ranges touch, so a query near the plane prunes neither. A run longer than a leaf (a
// lattice's plane through a large node) moves whole to the side that keeps the cut nearer
// the median, if that cut stays within [2n/5, 3n/5] (depth stays O(log n)), and the cut goes
// in the gap beside it. A shorter run keeps the tie split: moving every tied cut (exact
// duplicates tie at almost every cut, about ten copies each) off its multiple of the leaf
// capacity left partly filled leaves, measured (1e6 points) at 14 % more memory and kNN time
// on duplicate-heavy data, where the same move for every run had helped lattice kNN by
// ~15 %. Two partition passes, only when a tie spans the cut.
template <class T, class Entry>
split_choice<T> cut_in_gap(Entry* e, std::size_t n, std::size_t m, unsigned dim, T min_right,
                           std::size_t leaf_capacity) {
    T max_left = e[0].c[dim];
    for (std::size_t i = 1; i < m; ++i) max_left = e[i].c[dim] > max_left ? e[i].c[dim] : max_left;
    if (max_left < min_right) return {dim, max_left + (min_right - max_left) / 2, m};
    // The run of keys equal to min_right becomes [run_begin, run_end): the left side's
    // smaller keys first, the right side's equal keys first.
    const auto key = [dim](const Entry& a) { return a.c[dim]; };
    const auto run_begin = static_cast<std::size_t>(
        std::partition(e, e + m, [&](const Entry& a) { return key(a) < min_right; }) - e);
    const auto run_end = static_cast<std::size_t>(
        std::partition(e + m, e + n, [&](const Entry& a) { return !(min_right < key(a)); }) - e);
    if (run_end - run_begin <= leaf_capacity) return {dim, min_right, m};
    const bool below_ok = in_balance_band(run_begin, n), above_ok = in_balance_band(run_end, n);
    const bool below = below_ok && (!above_ok || m - run_begin <= run_end - m);
    if (below) {  // the run goes right: cut between the largest smaller key and the run
        T below_max = e[0].c[dim];
        for (std::size_t i = 1; i < run_begin; ++i) below_max = std::max(below_max, key(e[i]));
        return {dim, below_max + (min_right - below_max) / 2, run_begin};
    }
    if (above_ok) {  // the run goes left: cut between the run and the smallest larger key
        T above_min = e[run_end].c[dim];
        for (std::size_t i = run_end + 1; i < n; ++i) above_min = std::min(above_min, key(e[i]));
        return {dim, min_right + (above_min - min_right) / 2, run_end};
    }
    return {dim, min_right, m};
}

}  // namespace detail

// Default. Median along the dimension of widest spread (Friedman, Bentley & Finkel 1977),
// with the left count rounded up to a multiple of the leaf capacity so that leaves come out
// full (less memory, fewer nodes). Depth is log2(n / leaf_capacity) + O(1) on ANY input,
// including duplicates and degenerate (collinear, coplanar) sets.
//
// Exact selection moves every entry two or three times per level, and in large nodes the
// build is bound by that memory traffic. So nodes above 8192 entries ESTIMATE their median
// from a strided sample of min(4095, n/16) keys and are partitioned in a single pass (rank
// error a few percent, so depth is unaffected; it costs at most one partly filled leaf per
// such subtree, under 1% of the leaves). If the estimate is off by more than 10% (heavy
// duplicates, adversarial strides), the exact selection is used instead.
struct median_of_widest_spread {
    static constexpr std::size_t sampled_median_threshold = 8192;
    template <class Entry>
    auto operator()(Entry* e, std::size_t n, std::size_t leaf_capacity) const {
        using T = std::remove_cvref_t<decltype(e[0].c[0])>;
        constexpr std::size_t D = std::tuple_size_v<std::remove_cvref_t<decltype(e[0].c)>>;
        std::array<T, D> lo, hi;
        detail::bounding_box<T, D>(e, n, lo, hi);
        const unsigned dim = detail::widest_dimension(lo, hi);
        if (n > sampled_median_threshold) {
            std::array<T, 4095> buffer;
            const std::size_t count = std::min<std::size_t>(buffer.size(), n / 16) | 1;
            const std::size_t stride = n / count;
            for (std::size_t i = 0; i < count; ++i) buffer[i] = e[i * stride].c[dim];
            std::nth_element(buffer.begin(), buffer.begin() + count / 2, buffer.begin() + count);
            const T pivot = buffer[count / 2];
            Entry* cut = std::partition(e, e + n, [dim, pivot](const Entry& a) { return a.c[dim] < pivot; });
            const auto left = static_cast<std::size_t>(cut - e);
            // pivot is a data key, so it is the smallest key of the right side.
            if (detail::in_balance_band(left, n))
                return detail::cut_in_gap<T>(e, n, left, dim, pivot, leaf_capacity);
        }
        std::size_t m = n / 2;
        if (n > 2 * leaf_capacity) m = (m + leaf_capacity - 1) / leaf_capacity * leaf_capacity;
        m = std::clamp<std::size_t>(m, 1, n - 1);
        const T min_right = detail::median_partition(e, n, dim, m);
        return detail::cut_in_gap<T>(e, n, m, dim, min_right, leaf_capacity);
    }
};

// Midpoint of max spread (CGAL's Midpoint_of_max_spread): cut the widest side of the
// points' bounding box at its middle, so cells stay fat, which helps approximate search on
// clustered data (the motivation of Maneewongvatana & Mount 1999's sliding midpoint, of
// which this is the bounding-box variant). If the cut leaves fewer than a quarter of the
// points on one side, fall back to the median so that depth stays O(log n) — the kd_tree's
// balance rule relies on it.
struct midpoint_of_max_spread {
    template <class Entry>
    auto operator()(Entry* e, std::size_t n, std::size_t) const {
        using T = std::remove_cvref_t<decltype(e[0].c[0])>;
        constexpr std::size_t D = std::tuple_size_v<std::remove_cvref_t<decltype(e[0].c)>>;
        std::array<T, D> lo, hi;
        detail::bounding_box<T, D>(e, n, lo, hi);
        const unsigned dim = detail::widest_dimension(lo, hi);
        const T mid = lo[dim] + (hi[dim] - lo[dim]) / 2;
        Entry* cut = std::partition(e, e + n, [dim, mid](const Entry& a) { return a.c[dim] < mid; });
        const std::size_t left = static_cast<std::size_t>(cut - e);
        if (left >= n / 4 && n - left >= n / 4 && left > 0 && left < n) return split_choice<T>{dim, mid, left};
        const std::size_t m = n / 2;
        return split_choice<T>{dim, detail::median_partition(e, n, dim, m), m};
    }
};

}  // namespace spatial
