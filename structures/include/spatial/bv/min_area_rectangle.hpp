#pragma once
// spatial::min_area_rectangle — the minimum-area enclosing rectangle of a planar point set,
// used by the OBB fits (obb.hpp): exactly in 2D, and per candidate axis in 3D.
//
// Why it works: a minimum-area enclosing rectangle has a side collinear with an edge of the
// convex hull (Freeman & Shapira 1975, "Determining the minimum-area encasing rectangle for
// an arbitrary closed curve", CACM 18(7)). Rotating calipers (Toussaint 1983, "Solving
// geometric problems with the rotating calipers", MELECON) visit every hull edge with the
// three other supporting lines advancing monotonically around the hull, so all h candidate
// rectangles cost O(h) in total.
//
// min_area_rectangle(points): O(n log n) — an Akl–Toussaint pre-filter (Akl & Toussaint 1978,
// "A fast convex hull algorithm", IPL 7(5)) drops points strictly inside the octagon of the
// extreme points along 8 directions in O(n) (for uniform data almost all of them), then
// spatial::hull_2d (Andrew's monotone chain) and the calipers. The filter keeps a relative
// safety margin, so it never drops a hull vertex.
//
// Precision: everything in double; callers pass coordinates relative to a point of the set
// (small magnitudes). The rectangle is returned as a unit axis u, its normal v = perp(u)
// (counter-clockwise, so (u, v) is right-handed) and the projection intervals on both.
// Degenerate input: no points gives an empty result (lo > hi); one distinct point gives a
// zero rectangle with u = (1, 0); collinear points give u along the segment and zero width.
// Callers that need containment in another precision re-measure the extents themselves.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <vector>

#include "spatial/bv/hull_2d.hpp"
#include "spatial/core/point.hpp"

namespace spatial {

struct rectangle_2d {
    std::array<double, 2> axis{1.0, 0.0};  // unit u; the second axis is v = (-u[1], u[0])
    std::array<double, 2> lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
    std::array<double, 2> hi{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};

    bool is_empty() const { return !(lo[0] <= hi[0]) || !(lo[1] <= hi[1]); }
    double area() const { return is_empty() ? 0.0 : (hi[0] - lo[0]) * (hi[1] - lo[1]); }
    double perimeter() const { return is_empty() ? 0.0 : 2 * ((hi[0] - lo[0]) + (hi[1] - lo[1])); }
};

// The projection intervals of pts on u and perp(u).
inline rectangle_2d rectangle_with_axis(std::span<const point<double, 2>> pts, std::array<double, 2> u) {
    rectangle_2d r;
    r.axis = u;
    for (const auto& p : pts) {
        const double a = p[0] * u[0] + p[1] * u[1];
        const double b = -p[0] * u[1] + p[1] * u[0];
        r.lo[0] = std::min(r.lo[0], a), r.hi[0] = std::max(r.hi[0], a);
        r.lo[1] = std::min(r.lo[1], b), r.hi[1] = std::max(r.hi[1], b);
    }
    return r;
}

// Rotating calipers over a convex polygon given counter-clockwise without repeated or
// collinear vertices (hull_2d's output). O(h).
inline rectangle_2d min_area_rectangle_of_hull(std::span<const point<double, 2>> h) {
    const std::size_t m = h.size();
    if (m == 0) return {};
    if (m == 1) return rectangle_with_axis(h, {1.0, 0.0});
    if (m == 2) {
        const double ex = h[1][0] - h[0][0], ey = h[1][1] - h[0][1];
        const double len = std::hypot(ex, ey);
        return rectangle_with_axis(
            h, len > 0 ? std::array<double, 2>{ex / len, ey / len} : std::array<double, 2>{1.0, 0.0});
    }
    auto at = [&](std::size_t i) -> const point<double, 2>& { return h[i % m]; };
    auto dot = [&](std::size_t i, double x, double y) { return at(i)[0] * x + at(i)[1] * y; };
    // Counters grow without wrapping (indices are taken mod m); each caliper makes at most
    // two turns in total, which the guards enforce even if rounding breaks unimodality.
    std::size_t j = 1, k = 1, l = 1;
    double best = std::numeric_limits<double>::infinity();
    std::size_t best_i = 0;
    for (std::size_t i = 0; i < m; ++i) {
        const double ex = at(i + 1)[0] - at(i)[0], ey = at(i + 1)[1] - at(i)[1];
        const double len = std::hypot(ex, ey);
        if (!(len > 0)) continue;
        const double ux = ex / len, uy = ey / len;  // edge direction
        const double nx = -uy, ny = ux;             // inward normal (the hull is to the left)
        j = std::max(j, i + 1);
        while (j < i + m && dot(j + 1, ux, uy) > dot(j, ux, uy)) ++j;  // farthest along u
        k = std::max(k, j);
        while (k < i + m && dot(k + 1, nx, ny) > dot(k, nx, ny)) ++k;  // farthest from the edge
        l = std::max(l, k);
        while (l < i + m && dot(l + 1, ux, uy) < dot(l, ux, uy)) ++l;  // farthest against u
        const double area = (dot(j, ux, uy) - dot(l, ux, uy)) * (dot(k, nx, ny) - dot(i, nx, ny));
        if (area < best) best = area, best_i = i;
    }
    const double ex = at(best_i + 1)[0] - at(best_i)[0], ey = at(best_i + 1)[1] - at(best_i)[1];
    const double len = std::hypot(ex, ey);
    // Re-measure over all hull vertices: the intervals are then exact for the chosen axis
    // even if a caliper stopped early on rounding noise.
    return rectangle_with_axis(h, {ex / len, ey / len});
}

// Akl–Toussaint: the points that may be hull vertices (all others lie strictly inside the
// polygon of the extreme points along 8 directions, by a relative margin). O(n).
inline std::vector<point<double, 2>> hull_candidates(std::span<const point<double, 2>> pts) {
    std::vector<point<double, 2>> out;
    if (pts.size() < 64) {
        out.assign(pts.begin(), pts.end());
        return out;
    }
    // Directions in counter-clockwise order, so their extreme points are in hull order.
    static constexpr double dirs[8][2] = {{1, 0}, {1, 1}, {0, 1}, {-1, 1}, {-1, 0}, {-1, -1}, {0, -1}, {1, -1}};
    std::array<std::size_t, 8> arg{};
    std::array<double, 8> best;
    best.fill(-std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < pts.size(); ++i)
        for (std::size_t d = 0; d < 8; ++d) {
            const double s = pts[i][0] * dirs[d][0] + pts[i][1] * dirs[d][1];
            if (s > best[d]) best[d] = s, arg[d] = i;
        }
    std::vector<point<double, 2>> poly;
    for (std::size_t d = 0; d < 8; ++d)
        if (poly.empty() || !(pts[arg[d]] == poly.back())) poly.push_back(pts[arg[d]]);
    while (poly.size() > 1 && poly.front() == poly.back()) poly.pop_back();
    double extent = 0;
    for (const auto& p : poly) extent = std::max({extent, std::abs(p[0] - poly[0][0]), std::abs(p[1] - poly[0][1])});
    if (poly.size() < 3 || !(extent > 0)) {
        out.assign(pts.begin(), pts.end());
        return out;
    }
    // Edge data: a point is dropped when it is left of every edge by more than the margin.
    struct edge {
        double ax, ay, ex, ey, margin;
    };
    std::vector<edge> edges;
    for (std::size_t i = 0; i < poly.size(); ++i) {
        const auto& a = poly[i];
        const auto& b = poly[(i + 1) % poly.size()];
        const double ex = b[0] - a[0], ey = b[1] - a[1];
        edges.push_back({a[0], a[1], ex, ey, 1e-9 * std::hypot(ex, ey) * extent});
    }
    out.reserve(pts.size() / 8 + 16);
    for (const auto& p : pts) {
        bool inside = true;
        for (const auto& e : edges)
            if (!(e.ex * (p[1] - e.ay) - e.ey * (p[0] - e.ax) > e.margin)) {
                inside = false;
                break;
            }
        if (!inside) out.push_back(p);
    }
    return out;
}

// Minimum-area enclosing rectangle of any planar point set. O(n log n).
inline rectangle_2d min_area_rectangle(std::span<const point<double, 2>> pts) {
    const auto cand = hull_candidates(pts);
    const auto h = hull_2d(std::span<const point<double, 2>>(cand));
    return min_area_rectangle_of_hull(h);
}

}  // namespace spatial
