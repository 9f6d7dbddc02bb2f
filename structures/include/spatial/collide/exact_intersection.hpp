#pragma once
// spatial::collide — exact intersection tests of CLOSED segments and triangles (touching
// counts), decided only by the signs of orientation determinants that bv/predicates.hpp
// evaluates exactly (Shewchuk 1997). No tolerance, no epsilon: coplanar triangles, triangles
// touching at a vertex or along an edge, and degenerate (zero-area) triangles get the answer
// of exact arithmetic on the given coordinates (double; float converts exactly).
//
// Triangle against triangle (3D), after Guigue & Devillers 2003 ("Fast and robust
// triangle-triangle overlap test using orientation predicates", J. Graphics Tools 8(1)),
// who decide the test with orientation predicates alone; the structure here favours
// obviousness over their case tables:
//  1. each triangle against the other's plane: all three vertices strictly on one side
//     (orientations of equal nonzero sign) -> disjoint. This rejects most pairs with 6
//     orientations (Möller 1997 starts the same way).
//  2. non-coplanar triangles meet iff an edge of one meets the other triangle: T1 ∩ T2 lies
//     on the line where the planes meet, where it is the overlap of the two segments T1 ∩ L
//     and T2 ∩ L, whose endpoints lie on the triangles' edges.
//  3. coplanar triangles are tested in 2D (an edge crossing, or a vertex of one inside the
//     other) on all three coordinate projections: a projection never separates intersecting
//     sets and is exact when one to one on their plane, which at least one of them is; so
//     the answer is the AND of the three, with no normal computed and nothing rounded.
//  Degenerate triangles are the segments (or points) they span: tested as their edges.
// Cost: 6 filtered orientations for most disjoint pairs; at most ~40 for intersecting or
// near-degenerate ones.

#include <algorithm>
#include <array>

#include "spatial/bv/predicates.hpp"

namespace spatial::collide {

using vec3 = std::array<double, 3>;
using vec2 = std::array<double, 2>;

namespace detail {

inline int orient2(const vec2& a, const vec2& b, const vec2& c) { return predicates::orient_2d(a.data(), b.data(), c.data()); }
inline int orient3(const vec3& a, const vec3& b, const vec3& c, const vec3& d) {
    return predicates::orient_3d(a.data(), b.data(), c.data(), d.data());
}
// c on the closed segment [a, b], given that a, b, c are collinear: coordinate-wise between.
template <std::size_t D>
bool between(const std::array<double, D>& a, const std::array<double, D>& b, const std::array<double, D>& c) {
    for (std::size_t i = 0; i < D; ++i)
        if (c[i] < std::min(a[i], b[i]) || c[i] > std::max(a[i], b[i])) return false;
    return true;
}
inline bool collinear3(const vec3& a, const vec3& b, const vec3& c) {
    return predicates::collinear_3d(a.data(), b.data(), c.data());
}
inline vec2 drop(const vec3& p, int axis) {
    if (axis == 0) return {p[1], p[2]};
    if (axis == 1) return {p[0], p[2]};
    return {p[0], p[1]};
}

}  // namespace detail

// ---- 2D --------------------------------------------------------------------------------

// Closed segments [a, b] and [c, d] (either may be a point).
inline bool segments_intersect(const vec2& a, const vec2& b, const vec2& c, const vec2& d) {
    using detail::orient2;
    const int o1 = orient2(a, b, c), o2 = orient2(a, b, d), o3 = orient2(c, d, a), o4 = orient2(c, d, b);
    if (o1 * o2 < 0 && o3 * o4 < 0) return true;  // proper crossing
    // Touching or collinear: an endpoint on the other segment.
    if (o1 == 0 && detail::between(a, b, c)) return true;
    if (o2 == 0 && detail::between(a, b, d)) return true;
    if (o3 == 0 && detail::between(c, d, a)) return true;
    if (o4 == 0 && detail::between(c, d, b)) return true;
    // a == b (a point) or c == d: the orientations above are all 0 and between() decided.
    return false;
}

// p in the closed triangle (a, b, c); false for a degenerate triangle (callers test its
// edges instead).
inline bool point_in_triangle(const vec2& p, const vec2& a, const vec2& b, const vec2& c) {
    using detail::orient2;
    const int o = orient2(a, b, c);
    if (o == 0) return false;
    const int s0 = orient2(a, b, p), s1 = orient2(b, c, p), s2 = orient2(c, a, p);
    return s0 * o >= 0 && s1 * o >= 0 && s2 * o >= 0;
}

// Closed triangles in the plane (degenerate ones too).
inline bool triangles_intersect(const vec2& p1, const vec2& q1, const vec2& r1, const vec2& p2, const vec2& q2,
                                const vec2& r2) {
    const std::array<vec2, 3> t1{p1, q1, r1}, t2{p2, q2, r2};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (segments_intersect(t1[i], t1[(i + 1) % 3], t2[j], t2[(j + 1) % 3])) return true;
    // No boundary crossing: one contains the other entirely, or they are disjoint.
    return point_in_triangle(p1, p2, q2, r2) || point_in_triangle(p2, p1, q1, r1);
}

// ---- 3D --------------------------------------------------------------------------------

namespace detail {
// Coplanar (or collinear) configurations are decided in 2D. Projecting along a coordinate
// axis never separates intersecting sets, and it is exact when it is one to one on their
// common plane (or line), which holds for at least one of the three axes. So the 3D answer is
// the AND of the three projected answers — no normal, no rounding involved.
template <class Test2>
bool on_every_projection(Test2&& test) {
    return test(0) && test(1) && test(2);
}
}  // namespace detail

// Closed segments in space (either may be a point).
inline bool segments_intersect(const vec3& a, const vec3& b, const vec3& c, const vec3& d) {
    if (detail::orient3(a, b, c, d) != 0) return false;  // not coplanar: they cannot meet
    return detail::on_every_projection([&](int k) {
        return segments_intersect(detail::drop(a, k), detail::drop(b, k), detail::drop(c, k), detail::drop(d, k));
    });
}

// Closed segment [a, b] against the closed triangle (p, q, r), which may be degenerate.
inline bool segment_triangle_intersect(const vec3& a, const vec3& b, const vec3& p, const vec3& q, const vec3& r) {
    using detail::orient3;
    if (detail::collinear3(p, q, r))  // a segment or a point: its edges are all of it
        return segments_intersect(a, b, p, q) || segments_intersect(a, b, q, r) || segments_intersect(a, b, r, p);
    const int sa = orient3(p, q, r, a), sb = orient3(p, q, r, b);
    if (sa * sb > 0) return false;  // both strictly on one side
    if (sa == 0 && sb == 0)         // in the triangle's plane
        return detail::on_every_projection([&](int k) {
            const vec2 a2 = detail::drop(a, k), b2 = detail::drop(b, k);
            const vec2 p2 = detail::drop(p, k), q2 = detail::drop(q, k), r2 = detail::drop(r, k);
            return segments_intersect(a2, b2, p2, q2) || segments_intersect(a2, b2, q2, r2) ||
                   segments_intersect(a2, b2, r2, p2) || point_in_triangle(a2, p2, q2, r2);
        });
    // The segment meets the plane in exactly one point; it lies in the closed triangle iff
    // the line a b passes on the same side of (or through) all three edges.
    const int e0 = orient3(a, b, p, q), e1 = orient3(a, b, q, r), e2 = orient3(a, b, r, p);
    return !((e0 > 0 || e1 > 0 || e2 > 0) && (e0 < 0 || e1 < 0 || e2 < 0));
}

// Closed triangles in space (degenerate ones too).
inline bool triangles_intersect(const vec3& p1, const vec3& q1, const vec3& r1, const vec3& p2, const vec3& q2,
                                const vec3& r2) {
    using detail::orient3;
    const bool flat1 = detail::collinear3(p1, q1, r1), flat2 = detail::collinear3(p2, q2, r2);
    if (flat1)
        return segment_triangle_intersect(p1, q1, p2, q2, r2) || segment_triangle_intersect(q1, r1, p2, q2, r2) ||
               segment_triangle_intersect(r1, p1, p2, q2, r2);
    if (flat2)
        return segment_triangle_intersect(p2, q2, p1, q1, r1) || segment_triangle_intersect(q2, r2, p1, q1, r1) ||
               segment_triangle_intersect(r2, p2, p1, q1, r1);
    // 1. Each triangle against the other's plane.
    const int a0 = orient3(p2, q2, r2, p1), a1 = orient3(p2, q2, r2, q1), a2 = orient3(p2, q2, r2, r1);
    if ((a0 > 0 && a1 > 0 && a2 > 0) || (a0 < 0 && a1 < 0 && a2 < 0)) return false;
    const int b0 = orient3(p1, q1, r1, p2), b1 = orient3(p1, q1, r1, q2), b2 = orient3(p1, q1, r1, r2);
    if ((b0 > 0 && b1 > 0 && b2 > 0) || (b0 < 0 && b1 < 0 && b2 < 0)) return false;
    // 3. Coplanar.
    if (a0 == 0 && a1 == 0 && a2 == 0)
        return detail::on_every_projection([&](int k) {
            return triangles_intersect(detail::drop(p1, k), detail::drop(q1, k), detail::drop(r1, k), detail::drop(p2, k),
                                       detail::drop(q2, k), detail::drop(r2, k));
        });
    // 2. An edge of one meets the other.
    return segment_triangle_intersect(p1, q1, p2, q2, r2) || segment_triangle_intersect(q1, r1, p2, q2, r2) ||
           segment_triangle_intersect(r1, p1, p2, q2, r2) || segment_triangle_intersect(p2, q2, p1, q1, r1) ||
           segment_triangle_intersect(q2, r2, p1, q1, r1) || segment_triangle_intersect(r2, p2, p1, q1, r1);
}

}  // namespace spatial::collide
