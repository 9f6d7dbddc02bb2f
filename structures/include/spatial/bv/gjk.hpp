#pragma once
// spatial::gjk_intersect — do two convex sets intersect? The Gilbert-Johnson-Keerthi
// distance algorithm (Gilbert, Johnson & Keerthi 1988, "A fast procedure for computing the
// distance between complex objects in three-dimensional space", IEEE J. Robotics and
// Automation 4(2)) on the Minkowski difference M = A - B, driven only by support functions,
// so any convex type (hull, box, ellipsoid, capsule...) can reuse it.
//
//   support_a(dir) -> std::array<double, D>: a point of A maximising dir . x (dir is not
//   normalised and never zero); support_b likewise for B.
//
// Each iteration keeps a simplex of support points of M and its point v closest to the
// origin (Johnson's sub-algorithm, here by trying every face of the simplex: at most 15 in
// 3D); w = the support point of M in direction -v gives the certificate
//   min over M of v . x = v . w,
// so v . w > tolerance |v| (plus the rounding of that dot product) PROVES that the sets are
// more than `tolerance` apart. That (along v, or, when GJK stalls, along the normals of the
// candidate facets of M spanned by the simplex, which stay accurate when |v| is tiny against
// the coordinates) is the only way to return false: no false negatives.
// It returns true when |v| <= tolerance (v is a point of M, so the distance is <= |v|), when
// the origin is inside a full simplex, or when GJK stalls without a certificate: v stops
// improving (|v|^2 - v . w <= 1e-12 |v|^2, a repeated support point, or |v| not decreasing:
// then |v| is the distance up to rounding and the failed certificates bound it by about the
// tolerance), or after max_iterations (the answer errs toward "intersect"). So a "true" may
// be a false positive only for sets closer than about the tolerance plus the rounding of
// the support coordinates (relative ~1e-15 of them).
//
// Cost: O(iterations * (cost of two supports + 2^(D+1) small solves)); iterations are
// typically 3-10 for polytopes. Touching sets (distance 0) return true for any tolerance
// >= 0 in exact arithmetic; give tolerance a few ulps of the coordinates' magnitude so that
// rounding in the supports cannot turn contact into a certified gap.

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <limits>
#include <utility>

#include "spatial/bv/gauss_jordan.hpp"

namespace spatial {

namespace detail {

template <std::size_t D>
double gjk_dot(const std::array<double, D>& a, const std::array<double, D>& b) {
    double s = 0;
    for (std::size_t i = 0; i < D; ++i) s += a[i] * b[i];
    return s;
}

// Closest point to the origin of the convex hull of s[0..k), by checking the affine
// projection of the origin onto every face (subset); a face whose projection has all
// barycentric coordinates > 0 is a candidate, the nearest candidate wins (it is the
// true closest point: the closest point lies in the relative interior of exactly one face).
// Affinely dependent faces are skipped (a smaller face gives the same point). The simplex is
// reduced to the winning face. Returns false only if nothing was valid (cannot happen:
// single points are always valid).
template <std::size_t D>
bool gjk_closest(std::array<std::array<double, D>, D + 1>& s, std::size_t& k, std::array<double, D>& v) {
    double best = std::numeric_limits<double>::infinity();
    unsigned best_mask = 0;
    std::array<double, D> best_v{};
    for (unsigned mask = 1; mask < (1u << k); ++mask) {
        std::size_t idx[D + 1] = {}, m = 0;
        for (std::size_t i = 0; i < k; ++i)
            if (mask & (1u << i)) idx[m++] = i;
        const auto& s0 = s[idx[0]];
        std::array<double, D> p = s0;
        if (m > 1) {
            // Minimise |s0 + sum_j mu_j e_j|^2: Gram system G mu = -E^T s0.
            std::array<std::array<double, D>, D> e{};
            double g[D][D + 1];
            const std::size_t r = m - 1;
            double scale = 0;
            for (std::size_t j = 0; j < r; ++j) {
                for (std::size_t d = 0; d < D; ++d) e[j][d] = s[idx[j + 1]][d] - s0[d];
                scale = std::max(scale, gjk_dot(e[j], e[j]));
            }
            for (std::size_t i = 0; i < r; ++i) {
                for (std::size_t j = 0; j < r; ++j) g[i][j] = gjk_dot(e[i], e[j]);
                g[i][r] = -gjk_dot(e[i], s0);
            }
            const bool singular =
                !(scale > 0) || !gauss_jordan(g, r, [&](double pivot) { return std::abs(pivot) > 1e-13 * scale; });
            if (singular) continue;
            double mu_sum = 0;
            bool inside = true;
            for (std::size_t j = 0; j < r; ++j) {
                const double mu = g[j][r] / g[j][j];
                inside = inside && mu > 0;
                mu_sum += mu;
                for (std::size_t d = 0; d < D; ++d) p[d] += mu * e[j][d];
            }
            if (!inside || !(1 - mu_sum > 0)) continue;
        }
        const double dist = gjk_dot(p, p);
        if (dist < best) best = dist, best_mask = mask, best_v = p;
    }
    if (best_mask == 0) return false;
    std::size_t m = 0;
    for (std::size_t i = 0; i < k; ++i)
        if (best_mask & (1u << i)) s[m++] = s[i];
    k = m;
    v = best_v;
    return true;
}

}  // namespace detail

// The three outcomes: the sets are within `tolerance` of each other (proved: a point of M
// within tolerance of the origin, or the origin inside a simplex of M), a gap larger than
// `tolerance` is certified, or GJK stalled without either proof (|v| is then the distance up
// to rounding; callers with more structure, e.g. facet planes, can try other axes).
enum class gjk_outcome { intersect, separated, undecided };

template <std::size_t D, class SupportA, class SupportB>
gjk_outcome gjk_classify(SupportA&& support_a, SupportB&& support_b, std::array<double, D> initial_direction, double tolerance,
                         int max_iterations = 128) {
    using vec = std::array<double, D>;
    constexpr double eps = std::numeric_limits<double>::epsilon();
    auto support = [&](const vec& dir) {  // support point of M = A - B in direction dir
        vec neg;
        for (std::size_t i = 0; i < D; ++i) neg[i] = -dir[i];
        const vec a = support_a(dir), b = support_b(neg);
        vec w;
        for (std::size_t i = 0; i < D; ++i) w[i] = a[i] - b[i];
        return w;
    };
    bool nonzero = false;
    for (double x : initial_direction) nonzero = nonzero || x != 0;
    if (!nonzero) initial_direction[0] = 1;
    std::array<vec, D + 1> s{};
    std::size_t k = 1;
    s[0] = support(initial_direction);
    vec v = s[0];
    // The certificate: every x in M has n . x >= n . w, w the support point in direction -n;
    // n . w above tolerance |n| (plus the dot's rounding) proves a larger gap.
    auto certified = [&](const vec& n, const vec& w) {
        const double nn = std::sqrt(detail::gjk_dot(n, n)), wn = std::sqrt(detail::gjk_dot(w, w));
        return detail::gjk_dot(n, w) - 2 * double(D) * eps * nn * wn > tolerance * nn;
    };
    // When v is tiny against the coordinates (nearly touching parallel features), its
    // direction carries an absolute rounding error of ~eps |coordinates|; if the separating
    // directions form a thin cone (a facet of M nearest the origin), the certificate along v
    // then fails although the gap is well above the tolerance, and GJK stops progressing.
    // The normal of a candidate facet of M computed from its edge vectors has a relative
    // error of eps only: try every facet spanned by D points of the simplex and the last
    // support point (an edge in 2D, a triangle in 3D), oriented toward v.
    auto facet_certified = [&](const vec& w) {
        std::array<vec, D + 2> p;
        std::size_t m = 0;
        for (std::size_t i = 0; i < k; ++i) p[m++] = s[i];
        p[m++] = w;
        for (unsigned mask = 0; mask < (1u << m); ++mask) {
            if (static_cast<std::size_t>(std::popcount(mask)) != D) continue;
            vec q[D];
            std::size_t c = 0;
            for (std::size_t i = 0; i < m; ++i)
                if (mask & (1u << i)) q[c++] = p[i];
            vec n{};
            if constexpr (D == 2) {
                n = {-(q[1][1] - q[0][1]), q[1][0] - q[0][0]};
            } else if constexpr (D == 3) {
                const vec e1{q[1][0] - q[0][0], q[1][1] - q[0][1], q[1][2] - q[0][2]};
                const vec e2{q[2][0] - q[0][0], q[2][1] - q[0][1], q[2][2] - q[0][2]};
                n = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
            } else {
                return false;
            }
            const double side = detail::gjk_dot(n, v);
            if (!(side != 0) || !std::isfinite(side)) continue;
            if (side < 0)
                for (double& x : n) x = -x;
            vec neg;
            for (std::size_t i = 0; i < D; ++i) neg[i] = -n[i];
            if (certified(n, support(neg))) return true;
        }
        return false;
    };
    double previous = std::numeric_limits<double>::infinity();
    vec w{};
    auto stalled = [&] { return facet_certified(w) ? gjk_outcome::separated : gjk_outcome::undecided; };
    for (int it = 0; it < max_iterations; ++it) {
        const double vv = detail::gjk_dot(v, v);
        if (vv <= tolerance * tolerance) return gjk_outcome::intersect;
        vec neg;
        for (std::size_t i = 0; i < D; ++i) neg[i] = -v[i];
        w = support(neg);
        if (certified(v, w)) return gjk_outcome::separated;
        bool repeated = false;
        for (std::size_t i = 0; i < k; ++i) repeated = repeated || s[i] == w;
        // No progress (|v| must decrease strictly): v is, up to rounding, the closest point
        // of M, whose distance the failed certificates bound by about the tolerance.
        if (repeated || vv - detail::gjk_dot(v, w) <= 1e-12 * vv || !(vv < previous)) return stalled();
        previous = vv;
        s[k++] = w;
        if (!detail::gjk_closest<D>(s, k, v)) return stalled();
        if (k == D + 1) return gjk_outcome::intersect;  // the origin is inside a full simplex
    }
    return stalled();
}

// true unless a gap larger than `tolerance` is certified (stalls count as intersecting).
template <std::size_t D, class SupportA, class SupportB>
bool gjk_intersect(SupportA&& support_a, SupportB&& support_b, std::array<double, D> initial_direction, double tolerance,
                   int max_iterations = 128) {
    return gjk_classify<D>(support_a, support_b, initial_direction, tolerance, max_iterations) != gjk_outcome::separated;
}

}  // namespace spatial
