#pragma once
// spatial::kdop<T, D, K> — discrete oriented polytope: the intersection of K/2 slabs
// lo[j] <= n_j . x <= hi[j] along FIXED integer directions n_j (Klosowski, Held, Mitchell,
// Sowizral & Zikan 1998, "Efficient collision detection using bounding volume hierarchies
// of k-DOPs", IEEE TVCG 4(1)). The directions are unnormalised small-integer vectors, as is
// customary, so a slab value costs a few additions and fitting/merging are exact min/max:
//   3D  K = 6 : the axes
//       K = 14: axes + the 4 cube diagonals (1,+-1,+-1)
//       K = 18: axes + the 6 edge diagonals (1,+-1,0), (1,0,+-1), (0,1,+-1)
//       K = 26: axes + both of the above
//   2D  K = 4 : the axes
//       K = 8 : axes + (1,+-1)
//       K = 16: axes + (1,+-1) + (2,+-1) + (1,+-2) — integer directions at 0, +-26.57,
//               +-45, +-63.43 and 90 degrees (not exactly k * 22.5 degrees: integer vectors
//               keep every slab value an exact sum of exact products).
// Any other K is a compile-time error.
//
// Operations, with n points and A = K/2 directions:
//   fit              min/max of n_j . p over the points (in double), O(n A D). Every product
//                    is exact (|n_ji| <= 2), only the <= D - 1 additions round: each slab is
//                    widened by that rounding bound, (nnz - 1) eps |n_j|_1 max|x| (nothing for
//                    the axes, so the 6-DOP IS the aabb; nothing at all for float input whose
//                    coordinates per point are within 2^26 of each other in magnitude, as the
//                    double sums are then exact), and rounded outward to T: contains(p) holds
//                    for every input point (same arithmetic) AND the exact polytope contains
//                    the exact points. Measured: 3 / 13 / 14 / 24-35 ms for 1e6 points, K = 6 /
//                    14 / 18 / 26 (double, 3D). NaN/inf input throws std::invalid_argument.
//   overlaps         interval test on the A directions, O(A), exact comparisons. CONSERVATIVE
//                    (no false negatives, touching overlaps): two k-DOPs can be disjoint while
//                    all A intervals overlap (in 3D the separating axis may be the cross
//                    product of two edge directions; for k-DOPs not tight to their content,
//                    the slabs may also be jointly inconsistent).
//   overlaps_exact   exact up to rounding: false positives only when the pair is separated by
//                    less than ~1e-15 of the slab values' magnitude (relative to the pair's
//                    position, not to the origin); touching overlaps. Method: A and B share
//                    their directions, so A ∩ B is the k-DOP {s n_j . x <= b} with slabs
//                    [max lo, min hi]. By Farkas' lemma it is empty iff some nonnegative
//                    combination of its half-spaces reads 0 <= negative, and it suffices to
//                    try the extreme rays of that cone: the minimal positive circuits of the
//                    signed directions (at most D + 1 of them, integer weights), which are
//                    precomputed per K. The pairs {+n_j, -n_j} are exactly the interval test;
//                    the exact test adds the others: 3D K = 14: 34, K = 18: 110, K = 26: 764
//                    (coplanar triples and quadruples in general position); 2D K = 8: 8,
//                    K = 16: 112 (triples). (This is the dual of the separating-axis test over
//                    face normals and edge-edge cross products, without computing either
//                    polytope.) A few cyclic projections onto the slabs (Kaczmarz) first look
//                    for a common point, which accepts most overlapping pairs early.
//                    Measured (double, 3D, random pairs of small k-DOPs, 2 shared cores):
//                    overlaps 9-15 ns; overlaps_exact 9 / 25 / 33 / 110 ns for K = 6 / 14 /
//                    18 / 26 on average, and 0.6 / 1.1 / 2.7 us in the worst case (disjoint
//                    pairs whose intervals all overlap) for K = 14 / 18 / 26.
//   contains         O(A D), the same arithmetic as fit (hence exact agreement).
//   ray_interval     slab test (Kay & Kajiya 1986) in double; zero or negative-zero values
//                    of n_j . d take the "parallel" branch, so no 0 * inf NaN.
//   distance_lower_bound  max over directions of the distance to the slab (normalised by
//                    |n_j|), minus a rounding margin: valid because the polytope lies inside
//                    every slab. Not the exact distance (it is for the 4- and 6-DOP along an
//                    axis only). O(A D).
//   merged           min/max per direction: exact (the tightest k-DOP of the union).
//   vertices()       every vertex, by intersecting D planes at a time (precomputed integer
//                    adjugates) and keeping the points that satisfy all slabs within a
//                    rounding tolerance (near-duplicates merged), computed relative to a
//                    corner of the k-DOP so the tolerance scales with its size, not with its
//                    distance from the origin. O(C(A, D) 2^D A + V^2): ~2000 candidates for
//                    K = 26, 10-60 us (used by volume, surface_area, transformed).
//   volume, surface_area   from the vertices: 2D the angle-sorted polygon (shoelace area and
//                    perimeter); 3D each face polygon is the set of vertices on one of the
//                    K planes, ordered by angle; area by the shoelace formula in the plane;
//                    volume = sum over faces of area * (distance from the vertex centroid to
//                    the plane) / 3 (divergence theorem). Exact up to rounding (absolute
//                    error ~ eps * extent * area: relative accuracy is lost only for needles
//                    and slivers thinner than ~1e-12 of their length). A flat k-DOP
//                    (zero width along one of its directions) has volume 0 and surface area
//                    twice its area, as for a flat aabb.
//   transformed      a rotated k-DOP is not a k-DOP of the same directions: this refits the
//                    moved vertices, so the result contains the moved polytope but is larger
//                    than it (CONSERVATIVE; it is the tightest k-DOP of the moved polytope up
//                    to rounding). Padded by the vertices' rounding error and, as aabb and
//                    sphere do, by the rounding of xf.apply in T (a few ulps of T of the
//                    moved coordinates), so it contains xf.apply(p) for every p inside.
//
// Empty k-DOP: lo = +inf, hi = -inf (contains nothing, merging with it is the identity,
// volume 0). Degenerate input (one point, all equal, collinear, coplanar) gives a k-DOP of
// zero width along the directions orthogonal to the set — still containing every point.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <span>
#include <stdexcept>
#include <vector>

#include "spatial/bv/bounding_volume.hpp"
#include "spatial/bv/kdop_tables.hpp"
#include "spatial/bv/predicates.hpp"
#include "spatial/core/input_checks.hpp"
#include "spatial/core/point.hpp"
#include "spatial/core/rigid_transform.hpp"

namespace spatial {

template <class T, std::size_t D, std::size_t K>
struct kdop {
    static_assert(detail_kdop::supported<D, K>(),
                  "kdop<T, D, K>: supported are D = 3 with K = 6, 14, 18, 26 and D = 2 with K = 4, 8, 16");
    SPATIAL_POINT_MEMBER_TYPES(T, D);
    static constexpr std::size_t axis_count = K / 2;
    using geometry = detail_kdop::geometry<D, K>;
    using vec = std::array<double, D>;
    // The slab directions n_j (unnormalised integer vectors), axes first.
    static constexpr std::array<std::array<int, D>, K / 2> directions = geometry::dirs;

    std::array<T, K / 2> lo{}, hi{};  // lo[j] <= n_j . x <= hi[j]

    static kdop empty() {
        kdop b;
        b.lo.fill(std::numeric_limits<T>::infinity());
        b.hi.fill(-std::numeric_limits<T>::infinity());
        return b;
    }
    bool is_empty() const {
        for (std::size_t j = 0; j < axis_count; ++j)
            if (!(lo[j] <= hi[j])) return true;
        return false;
    }

    // n_j . p in double, in one fixed order: fit and contains use this one function, so they
    // agree bit for bit. Exact products; only the additions round.
    static double slab_value(std::size_t j, const point_type& p) {
        double s = 0;
        for (std::size_t i = 0; i < D; ++i)
            if (directions[j][i] != 0) s += static_cast<double>(directions[j][i]) * static_cast<double>(p[i]);
        return s;
    }

    static kdop fit(std::span<const point_type> pts) {
        kdop b = empty();
        if (pts.empty()) return b;
        std::array<double, axis_count> mn, mx;
        mn.fill(std::numeric_limits<double>::infinity());
        mx.fill(-std::numeric_limits<double>::infinity());
        // check becomes NaN iff some coordinate is NaN or infinite.
        double m = 0, check = 0;
        bool exact = std::numeric_limits<T>::digits <= 24;  // see below
        for (const auto& p : pts) {
            for (std::size_t j = 0; j < axis_count; ++j) {
                const double v = slab_value(j, p);
                mn[j] = std::min(mn[j], v);
                mx[j] = std::max(mx[j], v);
            }
            double mp = 0;
            for (std::size_t i = 0; i < D; ++i) {
                const double c = static_cast<double>(p[i]);
                mp = std::max(mp, std::abs(c));
                check += c * 0.0;
            }
            m = std::max(m, mp);
            if constexpr (std::numeric_limits<T>::digits <= 24) {
                // Float input: each term n_ji p_i is an integer multiple of the ulp of the
                // smallest nonzero |p_i| with at most 26 significant bits; when every nonzero
                // |p_i| is >= 2^-26 max_i |p_i| the sum of <= 3 of them needs < 53 bits, so
                // the double slab value is exact and needs no pad.
                for (std::size_t i = 0; i < D; ++i) {
                    const double c = std::abs(static_cast<double>(p[i]));
                    if (c != 0 && c < mp * 0x1p-26) exact = false;
                }
            }
        }
        if (!(check == 0))  // NaN and inf do not survive min/max: find and name the culprit
            for (const auto& p : pts) detail::require_finite(p, "kdop::fit", "input point");
        b.set_padded(mn, mx, exact ? 0.0 : m, 0);
        return b;
    }

    bool contains(const point_type& p) const {
        for (std::size_t j = 0; j < axis_count; ++j) {
            const double v = slab_value(j, p);
            if (v < static_cast<double>(lo[j]) || v > static_cast<double>(hi[j])) return false;
        }
        return true;
    }

    // Conservative: see the header comment. Exact comparisons; touching overlaps.
    bool overlaps(const kdop& o) const {
        for (std::size_t j = 0; j < axis_count; ++j)
            if (o.hi[j] < lo[j] || hi[j] < o.lo[j]) return false;
        return !is_empty() && !o.is_empty();
    }

    // Exact up to rounding: the k-DOP A ∩ B has a vertex (see the header comment).
    bool overlaps_exact(const kdop& o) const {
        if (!overlaps(o)) return false;
        if constexpr (axis_count == D) return true;  // boxes: the interval test is exact
        std::array<double, axis_count> l, h;
        for (std::size_t j = 0; j < axis_count; ++j) {
            l[j] = static_cast<double>(std::max(lo[j], o.lo[j]));
            h[j] = static_cast<double>(std::min(hi[j], o.hi[j]));
        }
        const local_slabs c = make_local(l, h);
        if (feasible_point_search(c.l, c.h, c.tau)) return true;
        // Farkas: empty iff some circuit has sum_i w_i b_i < 0, where the half-space
        // s n_j . x <= b has b = hi_j for s = +1 and b = -lo_j for s = -1. Each local b
        // is within 2 eps |b| + floor_err of the exact value; the sum of <= 4 terms rounds
        // by <= 4 eps sum w |b|: only a certificate beyond that error bound decides.
        const double eps = std::numeric_limits<double>::epsilon();
        for (std::size_t k = 0; k < geometry::circuits.count; ++k) {
            const auto& ci = geometry::circuits.item[k];
            double sum = 0, mag = 0, wsum = 0;
            for (std::size_t i = 0; i < ci.size; ++i) {
                const double b = ci.coef[i] > 0 ? c.h[ci.dir[i]] : -c.l[ci.dir[i]];
                const double w = std::abs(static_cast<double>(ci.coef[i]));
                sum += w * b;
                mag += w * std::abs(b);
                wsum += w;
            }
            if (sum < -(8 * eps * mag + 2 * wsum * c.floor_err)) return false;
        }
        return true;
    }

    bool ray_interval(const point_type& o, const point_type& d, T& t0, T& t1) const {
        if (is_empty()) return false;
        double a = -std::numeric_limits<double>::infinity(), b = std::numeric_limits<double>::infinity();
        for (std::size_t j = 0; j < axis_count; ++j) {
            const double on = slab_value(j, o), dn = slab_value(j, d);
            const double l = static_cast<double>(lo[j]), h = static_cast<double>(hi[j]);
            if (dn == 0) {  // parallel to the slab (also -0.0): inside it or never
                if (on < l || on > h) return false;
                continue;
            }
            double ta = (l - on) / dn, tb = (h - on) / dn;
            if (ta > tb) std::swap(ta, tb);
            a = std::max(a, ta);
            b = std::min(b, tb);
            if (a > b) return false;
        }
        t0 = detail_kdop::round_down<T>(a);
        t1 = detail_kdop::round_up<T>(b);
        return true;
    }

    T distance_lower_bound(const point_type& p) const {
        if (is_empty()) return std::numeric_limits<T>::infinity();
        double best = 0, m = 0;
        for (std::size_t i = 0; i < D; ++i) m = std::max(m, std::abs(static_cast<double>(p[i])));
        for (std::size_t j = 0; j < axis_count; ++j) {
            const double v = slab_value(j, p);
            const double gap = std::max(static_cast<double>(lo[j]) - v, v - static_cast<double>(hi[j]));
            // v is within (nnz - 1) eps |n|_1 m of the exact n . p; the subtraction above and
            // the division below round too (factor 4 covers them).
            const double err = 4 * std::numeric_limits<double>::epsilon() * geometry::l1[j] * (m + std::abs(v));
            best = std::max(best, (gap - err) / geometry::l2(j));
        }
        return detail_kdop::round_down<T>(best * (1 - 4 * std::numeric_limits<double>::epsilon()));
    }

    kdop merged(const kdop& o) const {  // exact
        kdop b;
        for (std::size_t j = 0; j < axis_count; ++j) {
            b.lo[j] = std::min(lo[j], o.lo[j]);
            b.hi[j] = std::max(hi[j], o.hi[j]);
        }
        return b;
    }

    // The vertices of the polytope (double precision), near-duplicates merged.
    std::vector<vec> vertices_double() const {
        std::vector<vec> v;
        if (is_empty()) return v;
        const local_slabs c = make_local(*this);
        v = local_vertices(c);
        for (auto& x : v)
            for (std::size_t i = 0; i < D; ++i) x[i] += c.r[i];
        return v;
    }
    // The vertices rounded to T (for float, within half an ulp of the exact vertices).
    std::vector<point_type> vertices() const {
        std::vector<point_type> out;
        for (const auto& x : vertices_double()) {
            point_type p;
            for (std::size_t i = 0; i < D; ++i) p[i] = static_cast<T>(x[i]);
            out.push_back(p);
        }
        return out;
    }

    T volume() const { return static_cast<T>(measures().first); }
    T surface_area() const { return static_cast<T>(measures().second); }

    // Refit of the moved vertices (conservative: see the header comment).
    kdop transformed(const rigid_transform<T, D>& xf) const {
        if (is_empty()) return empty();
        const local_slabs c = make_local(*this);
        const auto v = local_vertices(c);  // relative to c.r
        if (v.empty()) return empty();
        // Every exact vertex is within vertex_err (max norm) of a kept one: tau for the
        // candidate's rounding plus 4 tau for the near-duplicate merge.
        const double vertex_err = 5 * c.tau;
        double rnorm = 0, xmax = 0;
        for (std::size_t i = 0; i < D; ++i) {
            double r = 0;
            for (std::size_t k = 0; k < D; ++k) r += std::abs(static_cast<double>(xf.rotation[i][k]));
            rnorm = std::max(rnorm, r);
        }
        for (const auto& x : v)
            for (std::size_t i = 0; i < D; ++i) xmax = std::max(xmax, std::abs(x[i]));
        // y = (R r + t) + R x, with x relative to r.
        vec q;
        double m = 0;
        for (std::size_t i = 0; i < D; ++i) {
            q[i] = static_cast<double>(xf.translation[i]);
            double mag = std::abs(q[i]);
            for (std::size_t k = 0; k < D; ++k) {
                q[i] += static_cast<double>(xf.rotation[i][k]) * c.r[k];
                mag += std::abs(static_cast<double>(xf.rotation[i][k]) * c.r[k]);
            }
            m = std::max(m, mag + rnorm * xmax);
        }
        std::array<double, axis_count> mn, mx;
        mn.fill(std::numeric_limits<double>::infinity());
        mx.fill(-std::numeric_limits<double>::infinity());
        for (const auto& x : v) {
            vec y;
            for (std::size_t i = 0; i < D; ++i) {
                double a = 0;
                for (std::size_t k = 0; k < D; ++k) a += static_cast<double>(xf.rotation[i][k]) * x[k];
                y[i] = q[i] + a;
            }
            for (std::size_t j = 0; j < axis_count; ++j) {
                const double d = geometry::dot(j, y);
                mn[j] = std::min(mn[j], d);
                mx[j] = std::max(mx[j], d);
            }
        }
        kdop b;
        // Pad: the vertex error moved by R (|R|_inf <= rnorm), then the rounding of R x + t
        // in T ((D + 1) eps_T m per coordinate, so that the moved volume contains
        // xf.apply(p) as computed in T for every p inside, as for aabb and sphere), then
        // the rounding of the slab values.
        const double eps_t =
            std::max(static_cast<double>(std::numeric_limits<T>::epsilon()), std::numeric_limits<double>::epsilon());
        b.set_padded(mn, mx, m, rnorm * vertex_err + 2 * (static_cast<double>(D) + 1) * eps_t * m);
        return b;
    }

private:
    // Slabs relative to a reference point r (the axis-slab lower corner): b - n_j . r, with
    // n_j . r summed error-free (Knuth's two-sum), so the relative slab values carry only
    // ~eps of their OWN magnitude. Vertex computations then scale with the polytope's size,
    // not with its distance from the origin (offsets of 1e8, spreads of 1e-12).
    struct local_slabs {
        std::array<double, axis_count> l{}, h{};
        vec r{};
        double tau = 0;        // tolerance unit for for_each_vertex
        double floor_err = 0;  // each l, h is within 2 eps |value| + floor_err of exact
    };
    static local_slabs make_local(const std::array<double, axis_count>& l, const std::array<double, axis_count>& h) {
        local_slabs c;
        for (std::size_t i = 0; i < D; ++i) c.r[i] = l[i];
        double scale = 0, big = 0;
        for (std::size_t j = 0; j < axis_count; ++j) {
            double sum = 0, err = 0;
            for (std::size_t i = 0; i < D; ++i) {
                if (directions[j][i] == 0) continue;
                double e;
                predicates::two_sum(sum, static_cast<double>(directions[j][i]) * c.r[i], sum, e);  // products exact
                err += e;  // |err| <= 2 eps |sum|: its own rounding is negligible (eps^2)
            }
            c.l[j] = (l[j] - sum) - err;
            c.h[j] = (h[j] - sum) - err;
            scale = std::max({scale, std::abs(c.l[j]), std::abs(c.h[j])});
            big = std::max({big, std::abs(l[j]), std::abs(h[j])});
        }
        const double eps = std::numeric_limits<double>::epsilon();
        c.floor_err = 8 * eps * eps * big + std::numeric_limits<double>::denorm_min();
        c.tau = geometry::tolerance_unit(scale) + 8 * c.floor_err;
        return c;
    }
    static local_slabs make_local(const kdop& b) {
        std::array<double, axis_count> l, h;
        for (std::size_t j = 0; j < axis_count; ++j)
            l[j] = static_cast<double>(b.lo[j]), h[j] = static_cast<double>(b.hi[j]);
        return make_local(l, h);
    }
    // Vertices relative to c.r, near-duplicates (within 4 tau) merged.
    static std::vector<vec> local_vertices(const local_slabs& c) {
        std::vector<vec> v;
        geometry::for_each_vertex(c.l, c.h, c.tau, [&](const vec& x) {
            for (const auto& y : v) {
                double dmax = 0;
                for (std::size_t i = 0; i < D; ++i) dmax = std::max(dmax, std::abs(x[i] - y[i]));
                if (dmax <= 4 * c.tau) return false;
            }
            v.push_back(x);
            return false;
        });
        return v;
    }

    // Quick accept for overlaps_exact: cyclic projections (Kaczmarz / von Neumann) onto the
    // violated slabs, from the centre of the axis box; true when a point satisfies every slab
    // within tau * |n_j|_1 (the enumeration's own acceptance test). A few sweeps: overlapping
    // pairs usually finish here; otherwise the complete vertex enumeration decides.
    static bool feasible_point_search(const std::array<double, axis_count>& l, const std::array<double, axis_count>& h,
                                      double tau) {
        vec x;
        for (std::size_t i = 0; i < D; ++i) x[i] = l[i] + (h[i] - l[i]) / 2;
        auto feasible = [&] {
            for (std::size_t j = 0; j < axis_count; ++j) {
                const double v = geometry::dot(j, x);
                if (v < l[j] - tau * geometry::l1[j] || v > h[j] + tau * geometry::l1[j]) return false;
            }
            return true;
        };
        for (int sweep = 0; sweep < 6; ++sweep) {
            if (feasible()) return true;
            for (std::size_t j = 0; j < axis_count; ++j) {
                const double v = geometry::dot(j, x);
                // Project slightly past a violated plane (1/64 of the slab width) so that the
                // iterate does not creep along a face.
                const double target = v < l[j] ? l[j] + (h[j] - l[j]) / 64 : (v > h[j] ? h[j] - (h[j] - l[j]) / 64 : v);
                if (target == v) continue;
                double n2 = 0;
                for (std::size_t i = 0; i < D; ++i) n2 += static_cast<double>(directions[j][i] * directions[j][i]);
                const double step = (target - v) / n2;
                for (std::size_t i = 0; i < D; ++i) x[i] += step * static_cast<double>(directions[j][i]);
            }
        }
        return feasible();
    }

    // Sets lo/hi from exact-to-rounding extremes mn/mx of slab values of points whose
    // coordinates are at most m in magnitude, widened by the additions' rounding bound
    // (nothing for the axes) plus `extra` (max-norm error of the points), rounded outward.
    void set_padded(const std::array<double, axis_count>& mn, const std::array<double, axis_count>& mx, double m,
                    double extra) {
        const double eps = std::numeric_limits<double>::epsilon();
        for (std::size_t j = 0; j < axis_count; ++j) {
            const double err =
                static_cast<double>(geometry::nnz[j] - 1) * eps * geometry::l1[j] * m + geometry::l1[j] * extra;
            double l = mn[j], h = mx[j];
            if (err > 0) {
                l = std::nextafter(l - err, -std::numeric_limits<double>::infinity());
                h = std::nextafter(h + err, std::numeric_limits<double>::infinity());
            }
            lo[j] = detail_kdop::round_down<T>(l);
            hi[j] = detail_kdop::round_up<T>(h);
        }
    }

    // Sorts points of a convex polygon (2D coordinates) by angle about their centroid.
    static void sort_by_angle(std::vector<std::array<double, 2>>& q) {
        double cx = 0, cy = 0;
        for (const auto& p : q) cx += p[0], cy += p[1];
        cx /= static_cast<double>(q.size());
        cy /= static_cast<double>(q.size());
        std::sort(q.begin(), q.end(), [&](const auto& a, const auto& b) {
            return std::atan2(a[1] - cy, a[0] - cx) < std::atan2(b[1] - cy, b[0] - cx);
        });
    }
    // Area and perimeter of the convex polygon through q (angle-sorted first).
    static std::pair<double, double> polygon_measures(std::vector<std::array<double, 2>> q) {
        if (q.size() < 2) return {0, 0};
        sort_by_angle(q);
        double area = 0, perim = 0;
        for (std::size_t i = 0; i < q.size(); ++i) {
            const auto& a = q[i];
            const auto& b = q[(i + 1) % q.size()];
            area += (a[0] - q[0][0]) * (b[1] - q[0][1]) - (b[0] - q[0][0]) * (a[1] - q[0][1]);
            perim += std::hypot(b[0] - a[0], b[1] - a[1]);
        }
        return {std::abs(area) / 2, perim};
    }

    // (volume, surface area); (area, perimeter) in 2D.
    std::pair<double, double> measures() const {
        if (is_empty()) return {0, 0};
        const local_slabs loc = make_local(*this);
        const auto v = local_vertices(loc);
        if (v.empty()) return {0, 0};
        if constexpr (D == 2) {
            std::vector<std::array<double, 2>> q(v.begin(), v.end());
            return polygon_measures(q);
        } else {
            const double tau = loc.tau;
            vec r{};
            for (const auto& x : v)
                for (std::size_t i = 0; i < D; ++i) r[i] += x[i];
            for (std::size_t i = 0; i < D; ++i) r[i] /= static_cast<double>(v.size());
            double vol = 0, area = 0;
            for (std::size_t j = 0; j < axis_count; ++j) {
                const double nl = geometry::l2(j);
                vec n;
                for (std::size_t i = 0; i < D; ++i) n[i] = static_cast<double>(directions[j][i]) / nl;
                // An orthonormal basis (e1, e2) of the plane.
                vec e1 = std::abs(n[0]) < 0.9 ? vec{0, -n[2], n[1]} : vec{-n[2], 0, n[0]};
                const double e1n = std::sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
                for (auto& c : e1) c /= e1n;
                const vec e2{n[1] * e1[2] - n[2] * e1[1], n[2] * e1[0] - n[0] * e1[2], n[0] * e1[1] - n[1] * e1[0]};
                for (int side = 0; side < 2; ++side) {
                    const double b = side ? loc.h[j] : loc.l[j];
                    std::vector<std::array<double, 2>> q;
                    for (const auto& x : v)
                        if (std::abs(geometry::dot(j, x) - b) <= 4 * tau * geometry::l1[j])
                            q.push_back({x[0] * e1[0] + x[1] * e1[1] + x[2] * e1[2],
                                         x[0] * e2[0] + x[1] * e2[1] + x[2] * e2[2]});
                    if (q.size() < 3) continue;
                    const double fa = polygon_measures(q).first;
                    const double nr = geometry::dot(j, r);
                    const double h = (side ? b - nr : nr - b) / nl;  // outward distance from r
                    vol += fa * std::max(0.0, h) / 3;
                    area += fa;
                }
            }
            return {vol, area};
        }
    }
};

static_assert(bounding_volume<kdop<double, 3, 26>>);
static_assert(bounding_volume<kdop<float, 2, 8>>);

}  // namespace spatial
