#pragma once
// spatial::predicates — orientation tests whose SIGN is exact for double (and float) input,
// the ingredient that makes the convex hulls' topology correct by construction.
//
// Method (Shewchuk 1997, "Adaptive precision floating-point arithmetic and fast robust
// geometric predicates", Discrete & Computational Geometry 18): first evaluate the
// determinant in ordinary floating point together with a forward error bound (a multiple of
// the "permanent", the same expression with absolute values); when |det| exceeds the bound
// its sign is certain. Otherwise (orient_3d_exact) go through Shewchuk's adaptive stages:
// cheap exact certificates of coplanarity first (a shared coordinate, a repeated point, a
// parallelogram: box and lattice corners); then B, the determinant of the rounded
// differences computed exactly, decisive when the differences were exact or when it exceeds
// what their rounding errors can change; C, plus the first-order terms of those errors in
// floating point; D, the determinant from the coordinates themselves, exactly. The exact
// values are expansions (sums of nonoverlapping doubles): products split by Dekker's
// two-product (one fused multiply-add), combined by Shewchuk's Scale-Expansion and
// Fast-Expansion-Sum, each linear in the lengths.
//
// Cost: filtered stage a few dozen flops; certificates a few comparisons; stage B ~60
// two-sums and two-products, C ~40 flops more, D ~4x B (2D exact: ~20). Only exactly
// coplanar points that no certificate recognises, with inexact differences, reach D.
// Guarantee: the returned sign is the sign of the exact real determinant of the given
// doubles, provided no intermediate product overflows or underflows: every coordinate is 0
// or an integer multiple of 2^-340 (so products of three coordinates or differences, and their
// rounding errors, are multiples of 2^-1020, normal numbers) of magnitude at most 2^300 (so no
// sum of such products overflows). on_exact_grid() tells; every double from about 5e-87
// (2^-288) up to 2e90 qualifies, denormals do not. convex_hull fits points off the grid by
// their bounding box rounded outward onto it (to_exact_grid).
// Correct under fused multiply-add contraction too (two_sum has no product; two_product
// uses std::fma explicitly).

#include <cmath>
#include <initializer_list>

namespace spatial::predicates {

// The inputs for which the signs below are exact (see the header comment).
inline constexpr double exact_grid_scale = 0x1p+340;  // 1 / the grid step 2^-340
inline constexpr double exact_limit = 0x1p+300;
inline bool on_exact_grid(double x) {
    const double scaled = x * exact_grid_scale;  // exact: a power of two, no overflow below the limit
    return std::abs(x) <= exact_limit && scaled == std::trunc(scaled);
}
// x rounded onto the grid, down (toward -inf) or up.
inline double to_exact_grid(double x, bool down) {
    const double scaled = x * exact_grid_scale;
    return (down ? std::floor(scaled) : std::ceil(scaled)) / exact_grid_scale;
}

// s + e == a + b exactly, |e| <= ulp(s) / 2 (Knuth's branch-free two-sum).
inline void two_sum(double a, double b, double& s, double& e) {
    s = a + b;
    const double bv = s - a;
    const double av = s - bv;
    e = (a - av) + (b - bv);
}

// p + e == a * b exactly (the error of a product is representable; fma computes it).
inline void two_product(double a, double b, double& p, double& e) {
    p = a * b;
    e = std::fma(a, b, -p);
}

// ---- Expansion arithmetic (Shewchuk 1997, sections 2.4-2.6) ------------------------------
// An expansion is an array of doubles, nonoverlapping, in increasing magnitude, zeros
// eliminated; its value is their exact sum and its sign the sign of its last (largest)
// component. The operations below are linear in the lengths (growing one expansion a double
// at a time, Grow-Expansion, is quadratic).

// x = (a1 + a0) - (b1 + b0) exactly, as up to 4 components (Shewchuk's Two-Two-Diff).
// Returns the length after eliminating zeros.
inline int two_two_diff(double a1, double a0, double b1, double b0, double* x) {
    double i, j, k, x0, x1, x2, x3, low;
    two_sum(a0, -b0, i, x0);  // a0 - b0 = i + x0
    two_sum(a1, i, j, low);   // a1 + i = j + low
    two_sum(low, -b1, k, x1); // low - b1 = k + x1
    two_sum(j, k, x3, x2);    // j + k = x3 + x2
    int n = 0;
    for (const double c : {x0, x1, x2, x3})
        if (c != 0) x[n++] = c;
    return n;
}

// u0 v1 - u1 v0 exactly: the two products split by two_product, then Two-Two-Diff.
inline int exact_cross_2d(double u0, double v1, double u1, double v0, double* x) {
    double p, pe, q, qe;
    two_product(u0, v1, p, pe);
    two_product(u1, v0, q, qe);
    return two_two_diff(p, pe, q, qe, x);
}

// h = e * b exactly (Scale-Expansion-Zeroelim, Theorem 19); h has room for 2 * elen.
inline int scale_expansion(int elen, const double* e, double b, double* h) {
    if (elen == 0 || b == 0) return 0;
    int n = 0;
    double q, hh;
    two_product(e[0], b, q, hh);
    if (hh != 0) h[n++] = hh;
    for (int i = 1; i < elen; ++i) {
        double p1, p0, sum;
        two_product(e[i], b, p1, p0);
        two_sum(q, p0, sum, hh);
        if (hh != 0) h[n++] = hh;
        two_sum(p1, sum, q, hh);
        if (hh != 0) h[n++] = hh;
    }
    if (q != 0) h[n++] = q;
    return n;
}

// h = e + f exactly (Fast-Expansion-Sum-Zeroelim, Theorem 13: needs round-to-nearest-even,
// the IEEE default); components are merged by magnitude and swept with two_sum. h has room
// for elen + flen. Two-sum throughout (Shewchuk uses the cheaper Fast-Two-Sum where the
// order of magnitudes allows; the results are the same).
inline int expansion_sum(int elen, const double* e, int flen, const double* f, double* h) {
    int i = 0, j = 0, n = 0;
    auto next = [&]() {
        if (j == flen || (i < elen && std::abs(e[i]) < std::abs(f[j]))) return e[i++];
        return f[j++];
    };
    if (elen + flen == 0) return 0;
    double q = next();
    while (i < elen || j < flen) {
        double s, hh;
        two_sum(q, next(), s, hh);
        q = s;
        if (hh != 0) h[n++] = hh;
    }
    if (q != 0) h[n++] = q;
    return n;
}

inline int expansion_sign(int n, const double* e) { return n == 0 ? 0 : (e[n - 1] > 0 ? 1 : -1); }

// ---- 2D: sign of (b - a) x (c - a); > 0 counter-clockwise ------------------------------

inline int orient_2d_exact(const double* a, const double* b, const double* c) {
    // Fast exact case: all differences representable (common: lattices, offsets).
    double ux, uy, vx, vy, t0, t1, t2, t3;
    two_sum(b[0], -a[0], ux, t0);
    two_sum(b[1], -a[1], uy, t1);
    two_sum(c[0], -a[0], vx, t2);
    two_sum(c[1], -a[1], vy, t3);
    double x[4];
    if (t0 == 0 && t1 == 0 && t2 == 0 && t3 == 0) return expansion_sign(exact_cross_2d(ux, vy, uy, vx, x), x);
    // General case: (b - a) x (c - a) = b x c - a x c + a x b with u x v = u0 v1 - u1 v0.
    double bc[4], ca[4], ab[4], s[8], t[12];
    const int nbc = exact_cross_2d(b[0], c[1], b[1], c[0], bc);
    const int nca = exact_cross_2d(c[0], a[1], c[1], a[0], ca);
    const int nab = exact_cross_2d(a[0], b[1], a[1], b[0], ab);
    const int ns = expansion_sum(nbc, bc, nca, ca, s);
    return expansion_sign(expansion_sum(ns, s, nab, ab, t), t);
}

inline int orient_2d(const double* a, const double* b, const double* c) {
    const double ux = b[0] - a[0], uy = b[1] - a[1], vx = c[0] - a[0], vy = c[1] - a[1];
    const double l = ux * vy, r = uy * vx, det = l - r;
    // Shewchuk's ccwerrboundA is (3 + 16 eps) eps = 3.3e-16; 4e-16 leaves margin.
    const double bound = 4e-16 * (std::abs(l) + std::abs(r));
    if (det > bound) return 1;
    if (det < -bound) return -1;
    return orient_2d_exact(a, b, c);
}

// ---- 3D: sign of det[b - a, c - a, d - a] = ((b - a) x (c - a)) . (d - a) ----------------
// > 0 when d lies on the side of plane (a, b, c) that the normal (b - a) x (c - a) points to.

// det[x, y, z] = z . (x x y) exactly: three 2x2 minors (up to 4 components each), each
// scaled by a coordinate of z (8), summed (24). Returns the length; h has room for 24.
inline int exact_det_3d(const double* x, const double* y, const double* z, double* h) {
    double m[4], s0[8], s1[8], s2[8], t[16];
    const int n0 = scale_expansion(exact_cross_2d(x[1], y[2], x[2], y[1], m), m, z[0], s0);
    const int n1 = scale_expansion(exact_cross_2d(x[2], y[0], x[0], y[2], m), m, z[1], s1);
    const int n2 = scale_expansion(exact_cross_2d(x[0], y[1], x[1], y[0], m), m, z[2], s2);
    const int nt = expansion_sum(n0, s0, n1, s1, t);
    return expansion_sum(nt, t, n2, s2, h);
}

// Exact certificates of coplanarity that cost a few comparisons, tried before any
// expansion: the exactly coplanar quadruples that dominate real use are a box's or a
// lattice's corners (a face: one coordinate shared by all four; a diagonal rectangle: a
// parallelogram) and repeated points.
inline bool share_a_coordinate(const double* a, const double* b, const double* c, const double* d) {
    for (int i = 0; i < 3; ++i)
        if (a[i] == b[i] && a[i] == c[i] && a[i] == d[i]) return true;  // a zero column: det = 0
    return false;
}
inline bool same_point(const double* p, const double* q) { return p[0] == q[0] && p[1] == q[1] && p[2] == q[2]; }
// p + q == r + s exactly (the diagonals pq and rs share their midpoint): two_sum's (sum,
// error) pair is a function of the exact real sum, so equal pairs mean equal sums.
inline bool same_exact_sum(const double* p, const double* q, const double* r, const double* s) {
    for (int i = 0; i < 3; ++i) {
        double s0, e0, s1, e1;
        two_sum(p[i], q[i], s0, e0);
        two_sum(r[i], s[i], s1, e1);
        if (s0 != s1 || e0 != e1) return false;
    }
    return true;
}
inline bool certainly_coplanar(const double* a, const double* b, const double* c, const double* d) {
    return share_a_coordinate(a, b, c, d) || same_point(a, b) || same_point(a, c) || same_point(a, d) || same_point(b, c) ||
           same_point(b, d) || same_point(c, d) || same_exact_sum(a, b, c, d) || same_exact_sum(a, c, b, d) ||
           same_exact_sum(a, d, b, c);
}

// The last stage: det[b - a, c - a, d - a] by multilinearity from the coordinates
// themselves, det[b,c,d] - det[a,c,d] + det[a,b,d] - det[a,b,c] (a swap of two rows changes
// the sign: -det[a,c,d] = det[c,a,d], -det[a,b,c] = det[b,a,c]); up to 96 components.
inline int orient_3d_from_coordinates(const double* a, const double* b, const double* c, const double* d) {
    double e0[24], e1[24], e2[24], e3[24], s01[48], s23[48], all[96];
    const int n0 = exact_det_3d(b, c, d, e0);
    const int n1 = exact_det_3d(c, a, d, e1);
    const int n2 = exact_det_3d(a, b, d, e2);
    const int n3 = exact_det_3d(b, a, c, e3);
    const int n01 = expansion_sum(n0, e0, n1, e1, s01);
    const int n23 = expansion_sum(n2, e2, n3, e3, s23);
    return expansion_sign(expansion_sum(n01, s01, n23, s23, all), all);
}

// det[x, y, z] in floating point, and its permanent (the same sum with absolute values).
inline double det_3d(const double* x, const double* y, const double* z) {
    return z[0] * (x[1] * y[2] - x[2] * y[1]) + z[1] * (x[2] * y[0] - x[0] * y[2]) + z[2] * (x[0] * y[1] - x[1] * y[0]);
}
inline double permanent_3d(const double* x, const double* y, const double* z) {
    using std::abs;
    return abs(z[0]) * (abs(x[1] * y[2]) + abs(x[2] * y[1])) + abs(z[1]) * (abs(x[2] * y[0]) + abs(x[0] * y[2])) +
           abs(z[2]) * (abs(x[0] * y[1]) + abs(x[1] * y[0]));
}

// Error-bound constants of the adaptive stages, in units of eps = 2^-53 (Shewchuk's
// o3derrboundB = (3 + 28 eps) eps, o3derrboundC = (26 + 288 eps) eps^2 and resulterrbound
// = (3 + 8 eps) eps), each with margin for this evaluation order.
inline constexpr double orient_3d_bound_b = 4e-16;     // x permanent
inline constexpr double orient_3d_bound_c = 8e-31;     // x permanent (64 eps^2)
inline constexpr double orient_3d_bound_result = 4e-16;  // x |stage B estimate|

// The sign of det[b - a, c - a, d - a], exactly: Shewchuk's adaptive stages B-D after the
// certificates above. B: the differences u, v, w rounded to doubles; their determinant
// exactly, as an expansion; its sign is the answer when every difference was exact or when
// it exceeds the bound on what the differences' rounding errors (tails) can change. C: add
// the terms of first order in the tails in floating point; the rest is second order. D: the
// whole determinant from the coordinates. Stage D runs only for exactly or nearly coplanar
// points whose differences do not round exactly.
inline int orient_3d_exact(const double* a, const double* b, const double* c, const double* d) {
    if (certainly_coplanar(a, b, c, d)) return 0;
    double u[3], v[3], w[3], ut[3], vt[3], wt[3];
    bool diffs_exact = true;
    for (int i = 0; i < 3; ++i) {
        two_sum(b[i], -a[i], u[i], ut[i]);
        two_sum(c[i], -a[i], v[i], vt[i]);
        two_sum(d[i], -a[i], w[i], wt[i]);
        diffs_exact = diffs_exact && ut[i] == 0 && vt[i] == 0 && wt[i] == 0;
    }
    double h[24];
    const int n = exact_det_3d(u, v, w, h);
    if (diffs_exact) return expansion_sign(n, h);
    double estimate = 0;  // Shewchuk's estimate(): the components summed from the smallest
    for (int i = 0; i < n; ++i) estimate += h[i];
    const double perm = permanent_3d(u, v, w);
    if (std::abs(estimate) > orient_3d_bound_b * perm) return estimate > 0 ? 1 : -1;
    const double det = estimate + (det_3d(ut, v, w) + det_3d(u, vt, w) + det_3d(u, v, wt));
    if (std::abs(det) > orient_3d_bound_c * perm + orient_3d_bound_result * std::abs(estimate)) return det > 0 ? 1 : -1;
    return orient_3d_from_coordinates(a, b, c, d);
}

// Error-bound constant of the filtered 3D determinant: Shewchuk's o3derrboundA is
// (7 + 56 eps) eps = 7.8e-16 times the permanent; 1e-15 leaves margin. It applies to any
// evaluation that takes differences from one base point, forms the three 2x2 minors of two
// difference vectors and dots them with the third (the structure both users below share).
inline constexpr double orient_3d_filter = 1e-15;

inline int orient_3d(const double* a, const double* b, const double* c, const double* d) {
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double w[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
    const double det = det_3d(u, v, w);
    const double bound = orient_3d_filter * permanent_3d(u, v, w);
    if (det > bound) return 1;
    if (det < -bound) return -1;
    return orient_3d_exact(a, b, c, d);
}

// Are a, b, c exactly collinear (in 3D)? True iff all three coordinate projections are.
inline bool collinear_3d(const double* a, const double* b, const double* c) {
    for (int k = 0; k < 3; ++k) {
        const int i = (k + 1) % 3, j = (k + 2) % 3;
        const double pa[2] = {a[i], a[j]}, pb[2] = {b[i], b[j]}, pc[2] = {c[i], c[j]};
        if (orient_2d(pa, pb, pc) != 0) return false;
    }
    return true;
}

}  // namespace spatial::predicates
