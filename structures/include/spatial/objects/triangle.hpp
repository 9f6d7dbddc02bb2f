#pragma once
// spatial::objects::triangle<T, D> — a triangle object, D = 3 (a surface) or D = 2 (a filled
// triangle in the plane).
//
// 3D ray test (thickness 0): the watertight algorithm of Woop, Benthin & Wald, "Watertight
// Ray/Triangle Intersection", JCGT 2(1), 2013. The ray is sheared so that it becomes the +z
// axis; the three edge functions U, V, W are then 2D cross products of the SAME transformed
// vertices for every triangle that shares them, and an edge shared by two triangles gives
// exactly negated values in both (a*b - c*d vs c*d - a*b). So a ray through a shared edge or
// vertex of a closed mesh hits at least one of the triangles: it never slips through. When an
// edge function is exactly 0 it is recomputed in higher precision (double for float, long double
// for double), as the paper prescribes. Both faces are hit (no culling); a ray lying in the
// triangle's plane is a miss (det = 0), as in the paper (the mesh's other faces catch it).
// 2D: the ray is clipped against the three edges' half-planes (Cyrus & Beck 1978); an origin
// inside hits at t = 0. Degenerate triangles (zero area) are treated as their three segments.
// Thickness > 0: first contact of the capsule (thick_ray.hpp) with the exact point distance.
// squared_distance: closest point by Voronoi regions (Ericson, Real-Time Collision Detection,
// 2005, §5.1.5), degenerate triangles via their edges. overlaps_box: the separating axis test
// of Akenine-Möller, "Fast 3D Triangle-Box Overlap Testing", JGT 2001 (13 axes; 2D: the box
// axes and the 3 edge normals).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <type_traits>

#include "spatial/core/point.hpp"
#include "spatial/objects/box.hpp"
#include "spatial/objects/thick_ray.hpp"

namespace spatial::objects {

template <class T, std::size_t D>
class triangle {
    static_assert(D == 2 || D == 3, "objects::triangle: D must be 2 or 3");

public:
    SPATIAL_POINT_MEMBER_TYPES(T, D);

    triangle() = default;
    triangle(const point_type& a, const point_type& b, const point_type& c) : v_{a, b, c} {
        for (std::size_t i = 0; i < D; ++i) {
            lo_[i] = std::min({a[i], b[i], c[i]});
            hi_[i] = std::max({a[i], b[i], c[i]});
            // std::min and std::max skip a NaN after the first value: without this a NaN in
            // the second or third vertex left finite bounds, and containers (which check the
            // bounds) stored a triangle whose distances and ray tests are NaN.
            if (std::isnan(a[i]) || std::isnan(b[i]) || std::isnan(c[i]))
                lo_[i] = hi_[i] = std::numeric_limits<T>::quiet_NaN();
        }
    }

    const point_type& vertex(std::size_t i) const { return v_[i]; }
    const T* get_min_bound() const { return lo_.data(); }
    const T* get_max_bound() const { return hi_.data(); }
    friend bool operator==(const triangle& a, const triangle& b) { return a.v_ == b.v_; }
    template <class F>
    void for_each_hull_point(F&& f) const {
        for (const auto& p : v_) f(p);
    }

    T squared_distance(const point_type& p) const {
        if (is_degenerate()) {
            return std::min({segment_squared_distance(p, v_[0], v_[1]), segment_squared_distance(p, v_[1], v_[2]),
                             segment_squared_distance(p, v_[2], v_[0])});
        }
        if constexpr (D == 2) {
            if (contains_2d(p)) return T(0);
            return std::min({segment_squared_distance(p, v_[0], v_[1]), segment_squared_distance(p, v_[1], v_[2]),
                             segment_squared_distance(p, v_[2], v_[0])});
        } else {
            return squared_length(sub(p, closest_point_3d(p)));
        }
    }

    bool overlaps_box(const point_type& lo, const point_type& hi) const {
        for (std::size_t i = 0; i < D; ++i)
            if (hi_[i] < lo[i] || lo_[i] > hi[i]) return false;
        point_type c, h;  // box centre and half extents; the test runs relative to the centre
        for (std::size_t i = 0; i < D; ++i) {
            c[i] = lo[i] + (hi[i] - lo[i]) / 2;
            h[i] = (hi[i] - lo[i]) / 2;
        }
        const std::array<point_type, 3> w{sub(v_[0], c), sub(v_[1], c), sub(v_[2], c)};
        const std::array<point_type, 3> e{sub(w[1], w[0]), sub(w[2], w[1]), sub(w[0], w[2])};
        // An axis separates when the triangle's projection interval misses the box's.
        auto separates = [&](const point_type& axis) {
            T pmin = dot(w[0], axis), pmax = pmin;
            for (int k = 1; k < 3; ++k) {
                const T p = dot(w[k], axis);
                pmin = std::min(pmin, p);
                pmax = std::max(pmax, p);
            }
            T r = 0;
            for (std::size_t i = 0; i < D; ++i) r += h[i] * std::abs(axis[i]);
            return pmin > r || pmax < -r;
        };
        if constexpr (D == 2) {
            for (const auto& ed : e) {
                point_type n;
                n[0] = -ed[1];
                n[1] = ed[0];
                if (separates(n)) return false;
            }
            return true;
        } else {
            for (const auto& ed : e)
                for (std::size_t i = 0; i < 3; ++i) {
                    point_type u{};  // unit axis i
                    u[i] = 1;
                    if (separates(cross(u, ed))) return false;
                }
            return !separates(cross(e[0], e[1]));  // the triangle's normal
        }
    }

    template <class Info>
    bool intersect(const point_type& origin, const point_type& direction, T thickness, Info& info) const {
        return intersect(prepared_ray(origin, direction), thickness, info);
    }

    // OPTIONAL per-ray preparation (used by containers that test one ray against many
    // triangles, e.g. spatial::bvh): the per-ray part of the watertight test of Woop, Benthin
    // & Wald (2013) — the dominant axis kz, the cyclic kx, ky and the shear sx, sy, sz — is
    // computed once here instead of once per triangle. intersect(prepared_ray, ...) performs
    // EXACTLY the floating-point operations of intersect(origin, direction, ...) in the same
    // order (the unprepared call goes through it), so both give bit-identical answers.
    class prepared_ray {
    public:
        prepared_ray(const point_type& origin, const point_type& direction) : origin_(origin), direction_(direction) {
            if constexpr (D == 3) {
                // kz: the dominant axis of the direction; kx, ky follow it cyclically, swapped
                // when dir[kz] < 0 to keep the winding (so the sign tests need no special case).
                // Selected without branches: for incoherent rays each comparison is a coin
                // toss, and two mispredicted branches cost more than the rest of the setup.
                const T a0 = std::abs(direction[0]), a1 = std::abs(direction[1]), a2 = std::abs(direction[2]);
                const std::size_t k01 = a1 > a0 ? 1 : 0;
                kz_ = a2 > std::max(a0, a1) ? 2 : k01;
                const std::size_t next = kz_ == 2 ? 0 : kz_ + 1, after = next == 2 ? 0 : next + 1;
                const bool negative = direction[kz_] < 0;
                kx_ = negative ? after : next;
                ky_ = negative ? next : after;
                sx_ = direction[kx_] / direction[kz_];
                sy_ = direction[ky_] / direction[kz_];
                sz_ = T(1) / direction[kz_];
            }
        }
        const point_type& origin() const { return origin_; }
        const point_type& direction() const { return direction_; }

    private:
        friend class triangle;
        point_type origin_, direction_;
        std::size_t kx_ = 0, ky_ = 0, kz_ = 0;
        T sx_ = 0, sy_ = 0, sz_ = 0;
    };

    template <class Info>
    bool intersect(const prepared_ray& ray, T thickness, Info& info) const {
        const point_type& origin = ray.origin_;
        const point_type& direction = ray.direction_;
        T t;
        if (thickness > T(0)) {
            if (!detail::first_capsule_contact(lo_.data(), hi_.data(), D, origin, direction, thickness, info.hit_time,
                                               [&](T s) { return squared_distance(at(origin, direction, s)); }, t))
                return false;
        } else {
            bool hit;
            if constexpr (D == 3)
                hit = watertight_hit(v_, ray, t);
            else
                hit = clip_2d(origin, direction, t);
            if (!hit || !(t < info.hit_time)) return false;
        }
        info.hit_time = t;
        info.hit_location = at(origin, direction, t);
        return true;
    }
    // intersect(ray, 0, info) on the triangles in lanes [0, count) of SIMD vectors (GCC/Clang
    // vector extensions of T, one triangle per lane; vertex[k][axis][lane]), as if called on
    // each in lane order (bvh/compact_ray_form.hpp): the index of the lane hit (lowering info.hit_time), or -1. Every
    // lane runs the scalar test's floating-point operations (watertight_edges is shared, the rest is the same
    // expressions lane-wise), so the answers are bit-identical; a lane on an edge in T takes the scalar test with its
    // extended-precision fallback.
    template <class Lanes, class Info>
    static int intersect_thin_lanes(const Lanes (&vertex)[3][3], std::size_t count, const prepared_ray& ray,
                                    Info& info) requires(D == 3) {
        const auto e = watertight_edges<Lanes>(
            [&](std::size_t k, std::size_t axis) -> const Lanes& { return vertex[k][axis]; }, ray);
        const auto on_edge = (e.u == T(0)) | (e.v == T(0)) | (e.w == T(0));
        const auto negative = (e.u < T(0)) | (e.v < T(0)) | (e.w < T(0));
        const auto positive = (e.u > T(0)) | (e.v > T(0)) | (e.w > T(0));
        const Lanes det = e.u + e.v + e.w;
        const Lanes az = ray.sz_ * e.Az, bz = ray.sz_ * e.Bz, cz = ray.sz_ * e.Cz;
        const Lanes t_scaled = e.u * az + e.v * bz + e.w * cz;
        const Lanes t = t_scaled / det;  // inf or NaN in lanes that are rejected anyway
        const auto hit = ~(negative & positive) & (det != T(0)) & (t >= T(0));
        int best = -1;
        T best_t = info.hit_time;
        for (std::size_t i = 0; i < count; ++i) {
            T ti = t[i];
            bool lane_hit = hit[i] != 0;
            if (on_edge[i] != 0) [[unlikely]] {
                std::array<point_type, 3> v;
                for (std::size_t k = 0; k < 3; ++k)
                    for (std::size_t a = 0; a < 3; ++a) v[k][a] = vertex[k][a][i];
                lane_hit = watertight_hit(v, ray, ti);
            }
            if (lane_hit && ti < best_t) best_t = ti, best = static_cast<int>(i);
        }
        if (best >= 0) {
            info.hit_time = best_t;
            info.hit_location = at(ray.origin_, ray.direction_, best_t);
        }
        return best;
    }

    // The course's split: bounding boxes of the parts with normal . x <= offset (left) and
    // >= offset (right), by clipping the triangle (Sutherland & Hodgman 1974). New vertices are
    // computed in floating point, so each box is widened by a few ulps of its coordinates:
    // conservative, never missing part of the triangle. An empty part is an inverted box.
    void split(const T* normal, T offset, box<T, D>& left, box<T, D>& right) const {
        std::array<T, 3> side;
        for (int k = 0; k < 3; ++k) {
            side[k] = -offset;
            for (std::size_t i = 0; i < D; ++i) side[k] += normal[i] * v_[k][i];
        }
        left = clipped_box(side, true);
        right = clipped_box(side, false);
    }

    bool is_degenerate() const {
        if constexpr (D == 2) return cross2(sub(v_[1], v_[0]), sub(v_[2], v_[0])) == T(0);
        else return squared_length(cross(sub(v_[1], v_[0]), sub(v_[2], v_[0]))) == T(0);
    }

private:
    // ---- small vector helpers (D-generic where possible) ---------------------------------
    static point_type sub(const point_type& a, const point_type& b) {
        point_type r;
        for (std::size_t i = 0; i < D; ++i) r[i] = a[i] - b[i];
        return r;
    }
    static T dot(const point_type& a, const point_type& b) {
        T s = 0;
        for (std::size_t i = 0; i < D; ++i) s += a[i] * b[i];
        return s;
    }
    static T squared_length(const point_type& a) { return dot(a, a); }
    static point_type cross(const point_type& a, const point_type& b) {
        point_type r;
        r[0] = a[1] * b[2] - a[2] * b[1];
        r[1] = a[2] * b[0] - a[0] * b[2];
        r[2] = a[0] * b[1] - a[1] * b[0];
        return r;
    }
    static T cross2(const point_type& a, const point_type& b) { return a[0] * b[1] - a[1] * b[0]; }
    static point_type at(const point_type& o, const point_type& d, T t) {
        point_type p;
        for (std::size_t i = 0; i < D; ++i) p[i] = o[i] + t * d[i];
        return p;
    }

    static T segment_squared_distance(const point_type& p, const point_type& a, const point_type& b) {
        const point_type ab = sub(b, a);
        const T len2 = squared_length(ab);
        T s = len2 > T(0) ? dot(sub(p, a), ab) / len2 : T(0);
        s = std::clamp(s, T(0), T(1));
        return squared_length(sub(p, at(a, ab, s)));
    }

    // Ericson 2005, ClosestPtPointTriangle: Voronoi regions of vertices, then edges, then face.
    point_type closest_point_3d(const point_type& p) const {
        const point_type &a = v_[0], &b = v_[1], &c = v_[2];
        const point_type ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
        const T d1 = dot(ab, ap), d2 = dot(ac, ap);
        if (d1 <= 0 && d2 <= 0) return a;
        const point_type bp = sub(p, b);
        const T d3 = dot(ab, bp), d4 = dot(ac, bp);
        if (d3 >= 0 && d4 <= d3) return b;
        const T vc = d1 * d4 - d3 * d2;
        if (vc <= 0 && d1 >= 0 && d3 <= 0) return at(a, ab, d1 / (d1 - d3));
        const point_type cp = sub(p, c);
        const T d5 = dot(ab, cp), d6 = dot(ac, cp);
        if (d6 >= 0 && d5 <= d6) return c;
        const T vb = d5 * d2 - d1 * d6;
        if (vb <= 0 && d2 >= 0 && d6 <= 0) return at(a, ac, d2 / (d2 - d6));
        const T va = d3 * d6 - d5 * d4;
        if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
            return at(b, sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)));
        const T denom = T(1) / (va + vb + vc);
        const T v = vb * denom, w = vc * denom;
        point_type q;
        for (std::size_t i = 0; i < D; ++i) q[i] = a[i] + ab[i] * v + ac[i] * w;
        return q;
    }

    // Inside or on the boundary of a non-degenerate 2D triangle.
    bool contains_2d(const point_type& p) const {
        const T e0 = cross2(sub(v_[1], v_[0]), sub(p, v_[0]));
        const T e1 = cross2(sub(v_[2], v_[1]), sub(p, v_[1]));
        const T e2 = cross2(sub(v_[0], v_[2]), sub(p, v_[2]));
        return (e0 >= 0 && e1 >= 0 && e2 >= 0) || (e0 <= 0 && e1 <= 0 && e2 <= 0);
    }

    // ---- 3D watertight ray/triangle (Woop, Benthin & Wald 2013) ---------------------------
    // The sheared vertices relative to the origin and the edge functions u, v, w, for a
    // scalar V = T or SIMD lanes of T alike (the same operations; coordinate(k, axis) is
    // vertex k's coordinate, a T or lanes).
    template <class V>
    struct watertight_terms {
        V Az, Bz, Cz, ax, ay, bx, by, cx, cy, u, v, w;
    };
    template <class V, class Coordinate>
    static watertight_terms<V> watertight_edges(Coordinate&& coordinate, const prepared_ray& ray) requires(D == 3) {
        const point_type& org = ray.origin_;
        const std::size_t kx = ray.kx_, ky = ray.ky_, kz = ray.kz_;
        const T sx = ray.sx_, sy = ray.sy_;
        // Vertices relative to the origin, read in the ray's axis order (no temporaries
        // indexed at run time: they would go through memory).
        watertight_terms<V> e;
        e.Az = coordinate(0, kz) - org[kz], e.Bz = coordinate(1, kz) - org[kz], e.Cz = coordinate(2, kz) - org[kz];
        e.ax = (coordinate(0, kx) - org[kx]) - sx * e.Az, e.ay = (coordinate(0, ky) - org[ky]) - sy * e.Az;
        e.bx = (coordinate(1, kx) - org[kx]) - sx * e.Bz, e.by = (coordinate(1, ky) - org[ky]) - sy * e.Bz;
        e.cx = (coordinate(2, kx) - org[kx]) - sx * e.Cz, e.cy = (coordinate(2, ky) - org[ky]) - sy * e.Cz;
        e.u = e.cx * e.by - e.cy * e.bx;
        e.v = e.ax * e.cy - e.ay * e.cx;
        e.w = e.bx * e.ay - e.by * e.ax;
        return e;
    }

    // True, with the hit parameter t_out >= 0, exactly when the triangle with these vertices
    // is hit.
    static bool watertight_hit(const std::array<point_type, 3>& vertex, const prepared_ray& ray,
                               T& t_out) requires(D == 3) {
        const auto e = watertight_edges<T>([&](std::size_t k, std::size_t axis) { return vertex[k][axis]; }, ray);
        const T sz = ray.sz_;
        const T Az = e.Az, Bz = e.Bz, Cz = e.Cz;
        const T ax = e.ax, ay = e.ay, bx = e.bx, by = e.by, cx = e.cx, cy = e.cy;
        T u = e.u, v = e.v, w = e.w;
        if (u == T(0) || v == T(0) || w == T(0)) [[unlikely]] {  // on an edge in T: decide in more precision
            using W = std::conditional_t<std::is_same_v<T, float>, double, long double>;
            u = static_cast<T>(W(cx) * W(by) - W(cy) * W(bx));
            v = static_cast<T>(W(ax) * W(cy) - W(ay) * W(cx));
            w = static_cast<T>(W(bx) * W(ay) - W(by) * W(ax));
        }
        // Mixed signs: the ray passes outside an edge. Evaluated without branches (these
        // outcomes are unpredictable across the triangles of a leaf).
        const bool negative = (u < 0) | (v < 0) | (w < 0), positive = (u > 0) | (v > 0) | (w > 0);
        if (negative & positive) return false;
        const T det = u + v + w;
        if (det == T(0)) return false;
        const T az = sz * Az, bz = sz * Bz, cz = sz * Cz;
        const T t_scaled = u * az + v * bz + w * cz;
        const T t = t_scaled / det;
        if (!(t >= T(0))) return false;
        t_out = t;
        return true;
    }

    // ---- 2D filled triangle --------------------------------------------------------------
    bool clip_2d(const point_type& org, const point_type& dir, T& t_out) const {
        if (is_degenerate()) {
            bool any = false;
            T best = std::numeric_limits<T>::infinity();
            for (int k = 0; k < 3; ++k) {
                T t;
                if (segment_hit_2d(org, dir, v_[k], v_[(k + 1) % 3], t) && t < best) {
                    best = t;
                    any = true;
                }
            }
            t_out = best;
            return any;
        }
        // Orient the half-planes inward: for a counter-clockwise triangle, inside is left of
        // every edge (cross2(edge, p - start) >= 0).
        const T orientation = cross2(sub(v_[1], v_[0]), sub(v_[2], v_[0])) > 0 ? T(1) : T(-1);
        T t0 = 0, t1 = std::numeric_limits<T>::infinity();
        for (int k = 0; k < 3; ++k) {
            const point_type& s = v_[k];
            const point_type edge = sub(v_[(k + 1) % 3], s);
            // g(t) = orientation * cross2(edge, org + t dir - s) >= 0 is the half-plane.
            const T g0 = orientation * cross2(edge, sub(org, s));
            const T slope = orientation * cross2(edge, dir);
            if (slope == T(0)) {
                if (g0 < 0) return false;
                continue;
            }
            const T t = -g0 / slope;
            if (slope > 0) t0 = std::max(t0, t);
            else t1 = std::min(t1, t);
            if (t0 > t1) return false;
        }
        t_out = t0;
        return true;
    }
    // First t >= 0 at which the 2D ray meets the closed segment [a, b] (collinear overlap too).
    static bool segment_hit_2d(const point_type& org, const point_type& dir, const point_type& a,
                               const point_type& b, T& t_out) {
        const point_type e = sub(b, a), ao = sub(a, org);
        const T denom = cross2(dir, e);
        if (denom != T(0)) {
            const T t = cross2(ao, e) / denom, s = cross2(ao, dir) / denom;
            if (t >= 0 && s >= 0 && s <= 1) {
                t_out = t;
                return true;
            }
            return false;
        }
        if (cross2(ao, dir) != T(0)) return false;  // parallel, not collinear
        // Collinear: project the segment's ends onto the ray's parameter.
        const T dd = dot(dir, dir);
        const T ta = dot(ao, dir) / dd, tb = dot(sub(b, org), dir) / dd;
        const T lo = std::min(ta, tb), hi = std::max(ta, tb);
        if (hi < 0) return false;
        t_out = std::max(lo, T(0));
        return true;
    }

    // Bounds of the part of the triangle with sign(side) on the kept side (Sutherland-Hodgman
    // against one plane: at most 4 vertices).
    box<T, D> clipped_box(const std::array<T, 3>& side, bool keep_negative) const {
        box<T, D> b = box<T, D>::inverted();
        auto add = [&](const point_type& p) {
            for (std::size_t i = 0; i < D; ++i) {
                b.lo[i] = std::min(b.lo[i], p[i]);
                b.hi[i] = std::max(b.hi[i], p[i]);
            }
        };
        auto kept = [&](T s) { return keep_negative ? s <= 0 : s >= 0; };
        bool added_crossing = false;
        for (int k = 0; k < 3; ++k) {
            const int n = (k + 1) % 3;
            if (kept(side[k])) add(v_[k]);
            if ((side[k] < 0 && side[n] > 0) || (side[k] > 0 && side[n] < 0)) {
                const T s = side[k] / (side[k] - side[n]);
                add(at(v_[k], sub(v_[n], v_[k]), s));
                added_crossing = true;
            }
        }
        if (added_crossing && !b.is_empty()) {
            // Widen by the rounding of the crossing points (a few ulps of the largest magnitude).
            for (std::size_t i = 0; i < D; ++i) {
                const T mag = std::max({std::abs(lo_[i]), std::abs(hi_[i])});
                const T slack = 8 * std::numeric_limits<T>::epsilon() * mag;
                b.lo[i] = std::max(lo_[i], b.lo[i] - slack);
                b.hi[i] = std::min(hi_[i], b.hi[i] + slack);
            }
        }
        return b;
    }

    std::array<point_type, 3> v_{};
    std::array<T, D> lo_{}, hi_{};
};

}  // namespace spatial::objects
