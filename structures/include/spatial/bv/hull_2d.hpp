#pragma once
// spatial::hull_2d — the convex hull of a planar point set by Andrew's monotone chain
// (Andrew 1979, "Another efficient algorithm for convex hulls in two dimensions"):
// sort by (x, y), then build the lower and upper chains with an orientation test.
// O(n log n) time, O(n) memory. Used by convex_hull<T, 2>, by the flat (coplanar) case of
// convex_hull<T, 3>, and by the OBB's rotating calipers.
//
// Robustness: the orientation test has an exact sign (predicates.hpp: a floating-point
// filter with Shewchuk's error bound, exact expansion arithmetic when the filter is unsure),
// so the output is the exact convex hull of the input doubles/floats, whatever their offset,
// spread, duplicates or collinearities.
//
// Output: the hull's vertices in counter-clockwise order, without repeated or collinear
// vertices (strictly convex corners only), starting from the lexicographically smallest
// (x, then y) point. Degenerate input: no points gives none; one distinct point gives one
// vertex; collinear input gives its two extreme points (lexicographic order).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <span>
#include <vector>

#include "spatial/bv/predicates.hpp"
#include "spatial/core/point.hpp"

namespace spatial {

// Orientation of (a, b, c): > 0 counter-clockwise, < 0 clockwise, 0 collinear. The SIGN is
// exact (see predicates.hpp); the magnitude is twice the signed area evaluated in floating
// point when that value's sign is certain, and +-1 or 0 when the exact stage decided.
template <class T>
long double orientation_2d(const point<T, 2>& a, const point<T, 2>& b, const point<T, 2>& c) {
    const double pa[2] = {double(a[0]), double(a[1])}, pb[2] = {double(b[0]), double(b[1])},
                 pc[2] = {double(c[0]), double(c[1])};
    const double ux = pb[0] - pa[0], uy = pb[1] - pa[1], vx = pc[0] - pa[0], vy = pc[1] - pa[1];
    const double l = ux * vy, r = uy * vx, det = l - r;
    if (std::abs(det) > 4e-16 * (std::abs(l) + std::abs(r))) return static_cast<long double>(det);
    return static_cast<long double>(predicates::orient_2d_exact(pa, pb, pc));
}

// Monotone chain over any indexable set of n points given as double pairs by `at(i)`;
// returns the hull's point indices (CCW, strictly convex, as described above). Among
// duplicates of a hull vertex the one with the smallest index is reported.
template <class At>
std::vector<std::size_t> hull_2d_indices(std::size_t n, At&& at) {
    std::vector<std::size_t> idx(n);
    std::iota(idx.begin(), idx.end(), std::size_t(0));
    auto less = [&](std::size_t i, std::size_t j) {
        const std::array<double, 2> a = at(i), b = at(j);
        return a[0] < b[0] || (a[0] == b[0] && (a[1] < b[1] || (a[1] == b[1] && i < j)));
    };
    std::sort(idx.begin(), idx.end(), less);
    idx.erase(std::unique(idx.begin(), idx.end(), [&](std::size_t i, std::size_t j) { return at(i) == at(j); }), idx.end());
    if (idx.size() <= 2) return idx;
    auto turn = [&](std::size_t i, std::size_t j, std::size_t k) {
        const std::array<double, 2> a = at(i), b = at(j), c = at(k);
        return predicates::orient_2d(a.data(), b.data(), c.data());
    };
    std::vector<std::size_t> h(2 * idx.size());
    std::size_t k = 0;
    for (std::size_t i = 0; i < idx.size(); ++i) {  // lower chain
        while (k >= 2 && turn(h[k - 2], h[k - 1], idx[i]) <= 0) --k;
        h[k++] = idx[i];
    }
    for (std::size_t i = idx.size() - 1, lower = k + 1; i-- > 0;) {  // upper chain
        while (k >= lower && turn(h[k - 2], h[k - 1], idx[i]) <= 0) --k;
        h[k++] = idx[i];
    }
    h.resize(k - 1);  // the last point repeats the first
    return h;
}

template <class T>
std::vector<point<T, 2>> hull_2d(std::span<const point<T, 2>> pts) {
    const auto idx = hull_2d_indices(pts.size(), [&](std::size_t i) {
        return std::array<double, 2>{double(pts[i][0]), double(pts[i][1])};
    });
    std::vector<point<T, 2>> h;
    h.reserve(idx.size());
    for (std::size_t i : idx) h.push_back(pts[i]);
    return h;
}

}  // namespace spatial
