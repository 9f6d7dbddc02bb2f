#pragma once
// Validation of ray-cast answers against an oracle (brute_force over the same triangles).
//
// Two implementations may legitimately disagree on a ray that passes (within rounding) through
// an edge or a vertex: one reports the triangle on one side, another the neighbour, or — for
// a silhouette edge or a structure that is not watertight (CGAL's double predicates, Embree's
// float test) — one reports a hit and the other a miss. So an answer agrees when
//   * both miss, or both hit with |t_got - t_want| <= time_relative * max(|t_got|, |t_want|); or
//   * they differ but the ray is ambiguous at the implementations' precision: EXCUSED, counted
//     and reported, never silently accepted. With delta = edge_relative * scene_scale (how far
//     rounding may move a vertex or the ray), a ray is ambiguous when
//       - it passes within delta of some triangle edge before the farther of the two hits
//         (one side may report the neighbour, or a miss at a silhouette), or
//       - both hit, and one triangle explains both distances: the ray meets its plane at t_p,
//         within delta of the triangle, and |t - t_p| <= delta / |cos theta| for both answers,
//         theta being the angle between the ray and the triangle's normal (a grazing ray's
//         hit distance moves by delta / |cos theta| when the plane moves by delta).
// Anything else is a wrong answer (validation_error in the harness, a failure in tests).
// Directions are expected to be unit length, so t is a distance.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>

#include "datasets/triangle_mesh.hpp"
#include "spatial/core/point.hpp"
#include "spatial/objects/triangle.hpp"

namespace harness {

struct ray_answer {
    bool hit = false;
    double t = std::numeric_limits<double>::infinity();
};

struct ray_tolerance {
    double time_relative;  // allowed relative difference of hit distances
    double edge_relative;  // a ray this close to an edge (relative to scene_scale) is ambiguous
};

// Float peers (Embree): the brief's 1e-5; double peers: rounding of a different formula.
inline constexpr ray_tolerance float_peer_tolerance{1e-5, 1e-5};
inline constexpr ray_tolerance double_peer_tolerance{1e-9, 1e-9};

enum class ray_agreement { same, excused_ambiguous, different };

// max(bounding-box diagonal, largest |coordinate|): float rounding scales with the latter.
inline double scene_scale(const datasets::triangle_mesh& mesh) {
    const auto b = datasets::bounds_of(mesh);
    double s = b.diagonal();
    for (std::size_t d = 0; d < 3; ++d) s = std::max({s, std::abs(b.lo[d]), std::abs(b.hi[d])});
    return s;
}

namespace detail {

// Squared distance between the segments p0 + s (p1 - p0) and q0 + u (q1 - q0), s, u in [0, 1]
// (Ericson, Real-Time Collision Detection, 2005, §5.1.9). Computed in double.
inline double segment_segment_squared_distance(const double* p0, const double* p1, const double* q0,
                                               const double* q1) {
    double d1[3], d2[3], r[3];
    for (int i = 0; i < 3; ++i) {
        d1[i] = p1[i] - p0[i];
        d2[i] = q1[i] - q0[i];
        r[i] = p0[i] - q0[i];
    }
    auto dot = [](const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
    const double a = dot(d1, d1), e = dot(d2, d2), f = dot(d2, r);
    double s = 0, u = 0;
    if (a <= 0 && e <= 0) {
        s = u = 0;
    } else if (a <= 0) {
        u = std::clamp(f / e, 0.0, 1.0);
    } else {
        const double c = dot(d1, r);
        if (e <= 0) {
            s = std::clamp(-c / a, 0.0, 1.0);
        } else {
            const double b = dot(d1, d2), denom = a * e - b * b;
            s = denom > 0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
            u = (b * s + f) / e;
            if (u < 0) {
                u = 0;
                s = std::clamp(-c / a, 0.0, 1.0);
            } else if (u > 1) {
                u = 1;
                s = std::clamp((b - c) / a, 0.0, 1.0);
            }
        }
    }
    double dist2 = 0;
    for (int i = 0; i < 3; ++i) {
        const double x = p0[i] + s * d1[i] - (q0[i] + u * d2[i]);
        dist2 += x * x;
    }
    return dist2;
}

}  // namespace detail

// Smallest distance between the ray segment [origin, origin + length * direction] and any
// triangle edge. O(number of triangles); used only for rays whose answers differ.
template <class T>
double ray_edge_clearance(std::span<const spatial::objects::triangle<T, 3>> triangles,
                          const spatial::point<T, 3>& origin, const spatial::point<T, 3>& direction, double length) {
    double p0[3], p1[3];
    for (int i = 0; i < 3; ++i) {
        p0[i] = static_cast<double>(origin[i]);
        p1[i] = p0[i] + length * static_cast<double>(direction[i]);
    }
    double best = std::numeric_limits<double>::infinity();
    for (const auto& tri : triangles)
        for (std::size_t k = 0; k < 3; ++k) {
            const auto& a = tri.vertex(k);
            const auto& b = tri.vertex((k + 1) % 3);
            const double q0[3] = {static_cast<double>(a[0]), static_cast<double>(a[1]), static_cast<double>(a[2])};
            const double q1[3] = {static_cast<double>(b[0]), static_cast<double>(b[1]), static_cast<double>(b[2])};
            best = std::min(best, detail::segment_segment_squared_distance(p0, p1, q0, q1));
        }
    return std::sqrt(best);
}

// Whether one triangle, met at a grazing angle, explains both hit distances t1 and t2 up to a
// displacement delta of its plane (see the top of this file). O(number of triangles).
template <class T>
bool grazing_explains(std::span<const spatial::objects::triangle<T, 3>> triangles, const spatial::point<T, 3>& origin,
                      const spatial::point<T, 3>& direction, double t1, double t2, double delta) {
    double o[3], d[3];
    for (int i = 0; i < 3; ++i) {
        o[i] = static_cast<double>(origin[i]);
        d[i] = static_cast<double>(direction[i]);
    }
    const double d_len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (const auto& tri : triangles) {
        double a[3], e1[3], e2[3];
        for (int i = 0; i < 3; ++i) {
            a[i] = static_cast<double>(tri.vertex(0)[i]);
            e1[i] = static_cast<double>(tri.vertex(1)[i]) - a[i];
            e2[i] = static_cast<double>(tri.vertex(2)[i]) - a[i];
        }
        const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        const double n_len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        const double nd = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
        if (!(n_len > 0) || nd == 0) continue;
        const double t_plane = (n[0] * (a[0] - o[0]) + n[1] * (a[1] - o[1]) + n[2] * (a[2] - o[2])) / nd;
        const double slack = delta / (std::abs(nd) / (n_len * d_len)) / d_len;  // in units of the ray parameter
        if (std::abs(t1 - t_plane) > slack || std::abs(t2 - t_plane) > slack) continue;
        spatial::point<T, 3> p;
        for (std::size_t i = 0; i < 3; ++i) p[i] = static_cast<T>(o[i] + t_plane * d[i]);
        if (static_cast<double>(tri.squared_distance(p)) <= delta * delta) return true;
    }
    return false;
}

// Compares `got` with the oracle's `want` for one ray (see the top of this file).
// `far_length` bounds the ray for the edge test when neither answer hits (a length that
// crosses the whole scene).
template <class T>
ray_agreement compare_ray(const ray_answer& got, const ray_answer& want,
                          std::span<const spatial::objects::triangle<T, 3>> triangles,
                          const spatial::point<T, 3>& origin, const spatial::point<T, 3>& direction,
                          const ray_tolerance& tol, double scale, double far_length) {
    if (got.hit == want.hit) {
        if (!got.hit) return ray_agreement::same;
        if (std::abs(got.t - want.t) <= tol.time_relative * std::max({std::abs(got.t), std::abs(want.t), 1e-300}))
            return ray_agreement::same;
    }
    double length = far_length;
    if (got.hit && want.hit) length = std::max(got.t, want.t);
    else if (got.hit || want.hit) length = got.hit ? got.t : want.t;
    length *= 1 + tol.time_relative;
    const double delta = tol.edge_relative * scale;
    if (ray_edge_clearance(triangles, origin, direction, length) <= delta) return ray_agreement::excused_ambiguous;
    if (got.hit && want.hit && grazing_explains(triangles, origin, direction, got.t, want.t, delta))
        return ray_agreement::excused_ambiguous;
    return ray_agreement::different;
}

}  // namespace harness
