#pragma once
// spatial::obb<T, D> — oriented bounding box (D = 2, 3): a centre, D orthonormal right-handed
// axes (rows of `axes`) and the half-extents along them. A point p is inside when
// |axes[k] . (p - center)| <= half_extents[k] for every k.
//
// Fitting methods, in increasing cost (n points, h hull vertices of a 2D projection):
//   fit_pca — principal axes of the point covariance (Gottschalk, Lin & Manocha 1996,
//     "OBBTree"; spatial::principal_axes), extents from the projections. O(n). No tightness
//     guarantee: the covariance frame follows the point density, not the shape (a cube's
//     points give an arbitrary frame; a cluster pulls the axes off: 2.7x the optimum on
//     the skewed box of tests/obb_test.cpp's report), but it is excellent on uniformly
//     filled elongated sets.
//   fit_dito — DiTO (Larsson & Kallberg 2011, "Fast computation of tight-fitting oriented
//     bounding boxes", Game Engine Gems 2). 3D: the extreme points along 7 (k = 14) or 13
//     (k = 26, default) fixed directions; the farthest pair and the point farthest from
//     their line form a large base triangle, the extreme points on both sides of its plane
//     make a ditetrahedron; every edge of its 7 triangles with the triangle's normal is a
//     candidate frame (21 frames, plus the axis-aligned one), ranked on the extreme points
//     alone. The paper ranks by surface area; we rank by volume, the tightness figure of
//     this study. Then (refine = true, default) an O(n) local refinement of ours, up to
//     two rounds: one pass finds the extreme points along 8 directions in each plane
//     orthogonal to an axis of the frame; the minimum-area rectangle of each plane's 16
//     support points turns the other two axes, and the best turned frame is kept only if
//     it measures smaller over all points (so refining never hurts). 2D: the extreme
//     points along 4 (k = 8) or 8 (k = 16, default) directions and the exact minimum-area
//     rectangle of their hull (the same "few extreme points choose the frame" idea).
//     O(n) in all cases; the winner is measured over all points. No guarantee beyond
//     containment; robust where PCA fails. Measured (tests/obb_test.cpp report, 1e5 and
//     1e6 points): 3D within 0.1-2.3% of the best fit on box, ellipsoid and skewed sets
//     (unrefined DiTO-26: up to 45% off); the refinement costs 2-3x the plain DiTO pass.
//   fit_principal_axes_search — the course's method: each principal (medial) axis is tried
//     as one box axis; the points are projected onto the plane orthogonal to it and the
//     minimum-area rectangle of the projection (rotating calipers, min_area_rectangle.hpp)
//     gives the other two axes; the smallest-volume box is kept. O(n log n). Guarantee:
//     volume <= fit_pca's (the PCA box is one of the boxes each candidate minimises over),
//     up to rounding. In 2D fixing one axis fixes the frame, so both candidates are the
//     PCA box and this equals fit_pca (use fit_min_area for the optimum).
//   fit_min_area (2D only) — the exact minimum-area enclosing rectangle: an optimal
//     rectangle has a side collinear with a hull edge (Freeman & Shapira 1975), all hull
//     edges visited by rotating calipers (Toussaint 1983). O(n log n). Optimal up to
//     rounding, so <= every other 2D fit.
// Candidates are ranked by volume (area in 2D); boxes that are flat (volume below 1e-9 of
// the surface measure's natural scale: a coplanar set in 3D, a collinear set in 2D) are
// ranked by surface area (perimeter) instead, so a flat set gets its tightest flat box.
//
// Precision and guarantees of every fit: the frame is found in double relative to the
// first point (coordinates offset by 1e8 and spreads of 1e-12 keep their shape), rounded to
// T, and then the half-extents are measured with the same arithmetic as contains() plus an
// outward error bound, so contains(p) holds for EVERY input point even under a different
// floating-point contraction. Degenerate input: no points gives the empty box; one point
// or all equal gives a zero box at that point; collinear and coplanar sets give boxes with
// zero (or rounding-sized) extents across them; no NaN. NaN/inf input is rejected with
// std::invalid_argument naming the bad coordinate.
//
// Queries: overlaps() is the separating-axis test (Gottschalk, Lin & Manocha 1996; Ericson,
// "Real-Time Collision Detection" 2005, sec. 4.4.1): 15 axes in 3D, 4 in 2D. Ericson's
// epsilon on |R| keeps the cross-product axes of near-parallel edges (nearly zero vectors)
// from reporting false separations, and every comparison carries a relative rounding
// margin, so it has no false negatives (touching boxes overlap) and only rounding-sized
// false positives (about 1e-15 of the box size in double). ray_interval() is the slab test
// in the box frame, distance_lower_bound() the exact distance in the box frame minus a
// rounding margin, merged() the smallest of three O(1) candidate boxes over the corners of
// both boxes (their PCA frame and each box's frame), transformed() exact (rotate the axes,
// move the centre) plus a rounding pad.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "spatial/bv/bounding_volume.hpp"
#include "spatial/bv/min_area_rectangle.hpp"
#include "spatial/bv/principal_axes.hpp"
#include "spatial/bv/rounding.hpp"
#include "spatial/core/input_checks.hpp"
#include "spatial/core/point.hpp"
#include "spatial/core/rigid_transform.hpp"

namespace spatial {

namespace detail_obb {

template <std::size_t D>
using vec = std::array<double, D>;
template <std::size_t D>
using frame = std::array<vec<D>, D>;  // rows: orthonormal, right-handed

template <std::size_t D>
constexpr frame<D> identity_frame() {
    frame<D> f{};
    for (std::size_t i = 0; i < D; ++i) f[i][i] = 1;
    return f;
}

template <std::size_t D>
double dot(const vec<D>& a, const vec<D>& b) {
    double s = 0;
    for (std::size_t i = 0; i < D; ++i) s += a[i] * b[i];
    return s;
}
inline vec<3> cross(const vec<3>& a, const vec<3>& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
template <std::size_t D>
double norm(const vec<D>& a) {
    return std::sqrt(dot<D>(a, a));
}
template <std::size_t D>
vec<D> sub(const vec<D>& a, const vec<D>& b) {
    vec<D> r;
    for (std::size_t i = 0; i < D; ++i) r[i] = a[i] - b[i];
    return r;
}

template <class T, std::size_t D>
vec<D> to_double(const point<T, D>& p) {
    vec<D> r;
    for (std::size_t i = 0; i < D; ++i) r[i] = static_cast<double>(p[i]);
    return r;
}

// Projection intervals of (p - ref) on the rows of f; also the box's measures.
template <std::size_t D>
struct extents {
    vec<D> lo, hi;
    extents() {
        lo.fill(std::numeric_limits<double>::infinity());
        hi.fill(-std::numeric_limits<double>::infinity());
    }
    void add(const vec<D>& rel, const frame<D>& f) {
        for (std::size_t k = 0; k < D; ++k) {
            const double s = dot<D>(f[k], rel);
            lo[k] = std::min(lo[k], s);
            hi[k] = std::max(hi[k], s);
        }
    }
    double volume() const {
        double v = 1;
        for (std::size_t k = 0; k < D; ++k) v *= std::max(0.0, hi[k] - lo[k]);
        return v;
    }
    double surface() const {  // perimeter in 2D
        if constexpr (D == 2)
            return 2 * (std::max(0.0, hi[0] - lo[0]) + std::max(0.0, hi[1] - lo[1]));
        else {
            double s = 0;
            for (std::size_t i = 0; i < D; ++i) {
                double f = 1;
                for (std::size_t j = 0; j < D; ++j)
                    if (j != i) f *= std::max(0.0, hi[j] - lo[j]);
                s += 2 * f;
            }
            return s;
        }
    }
};

// Ranking of candidate boxes: by volume, or by surface measure when both are flat.
template <std::size_t D>
struct quality {
    double volume = std::numeric_limits<double>::infinity();
    double surface = std::numeric_limits<double>::infinity();
    bool better_than(const quality& o) const {
        if (!std::isfinite(o.volume)) return std::isfinite(volume);
        const double s = std::max(surface, o.surface) / double(2 * D);  // a face's measure
        const double scale = D == 2 ? s * s : std::pow(s, 1.5);
        if (std::max(volume, o.volume) <= 1e-9 * scale) return surface < o.surface;
        return volume < o.volume;
    }
};

template <class T, std::size_t D>
extents<D> measure(std::span<const point<T, D>> pts, const vec<D>& ref, const frame<D>& f) {
    extents<D> e;
    for (const auto& p : pts) e.add(sub<D>(to_double(p), ref), f);
    return e;
}

template <std::size_t D>
quality<D> quality_of(const extents<D>& e) {
    return {e.volume(), e.surface()};
}

// A right-handed orthonormal frame whose last row is the unit vector n (3D).
inline frame<3> frame_around(const vec<3>& n) {
    // Pick the coordinate axis least aligned with n for a stable cross product.
    vec<3> a{0, 0, 0};
    std::size_t m = 0;
    for (std::size_t i = 1; i < 3; ++i)
        if (std::abs(n[i]) < std::abs(n[m])) m = i;
    a[m] = 1;
    vec<3> x = cross(a, n);
    const double lx = norm<3>(x);
    for (auto& c : x) c /= lx;
    const vec<3> y = cross(n, x);
    return {x, y, n};
}

// The right-handed frame (x, y, a) of a plane fit: rect.axis = (c, s) is the rectangle's
// first axis in the plane's coordinates along u and v, so x = c u + s v, y = -s u + c v,
// and x cross y = (c^2 + s^2) u cross v = a when (u, v, a) is right-handed.
inline frame<3> frame_in_plane(const rectangle_2d& rect, const vec<3>& u, const vec<3>& v, const vec<3>& a) {
    const double c = rect.axis[0], s = rect.axis[1];
    frame<3> f;
    for (std::size_t d = 0; d < 3; ++d) {
        f[0][d] = c * u[d] + s * v[d];
        f[1][d] = -s * u[d] + c * v[d];
        f[2][d] = a[d];
    }
    return f;
}

}  // namespace detail_obb

template <class T, std::size_t D>
struct obb {
    static_assert(D == 2 || D == 3, "obb<T, D>: D must be 2 or 3");
    SPATIAL_POINT_MEMBER_TYPES(T, D);
    static constexpr std::size_t corner_count = std::size_t(1) << D;

    point_type center{};
    std::array<std::array<T, D>, D> axes = identity_axes();  // rows, orthonormal, det +1
    std::array<T, D> half_extents = empty_extents();         // all >= 0 unless empty

    // The empty box (negative half-extents; contains nothing, merging with it is the
    // identity). A default-constructed obb is empty.
    static obb empty() { return obb{}; }
    bool is_empty() const {
        for (std::size_t k = 0; k < D; ++k)
            if (!(half_extents[k] >= 0)) return true;
        return false;
    }

    // Coordinate of p along axis k in the box frame. contains() and the fits' final
    // measuring pass both use exactly this expression.
    T local(const point_type& p, std::size_t k) const {
        T s = 0;
        for (std::size_t d = 0; d < D; ++d) s += axes[k][d] * (p[d] - center[d]);
        return s;
    }

    // ---- fits ---------------------------------------------------------------------------

    static obb fit_pca(std::span<const point_type> pts) {
        check_input(pts, "obb::fit_pca");
        if (pts.empty()) return empty();
        const auto pf = principal_axes(pts);
        return from_frame(pts, pf.axes);
    }

    static obb fit_principal_axes_search(std::span<const point_type> pts) {
        check_input(pts, "obb::fit_principal_axes_search");
        if (pts.empty()) return empty();
        const auto pf = principal_axes(pts);
        if constexpr (D == 2) {
            return from_frame(pts, pf.axes);  // one fixed axis fixes the 2D frame
        } else {
            using namespace detail_obb;
            const vec<3> ref = to_double(pts[0]);
            std::vector<point<double, 2>> q(pts.size());
            frame<3> best_frame = pf.axes;
            quality<3> best = quality_of(measure(pts, ref, pf.axes));
            for (std::size_t i = 0; i < 3; ++i) {
                // (a, u, v) is a cyclic permutation of a right-handed frame, so u x v = a.
                const vec<3>& a = pf.axes[i];
                const vec<3>& u = pf.axes[(i + 1) % 3];
                const vec<3>& v = pf.axes[(i + 2) % 3];
                double lo = std::numeric_limits<double>::infinity(), hi = -lo;
                for (std::size_t j = 0; j < pts.size(); ++j) {
                    const vec<3> r = sub<3>(to_double(pts[j]), ref);
                    q[j][0] = dot<3>(u, r);
                    q[j][1] = dot<3>(v, r);
                    const double s = dot<3>(a, r);
                    lo = std::min(lo, s), hi = std::max(hi, s);
                }
                const rectangle_2d rect = min_area_rectangle(std::span<const point<double, 2>>(q));
                const frame<3> f = frame_in_plane(rect, u, v, a);
                const double ext = hi - lo;
                const quality<3> cand{rect.area() * ext, 2 * (rect.area() + ext * (rect.perimeter() / 2))};
                if (cand.better_than(best)) best = cand, best_frame = f;
            }
            return from_frame(pts, best_frame);
        }
    }

    static obb fit_min_area(std::span<const point_type> pts) requires(D == 2) {
        check_input(pts, "obb::fit_min_area");
        if (pts.empty()) return empty();
        using namespace detail_obb;
        const vec<2> ref = to_double(pts[0]);
        std::vector<point<double, 2>> q(pts.size());
        for (std::size_t j = 0; j < pts.size(); ++j) {
            q[j][0] = static_cast<double>(pts[j][0]) - ref[0];
            q[j][1] = static_cast<double>(pts[j][1]) - ref[1];
        }
        const rectangle_2d rect = min_area_rectangle(std::span<const point<double, 2>>(q));
        return from_frame(pts, frame_of(rect));
    }

    // k: the number of extreme points, 14 or 26 in 3D (DiTO-14 / DiTO-26), 8 or 16 in 2D.
    // refine (3D): follow DiTO with the in-plane refinement described in the header. O(n).
    static obb fit_dito(std::span<const point_type> pts, std::size_t k = D == 3 ? 26 : 16, bool refine = true) {
        check_input(pts, "obb::fit_dito");
        using namespace detail_obb;
        std::vector<vec<D>> dirs;
        if constexpr (D == 3) {
            if (k != 14 && k != 26)
                throw std::invalid_argument("obb::fit_dito: k must be 14 or 26 in 3D, got " + std::to_string(k));
            dirs = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}, {1, 1, -1}, {1, -1, 1}, {1, -1, -1}};
            if (k == 26)
                for (const vec<3>& v : {vec<3>{1, 1, 0}, vec<3>{1, -1, 0}, vec<3>{1, 0, 1}, vec<3>{1, 0, -1},
                                        vec<3>{0, 1, 1}, vec<3>{0, 1, -1}})
                    dirs.push_back(v);
        } else {
            if (k != 8 && k != 16)
                throw std::invalid_argument("obb::fit_dito: k must be 8 or 16 in 2D, got " + std::to_string(k));
            const std::size_t s = k / 2;
            for (std::size_t i = 0; i < s; ++i) {
                const double ang = 3.14159265358979323846 * static_cast<double>(i) / static_cast<double>(s);
                dirs.push_back({std::cos(ang), std::sin(ang)});
            }
        }
        if (pts.empty()) return empty();
        const vec<D> ref = to_double(pts[0]);
        // Extreme points (relative to ref) along every direction, one O(n) pass.
        const std::size_t s = dirs.size();
        std::vector<double> lo(s, std::numeric_limits<double>::infinity()),
            hi(s, -std::numeric_limits<double>::infinity());
        std::vector<vec<D>> ext(2 * s, vec<D>{});
        for (const auto& p : pts) {
            const vec<D> r = sub<D>(to_double(p), ref);
            for (std::size_t i = 0; i < s; ++i) {
                const double v = dot<D>(dirs[i], r);
                if (v < lo[i]) lo[i] = v, ext[2 * i] = r;
                if (v > hi[i]) hi[i] = v, ext[2 * i + 1] = r;
            }
        }
        if constexpr (D == 2) {
            std::vector<point<double, 2>> e2(ext.size());
            for (std::size_t i = 0; i < ext.size(); ++i) e2[i][0] = ext[i][0], e2[i][1] = ext[i][1];
            const rectangle_2d rect = min_area_rectangle(std::span<const point<double, 2>>(e2));
            return from_frame(pts, frame_of(rect));
        } else {
            const detail_obb::frame<3> f = dito_frame(ext);
            return from_frame(pts, refine ? refine_in_planes(pts, ref, f, 2) : f);
        }
    }

    // ---- queries ------------------------------------------------------------------------

    bool contains(const point_type& p) const {
        if (is_empty()) return false;
        for (std::size_t k = 0; k < D; ++k)
            if (!(std::abs(local(p, k)) <= half_extents[k])) return false;
        return true;
    }

    // Separating-axis test; see the header comment for the robustness argument.
    bool overlaps(const obb& b) const {
        if (is_empty() || b.is_empty()) return false;
        constexpr T eps = std::numeric_limits<T>::epsilon();
        std::array<T, D> dc, t;
        T dmag = 0, hsum = 0;
        for (std::size_t d = 0; d < D; ++d) {
            dc[d] = b.center[d] - center[d];
            dmag += std::abs(dc[d]);
            hsum += half_extents[d] + b.half_extents[d];
        }
        for (std::size_t i = 0; i < D; ++i) {
            T s = 0;
            for (std::size_t d = 0; d < D; ++d) s += axes[i][d] * dc[d];
            t[i] = s;
        }
        // R[i][j] = a_i . b_j; AR = |R| + epsilon (Ericson 4.4.1): a near-zero cross axis
        // then gets a radius that covers its rounding noise.
        std::array<std::array<T, D>, D> R, AR;
        for (std::size_t i = 0; i < D; ++i)
            for (std::size_t j = 0; j < D; ++j) {
                T s = 0;
                for (std::size_t d = 0; d < D; ++d) s += axes[i][d] * b.axes[j][d];
                R[i][j] = s;
                AR[i][j] = std::abs(s) + T(4 * D) * eps;
            }
        // Rounding margin of each comparison: the error of t (relative to |dc|), of the
        // radii and of the axes' orthonormality (relative to the extents).
        const T margin = T(4 * D) * eps * (dmag + hsum);
        for (std::size_t i = 0; i < D; ++i) {  // the axes of this box
            T rb = 0;
            for (std::size_t j = 0; j < D; ++j) rb += b.half_extents[j] * AR[i][j];
            if (std::abs(t[i]) > half_extents[i] + rb + margin) return false;
        }
        for (std::size_t j = 0; j < D; ++j) {  // the axes of the other box
            T ra = 0, tj = 0;
            for (std::size_t i = 0; i < D; ++i) ra += half_extents[i] * AR[i][j], tj += t[i] * R[i][j];
            if (std::abs(tj) > ra + b.half_extents[j] + margin) return false;
        }
        if constexpr (D == 3) {  // a_i x b_j
            for (std::size_t i = 0; i < 3; ++i) {
                const std::size_t i1 = (i + 1) % 3, i2 = (i + 2) % 3;
                for (std::size_t j = 0; j < 3; ++j) {
                    const std::size_t j1 = (j + 1) % 3, j2 = (j + 2) % 3;
                    const T ra = half_extents[i1] * AR[i2][j] + half_extents[i2] * AR[i1][j];
                    const T rb = b.half_extents[j1] * AR[i][j2] + b.half_extents[j2] * AR[i][j1];
                    const T tl = t[i2] * R[i1][j] - t[i1] * R[i2][j];
                    if (std::abs(tl) > ra + rb + margin) return false;
                }
            }
        }
        return true;
    }

    // The parameter interval of the line o + t d inside the box (slab test in the box
    // frame; Kay & Kajiya 1986). A local direction component of 0 or -0 means the line is
    // parallel to that slab: it is inside it or misses. Each slab is widened by a rounding
    // margin, so a grazing line is never missed (the interval may be slightly too long).
    bool ray_interval(const point_type& o, const point_type& d, T& t0, T& t1) const {
        if (is_empty()) return false;
        constexpr T eps = std::numeric_limits<T>::epsilon();
        t0 = -std::numeric_limits<T>::infinity();
        t1 = std::numeric_limits<T>::infinity();
        for (std::size_t k = 0; k < D; ++k) {
            T ok = 0, dk = 0, mag = 0;
            for (std::size_t i = 0; i < D; ++i) {
                const T r = o[i] - center[i];
                ok += axes[k][i] * r;
                dk += axes[k][i] * d[i];
                mag += std::abs(r);
            }
            const T h = half_extents[k] + T(D + 3) * eps * (mag + half_extents[k]);
            if (dk == 0) {
                if (std::abs(ok) > h) return false;
                continue;
            }
            T a = (-h - ok) / dk, b = (h - ok) / dk;
            if (a > b) std::swap(a, b);
            t0 = std::max(t0, a);
            t1 = std::min(t1, b);
            if (t0 > t1) return false;
        }
        return true;
    }

    // The Euclidean distance to the box, measured in its frame, minus a rounding margin so
    // that it never exceeds the true distance. 0 inside.
    T distance_lower_bound(const point_type& p) const {
        if (is_empty()) return std::numeric_limits<T>::infinity();
        constexpr T eps = std::numeric_limits<T>::epsilon();
        T s = 0, mag = 0, hsum = 0;
        for (std::size_t d = 0; d < D; ++d) mag += std::abs(p[d] - center[d]), hsum += half_extents[d];
        for (std::size_t k = 0; k < D; ++k) {
            const T e = std::max(T(0), std::abs(local(p, k)) - half_extents[k]);
            s += e * e;
        }
        return std::max(T(0), std::sqrt(s) - T(2 * D + 4) * eps * (mag + hsum));
    }

    // The 2^D corners: bit k of the index selects +half_extents[k] (set) or - (clear).
    std::array<point_type, corner_count> corners() const {
        std::array<point_type, corner_count> c;
        for (std::size_t i = 0; i < corner_count; ++i) {
            c[i] = center;
            for (std::size_t k = 0; k < D; ++k) {
                const T h = (i >> k & 1) ? half_extents[k] : -half_extents[k];
                for (std::size_t d = 0; d < D; ++d) c[i][d] += h * axes[k][d];
            }
        }
        return c;
    }

    // A box containing both: the smallest of three candidate frames (the PCA frame of all
    // 2^(D+1) corners, this box's frame, the other box's frame) measured over the corners,
    // padded for the rounding of the corners. O(1).
    obb merged(const obb& o) const {
        if (is_empty()) return o;
        if (o.is_empty()) return *this;
        using namespace detail_obb;
        std::array<point_type, 2 * corner_count> pts;
        const auto ca = corners(), cb = o.corners();
        std::copy(ca.begin(), ca.end(), pts.begin());
        std::copy(cb.begin(), cb.end(), pts.begin() + corner_count);
        const std::span<const point_type> s(pts);
        const vec<D> ref = to_double(pts[0]);
        frame<D> best = principal_axes(s).axes;
        quality<D> bq = quality_of(measure(s, ref, best));
        for (const obb* b : {this, &o}) {
            frame<D> f;
            for (std::size_t k = 0; k < D; ++k)
                for (std::size_t d = 0; d < D; ++d) f[k][d] = static_cast<double>(b->axes[k][d]);
            const quality<D> q = quality_of(measure(s, ref, f));
            if (q.better_than(bq)) bq = q, best = f;
        }
        obb m = from_frame(s, best);
        // The corners were rounded to T: pad by their error bound.
        constexpr T eps = std::numeric_limits<T>::epsilon();
        // A corner coordinate's error is below (D + 1) ulps of max|c| + sum h of its box.
        T mag = 0;
        for (const obb* b : {this, &o}) {
            T m1 = 0, hs = 0;
            for (std::size_t d = 0; d < D; ++d) m1 = std::max(m1, std::abs(b->center[d])), hs += b->half_extents[d];
            mag = std::max(mag, m1 + hs);
        }
        for (std::size_t k = 0; k < D; ++k)
            m.half_extents[k] = detail_rounding::next_up(m.half_extents[k] + T(2 * D + 2) * eps * mag);
        return m;
    }

    // Exact: the axes rotate, the centre moves, the extents stay (plus a pad for the
    // rounding of the moved centre and axes).
    obb transformed(const rigid_transform<T, D>& xf) const {
        if (is_empty()) return *this;
        obb b;
        b.center = xf.apply(center);
        for (std::size_t k = 0; k < D; ++k) {
            point_type a;
            for (std::size_t d = 0; d < D; ++d) a[d] = axes[k][d];
            const point_type r = xf.apply_vector(a);
            for (std::size_t d = 0; d < D; ++d) b.axes[k][d] = r[d];
        }
        constexpr T eps = std::numeric_limits<T>::epsilon();
        T mag = 0;
        for (std::size_t d = 0; d < D; ++d)
            mag += std::abs(center[d]) + std::abs(b.center[d]) + std::abs(xf.translation[d]) + half_extents[d];
        for (std::size_t k = 0; k < D; ++k)
            b.half_extents[k] = detail_rounding::next_up(half_extents[k] + T(4 * D + 4) * eps * mag);
        return b;
    }

    T volume() const {  // area in 2D
        if (is_empty()) return 0;
        T v = 1;
        for (std::size_t k = 0; k < D; ++k) v *= 2 * half_extents[k];
        return v;
    }
    T surface_area() const {  // perimeter in 2D
        if (is_empty()) return 0;
        if constexpr (D == 2)
            return 4 * (half_extents[0] + half_extents[1]);
        else {
            const T x = half_extents[0], y = half_extents[1], z = half_extents[2];
            return 8 * (x * y + y * z + z * x);
        }
    }

private:
    static constexpr std::array<std::array<T, D>, D> identity_axes() {
        std::array<std::array<T, D>, D> a{};
        for (std::size_t i = 0; i < D; ++i) a[i][i] = 1;
        return a;
    }
    static constexpr std::array<T, D> empty_extents() {
        std::array<T, D> h{};
        for (auto& x : h) x = -1;
        return h;
    }

    static void check_input(std::span<const point_type> pts, const char* where) {
        for (const auto& p : pts) detail::require_finite(p, where, "input point");
    }

    static detail_obb::frame<2> frame_of(const rectangle_2d& r) {
        return {detail_obb::vec<2>{r.axis[0], r.axis[1]}, detail_obb::vec<2>{-r.axis[1], r.axis[0]}};
    }

    // The box with frame f (double, orthonormal, right-handed) around pts: centre from the
    // projection intervals in double, then the frame and centre rounded to T and the
    // half-extents measured in T with contains()'s own arithmetic, plus an error bound on
    // that arithmetic (so a differently contracted evaluation still contains every point).
    static obb from_frame(std::span<const point_type> pts, const detail_obb::frame<D>& f) {
        using namespace detail_obb;
        const vec<D> ref = to_double(pts[0]);
        const extents<D> e = measure(pts, ref, f);
        vec<D> c = ref;
        for (std::size_t k = 0; k < D; ++k) {
            const double mid = e.lo[k] + (e.hi[k] - e.lo[k]) / 2;
            for (std::size_t d = 0; d < D; ++d) c[d] += mid * f[k][d];
        }
        obb b;
        for (std::size_t d = 0; d < D; ++d) b.center[d] = static_cast<T>(c[d]);
        for (std::size_t k = 0; k < D; ++k)
            for (std::size_t d = 0; d < D; ++d) b.axes[k][d] = static_cast<T>(f[k][d]);
        std::array<T, D> h{}, bound{};
        for (const auto& p : pts) {
            for (std::size_t k = 0; k < D; ++k) {
                h[k] = std::max(h[k], std::abs(b.local(p, k)));
                T m = 0;
                for (std::size_t d = 0; d < D; ++d) m += std::abs(b.axes[k][d]) * std::abs(p[d] - b.center[d]);
                bound[k] = std::max(bound[k], m);
            }
        }
        constexpr T eps = std::numeric_limits<T>::epsilon();
        for (std::size_t k = 0; k < D; ++k) {
            const T pad = T(D + 3) * eps * bound[k];
            b.half_extents[k] = pad > 0 ? detail_rounding::next_up(h[k] + pad) : h[k];
        }
        return b;
    }

    // O(n) refinement of a 3D frame f, `rounds` times: one pass finds the extreme points
    // along 8 directions in each plane orthogonal to an axis of f (21 distinct directions,
    // including f's own axes, which give f's exact extents); per plane, the minimum-area
    // rectangle of those 16 support points turns the other two axes; the most promising
    // turned frame (ranked on all support points) is measured over all points and kept
    // only if it is really smaller. Never worse than f.
    static detail_obb::frame<3> refine_in_planes(std::span<const point_type> pts, const detail_obb::vec<3>& ref,
                                                 detail_obb::frame<3> f, int rounds) {
        using namespace detail_obb;
        for (int round = 0; round < rounds; ++round) {
            // dirs[0..2] = f's axes; then for plane k the oblique directions m * pi / M.
            constexpr std::size_t M = 8, per = M - 2, nd = 3 + 3 * per;
            std::array<vec<3>, nd> dirs;
            for (std::size_t k = 0; k < 3; ++k) dirs[k] = f[k];
            for (std::size_t k = 0; k < 3; ++k) {
                const vec<3>& u = f[(k + 1) % 3];
                const vec<3>& v = f[(k + 2) % 3];
                for (std::size_t m = 1, slot = 0; m < M; ++m) {
                    if (2 * m == M) continue;
                    const double a = 3.14159265358979323846 * static_cast<double>(m) / static_cast<double>(M);
                    for (std::size_t d = 0; d < 3; ++d)
                        dirs[3 + per * k + slot][d] = std::cos(a) * u[d] + std::sin(a) * v[d];
                    ++slot;
                }
            }
            std::array<double, nd> lo, hi;
            lo.fill(std::numeric_limits<double>::infinity());
            hi.fill(-std::numeric_limits<double>::infinity());
            std::array<vec<3>, nd> arg_lo{}, arg_hi{};
            for (const auto& p : pts) {
                const vec<3> r = sub<3>(to_double(p), ref);
                for (std::size_t i = 0; i < nd; ++i) {
                    const double s = dot<3>(dirs[i], r);
                    if (s < lo[i]) lo[i] = s, arg_lo[i] = r;
                    if (s > hi[i]) hi[i] = s, arg_hi[i] = r;
                }
            }
            extents<3> fe;
            for (std::size_t k = 0; k < 3; ++k) fe.lo[k] = lo[k], fe.hi[k] = hi[k];
            const quality<3> current = quality_of(fe);
            std::vector<vec<3>> support(arg_lo.begin(), arg_lo.end());
            support.insert(support.end(), arg_hi.begin(), arg_hi.end());
            frame<3> cand{};
            quality<3> cq;
            for (std::size_t k = 0; k < 3; ++k) {
                const std::size_t i = (k + 1) % 3, j = (k + 2) % 3;
                const vec<3>& u = f[i];
                const vec<3>& v = f[j];
                std::vector<point<double, 2>> q;
                auto add = [&](const vec<3>& r) { q.push_back(point<double, 2>{{dot<3>(u, r), dot<3>(v, r)}}); };
                for (const std::size_t idx : {i, j}) add(arg_lo[idx]), add(arg_hi[idx]);
                for (std::size_t slot = 0; slot < per; ++slot)
                    add(arg_lo[3 + per * k + slot]), add(arg_hi[3 + per * k + slot]);
                const rectangle_2d rect = min_area_rectangle(std::span<const point<double, 2>>(q));
                const frame<3> g = frame_in_plane(rect, u, v, f[k]);  // (u, v, f_k) is cyclic
                extents<3> ge;
                for (const auto& r : support) ge.add(r, g);
                const quality<3> gq = quality_of(ge);
                if (gq.better_than(cq)) cq = gq, cand = g;
            }
            if (!cq.better_than(current)) break;
            const quality<3> real = quality_of(measure(pts, ref, cand));
            if (!real.better_than(current)) break;
            f = cand;
        }
        return f;
    }

    // DiTO's candidate frames from the extreme points (relative coordinates), 3D.
    static detail_obb::frame<3> dito_frame(const std::vector<detail_obb::vec<3>>& ext) {
        using namespace detail_obb;
        auto eval = [&](const frame<3>& f) {
            extents<3> e;
            for (const auto& r : ext) e.add(r, f);
            return quality_of(e);
        };
        frame<3> best = identity_frame<3>();
        quality<3> bq = eval(best);
        // Base triangle: the farthest pair, then the point farthest from their line.
        std::size_t i0 = 0, i1 = 0;
        double dmax = 0;
        for (std::size_t i = 0; i < ext.size(); ++i)
            for (std::size_t j = i + 1; j < ext.size(); ++j) {
                const vec<3> dd = sub<3>(ext[j], ext[i]);
                const double d2 = dot<3>(dd, dd);
                if (d2 > dmax) dmax = d2, i0 = i, i1 = j;
            }
        if (!(dmax > 0)) return best;  // all extreme points equal: the (zero) AABB
        const vec<3> p0 = ext[i0], p1 = ext[i1];
        vec<3> e0 = sub<3>(p1, p0);
        const double l0 = norm<3>(e0);
        for (auto& c : e0) c /= l0;
        std::size_t i2 = 0;
        double fmax = 0;
        for (std::size_t i = 0; i < ext.size(); ++i) {
            const vec<3> c = cross(e0, sub<3>(ext[i], p0));
            const double d2 = dot<3>(c, c);
            if (d2 > fmax) fmax = d2, i2 = i;
        }
        auto consider = [&](const frame<3>& f) {
            const quality<3> q = eval(f);
            if (q.better_than(bq)) bq = q, best = f;
        };
        // Collinear extreme points: e0 as an axis, the rest of the frame arbitrary.
        if (!(std::sqrt(fmax) > 1e-12 * l0)) {
            const frame<3> g = frame_around(e0);
            consider({g[2], g[0], g[1]});
            return best;
        }
        const vec<3> p2 = ext[i2];
        // Try the three edges of triangle (a, b, c) each with the triangle's normal.
        auto try_triangle = [&](const vec<3>& a, const vec<3>& b, const vec<3>& c) {
            vec<3> n = cross(sub<3>(b, a), sub<3>(c, a));
            const double ln = norm<3>(n);
            const double scale = std::max({norm<3>(sub<3>(b, a)), norm<3>(sub<3>(c, a)), norm<3>(sub<3>(c, b))});
            if (!(ln > 1e-12 * scale * scale)) return;  // degenerate triangle
            for (auto& x : n) x /= ln;
            for (const auto& [u, v] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
                vec<3> e = sub<3>(v, u);
                // Remove the component along n (rounding) and normalise.
                const double en = dot<3>(e, n);
                for (std::size_t d = 0; d < 3; ++d) e[d] -= en * n[d];
                const double le = norm<3>(e);
                if (!(le > 0)) continue;
                for (auto& x : e) x /= le;
                consider({e, cross(n, e), n});  // e x (n x e) = n: right-handed
            }
        };
        try_triangle(p0, p1, p2);
        // Ditetrahedron apexes: the extreme points on both sides of the base plane.
        vec<3> n = cross(sub<3>(p1, p0), sub<3>(p2, p0));
        const double ln = norm<3>(n);
        for (auto& x : n) x /= ln;
        std::size_t top = 0, bottom = 0;
        double smax = 0, smin = 0;
        for (std::size_t i = 0; i < ext.size(); ++i) {
            const double sv = dot<3>(n, sub<3>(ext[i], p0));
            if (sv > smax) smax = sv, top = i;
            if (sv < smin) smin = sv, bottom = i;
        }
        const double tol = 1e-12 * l0;
        for (const auto& [idx, side] : {std::pair{top, smax}, std::pair{bottom, -smin}}) {
            if (!(side > tol)) continue;
            const vec<3>& q = ext[idx];
            try_triangle(p0, p1, q);
            try_triangle(p1, p2, q);
            try_triangle(p2, p0, q);
        }
        return best;
    }
};

static_assert(bounding_volume<obb<double, 3>>);
static_assert(bounding_volume<obb<float, 2>>);

}  // namespace spatial
