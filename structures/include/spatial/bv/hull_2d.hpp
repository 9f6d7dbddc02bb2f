#pragma once
// spatial::hull_2d — the convex hull of a planar point set by Andrew's monotone chain
// (Andrew 1979, "Another efficient algorithm for convex hulls in two dimensions"):
// sort by (x, y), then build the lower and upper chains with an orientation test.
// O(n log n) time, O(n) memory. Used by convex_hull<T, 2> and by the OBB's rotating calipers.
//
// Output: the hull's vertices in counter-clockwise order, without repeated or collinear
// vertices (strictly convex corners only). Degenerate input: one distinct point gives one
// vertex; collinear input gives its two extreme points.

#include <algorithm>
#include <cstddef>
#include <span>
#include <vector>

#include "spatial/core/point.hpp"

namespace spatial {

// Sign of the orientation of (a, b, c): > 0 counter-clockwise, < 0 clockwise, 0 collinear.
// Evaluated in long double after subtracting a (differences of doubles are exact in most
// cases that matter; the convex_hull header documents the remaining tolerance).
template <class T>
long double orientation_2d(const point<T, 2>& a, const point<T, 2>& b, const point<T, 2>& c) {
    using L = long double;
    const L abx = L(b[0]) - L(a[0]), aby = L(b[1]) - L(a[1]);
    const L acx = L(c[0]) - L(a[0]), acy = L(c[1]) - L(a[1]);
    return abx * acy - aby * acx;
}

template <class T>
std::vector<point<T, 2>> hull_2d(std::span<const point<T, 2>> pts) {
    std::vector<point<T, 2>> p(pts.begin(), pts.end());
    std::sort(p.begin(), p.end(), [](const auto& a, const auto& b) { return a[0] < b[0] || (a[0] == b[0] && a[1] < b[1]); });
    p.erase(std::unique(p.begin(), p.end()), p.end());
    if (p.size() <= 2) return p;
    std::vector<point<T, 2>> h(2 * p.size());
    std::size_t k = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {  // lower chain
        while (k >= 2 && orientation_2d(h[k - 2], h[k - 1], p[i]) <= 0) --k;
        h[k++] = p[i];
    }
    for (std::size_t i = p.size() - 1, lower = k + 1; i-- > 0;) {  // upper chain
        while (k >= lower && orientation_2d(h[k - 2], h[k - 1], p[i]) <= 0) --k;
        h[k++] = p[i];
    }
    h.resize(k - 1);  // the last point repeats the first
    if (h.size() == 2 && h[0] == h[1]) h.resize(1);
    return h;
}

}  // namespace spatial
