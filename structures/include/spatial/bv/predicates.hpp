#pragma once
// spatial::predicates — orientation tests whose SIGN is exact for double (and float) input,
// the ingredient that makes the convex hulls' topology correct by construction.
//
// Method (Shewchuk 1997, "Adaptive precision floating-point arithmetic and fast robust
// geometric predicates", Discrete & Computational Geometry 18): first evaluate the
// determinant in ordinary floating point together with a forward error bound (a multiple of
// the "permanent", the same expression with absolute values); when |det| exceeds the bound
// its sign is certain. Otherwise re-evaluate exactly: every term of the determinant is
// written as a sum of products of input coordinates, each product is split into an exact
// sum of doubles (Dekker's two-product, here with one fused multiply-add), and the sign of
// the exact sum of all pieces is found by growing a nonoverlapping expansion with
// Knuth's two-sum (Shewchuk's Grow-Expansion). The exact stage is simpler and slower than
// Shewchuk's adaptive stages B-D, which is fine: it runs only on (near-)degenerate input.
//
// Cost: filtered stage a few dozen flops; exact stage ~100 two-sums (2D: ~12).
// Guarantee: the returned sign is the sign of the exact real determinant of the given
// doubles, provided no intermediate product overflows or underflows: every coordinate is 0
// or an integer multiple of 2^-340 (so products of three coordinates or differences, and their
// rounding errors, are multiples of 2^-1020, normal numbers) of magnitude at most 2^300 (so no
// sum of such products overflows). on_exact_grid() tells; every double from about 5e-87
// (2^-288) up to 2e90 qualifies, denormals do not. convex_hull fits points off the grid by
// their bounding box rounded outward onto it (to_exact_grid).
// Correct under fused multiply-add contraction too (two_sum has no product; two_product
// uses std::fma explicitly).

#include <array>
#include <cmath>
#include <cstddef>

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

// The exact sum of a stream of doubles as a nonoverlapping expansion (components in
// increasing magnitude, zeros eliminated); the sign is the sign of the largest component.
template <std::size_t Capacity>
class exact_sum {
public:
    void add(double b) {
        double q = b;
        std::size_t m = 0;
        for (std::size_t i = 0; i < n_; ++i) {
            double s, e;
            two_sum(q, c_[i], s, e);
            q = s;
            if (e != 0) c_[m++] = e;
        }
        if (q != 0) c_[m++] = q;
        n_ = m;
    }
    // a * b, exactly.
    void add_product(double a, double b) {
        double p, e;
        two_product(a, b, p, e);
        add(e);
        add(p);
    }
    // sign * a * b * c, exactly (a * b = p + e exactly, then each part times c).
    void add_product(double a, double b, double c, double sign) {
        double p, e, p1, e1, p2, e2;
        two_product(a, b, p, e);
        two_product(p, c, p1, e1);
        two_product(e, c, p2, e2);
        add(sign * e2);
        add(sign * p2);
        add(sign * e1);
        add(sign * p1);
    }
    int sign() const { return n_ == 0 ? 0 : (c_[n_ - 1] > 0 ? 1 : -1); }

private:
    double c_[Capacity];
    std::size_t n_ = 0;
};

// ---- 2D: sign of (b - a) x (c - a); > 0 counter-clockwise ------------------------------

inline int orient_2d_exact(const double* a, const double* b, const double* c) {
    // Fast exact case: all differences representable (common: lattices, offsets).
    double ux, uy, vx, vy, t0, t1, t2, t3;
    two_sum(b[0], -a[0], ux, t0);
    two_sum(b[1], -a[1], uy, t1);
    two_sum(c[0], -a[0], vx, t2);
    two_sum(c[1], -a[1], vy, t3);
    exact_sum<32> s;
    if (t0 == 0 && t1 == 0 && t2 == 0 && t3 == 0) {
        s.add_product(ux, vy);
        s.add_product(-uy, vx);
        return s.sign();
    }
    // General case: (b - a) x (c - a) = b x c - a x c + a x b with u x v = u0 v1 - u1 v0.
    s.add_product(b[0], c[1]);
    s.add_product(-b[1], c[0]);
    s.add_product(-a[0], c[1]);
    s.add_product(a[1], c[0]);
    s.add_product(a[0], b[1]);
    s.add_product(-a[1], b[0]);
    return s.sign();
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

inline int orient_3d_exact(const double* a, const double* b, const double* c, const double* d) {
    double u[3], v[3], w[3], tail[9];
    for (int i = 0; i < 3; ++i) {
        two_sum(b[i], -a[i], u[i], tail[i]);
        two_sum(c[i], -a[i], v[i], tail[3 + i]);
        two_sum(d[i], -a[i], w[i], tail[6 + i]);
    }
    bool diffs_exact = true;
    for (double t : tail) diffs_exact = diffs_exact && t == 0;
    exact_sum<160> s;
    // det3(x, y, z) = x . (y x z) as six signed triple products.
    auto add_det3 = [&s](const double* x, const double* y, const double* z, double sign) {
        s.add_product(x[0], y[1], z[2], sign);
        s.add_product(x[0], y[2], z[1], -sign);
        s.add_product(x[1], y[2], z[0], sign);
        s.add_product(x[1], y[0], z[2], -sign);
        s.add_product(x[2], y[0], z[1], sign);
        s.add_product(x[2], y[1], z[0], -sign);
    };
    if (diffs_exact) {
        add_det3(u, v, w, 1);
        return s.sign();
    }
    // Multilinearity: det[b - a, c - a, d - a] = det[b,c,d] - det[a,c,d] + det[a,b,d] - det[a,b,c].
    add_det3(b, c, d, 1);
    add_det3(a, c, d, -1);
    add_det3(a, b, d, 1);
    add_det3(a, b, c, -1);
    return s.sign();
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
    const double m0l = u[1] * v[2], m0r = u[2] * v[1];
    const double m1l = u[2] * v[0], m1r = u[0] * v[2];
    const double m2l = u[0] * v[1], m2r = u[1] * v[0];
    const double det = w[0] * (m0l - m0r) + w[1] * (m1l - m1r) + w[2] * (m2l - m2r);
    const double perm = std::abs(w[0]) * (std::abs(m0l) + std::abs(m0r)) + std::abs(w[1]) * (std::abs(m1l) + std::abs(m1r)) +
                        std::abs(w[2]) * (std::abs(m2l) + std::abs(m2r));
    const double bound = orient_3d_filter * perm;
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
