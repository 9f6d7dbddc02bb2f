#pragma once
// spatial::ellipsoid<T, D> — bounding ellipsoid (an ellipse in 2D): a centre c, an
// orthonormal frame (rows of `axes`, u_k) and semi-axis lengths a_k:
//     x inside  <=>  sum_k ((x - c) . u_k / a_k)^2 <= 1.
// Every query evaluates exactly this form with the STORED (rounded) u_k and a_k, so the
// stored numbers define the set; the frame is orthonormal to T's precision.
//
// Fitting methods (n points), both containing every input point in floating point:
//   fit_pca — principal axes (spatial::principal_axes; Gottschalk, Lin & Manocha 1996), the
//     variance along each axis re-measured directly (accurate for thin sets), then scaled:
//     semi-axes sigma_k * sqrt(max_p sum_k (y_k / sigma_k)^2). O(n D^2). No tightness
//     guarantee. Measured volume / MVEE volume on 1e5 points (2D, 3D): uniform box 1.01,
//     1.05; gaussian 1.36, 1.32; a tight cluster plus 1% spread-out points 2.3, 2.8.
//   fit_khachiyan(pts, tolerance = 1e-3) — the minimum-volume enclosing ellipsoid (MVEE) to
//     a relative VOLUME tolerance: Khachiyan's barycentric coordinate ascent (Khachiyan
//     1996, "Rounding of polytopes in the real number model of computation") with the
//     Wolfe-Atwood away steps of Todd & Yildirim 2007 ("On Khachiyan's algorithm for the
//     computation of minimum-volume enclosing ellipsoids") and the Kumar & Yildirim 2005
//     initialisation (extreme points along fixed directions), in double with Eigen:
//       * affine invariance: the points are first whitened in the PCA frame (unit
//         variance per axis), so thin and offset sets are well conditioned;
//       * active set: the ascent runs on a small set of points (initially the extreme
//         points along 2, 8 or 26 directions); then ALL points are checked and the worst
//         violators are added (at most doubling the set per round), until every point
//         satisfies the certificate below. Only O(n) passes touch the full set, so this is
//         safe without a convex hull and O(n) per round in practice (a few rounds).
//     Guarantee (a posteriori, checked on all points): with weights u on the active set,
//     centre c(u) = sum u_i z_i and Sigma(u) = sum u_i z_i z_i^T - c c^T, every feasible
//     ellipsoid has volume >= vol_unit * sqrt(m^m det Sigma(u)) (weak duality: for an
//     enclosing {(z - c)^T H (z - c) <= 1}, tr(H Sigma) <= 1, then AM-GM), and the returned
//     ellipsoid is {(z - c)^T (m Sigma)^-1 (z - c) <= s} with s = the max over all points,
//     of volume exactly s^(m/2) times that bound. The loop stops when s^(m/2) <= 1 +
//     tolerance, so: volume <= (1 + tolerance) * volume(MVEE), after the final scaling that
//     makes every point contained (up to rounding of the result to T: a few ulps per
//     semi-axis; for float, a centre far from the origin or a thin shape amplifies that).
//     tolerance must be > 0 (else std::invalid_argument) and is clamped to [1e-12, 1]. Cost:
//     O(n) per round plus the ascent on the active set (O(active * iterations), iterations ~ m
//     / tolerance in the worst case, usually far fewer: 6-5000 iterations on 19-26 active
//     points for tolerance 1e-3 on the sets measured below). If the iteration cap (200000
//     steps in total, ~0.1 s) is reached the result still contains every point but the bound
//     is not certified (see khachiyan_report::certified_ratio). That happens for small
//     tolerances on sets that lie almost exactly on an ellipsoid's surface (e.g. surface
//     samples rounded to float: nearly every point is active and the ascent zig-zags): there,
//     tolerances below the points' distance from a common ellipsoid (~1e-7 relative) are not
//     reached. Measured (double, 3D, 2 shared cores): 1e5 points 6-10 ms, 1e6 points 60-120 ms
//     (uniform cube, gaussian, sphere surface), against fit_pca's 2 / 17-23 ms.
//   Degenerate input: an axis whose spread is <= 1e-12 of the largest spread (all points
//     equal, collinear, coplanar) is THIN: the MVEE does not exist (its volume infimum is
//     0); the fit works in the affine hull (dimension m < D) and gives each thin axis the
//     semi-axis max(1e-9 * the largest semi-axis, 10 sqrt(D) * the largest offset of any
//     point along it as measured in the rounded frame, a tiny absolute floor). The volume
//     guarantee then holds for the fitted cross-section only. One point or all equal: a
//     ball of radius 16 ulps of |c| (or the smallest normal T) at that point. Never NaN.
//     Coordinates offset by 1e8 and spreads of 1e-12 are handled by working in double
//     relative to the mean. NaN/inf input throws std::invalid_argument.
//
// Queries:
//   overlaps   EXACT up to rounding, by the Perram-Wertheim contact function (Perram &
//     Wertheim 1985, "Statistical mechanics of hard ellipsoids. I. Overlap algorithm and
//     the contact function", J. Comput. Phys. 58): with shape matrices A, B and
//     r = c_B - c_A, F(l) = l (1 - l) r^T [(1 - l) A^-1 + l B^-1]^-1 r is concave on
//     [0, 1] and the ellipsoids intersect iff max F <= 1 (= 1: touching). Evaluated
//     after mapping one ellipsoid to the unit ball (choosing the one that keeps the other's
//     image best conditioned): the other becomes c' + G z, |z| <= 1, and with the SVD
//     G = U diag(mu) V^T, w = (U^T c')^2, F(l) = l (1 - l) sum_k w_k / (1 - l + l mu_k^2);
//     F' = 0 is bracketed by the per-term maxima l_k = 1 / (1 + mu_k) and found by a
//     safeguarded Newton iteration (bisection when a step leaves the bracket). F is concave,
//     so every iterate x bounds max F from both sides: F(x) <= max F <= F(x) + F'(x) (end
//     of the bracket - x), and overlaps() stops as soon as the decision is certain. The
//     pair is reported disjoint only on a certificate F(x) > 1 + tol, tol = 1e-12 plus a
//     first-order bound of the rounding of G and c' (~1e-13 for moderate aspect ratios;
//     it grows with the squared aspect ratio for very thin ellipsoids): no false
//     negatives, false positives only within that band; touching overlaps.
//     Bounding/inscribed-ball early exits first. O(D^3). Measured (double, 3D): 90 ns per
//     pair on random pairs, ~0.6 us when the balls cannot decide. contact_function()
//     exposes max F (converged), its certified upper bound and the tolerance.
//   contains   O(D^2). ray_interval: the line in the unit-ball frame, a robust quadratic
//     (perpendicular offset form, as in sphere.hpp). distance_lower_bound: the EXACT
//     point-ellipsoid distance by Eberly's bisection on the secular equation (Eberly 2013,
//     "Distance from a point to an ellipse, an ellipsoid, or a hyperellipsoid"), evaluated
//     through the Lagrangian dual g(t) = sum y_k^2 t / (a_k^2 + t) - t, which is <= the
//     squared distance for EVERY t >= 0 (weak duality) and equal to it at the root: so the
//     result is a valid lower bound whatever the bisection's accuracy; minus a rounding
//     margin. merged: the smallest of three candidates (each input's frame, and the PCA
//     frame of the 4D semi-axis end points of both), each scaled by a certified bound on
//     max over the other ellipsoid of its quadratic form: max_{|z|<=1} |g + H z|^2 <=
//     nu + |g|^2 + g^T H (nu I - H^T H)^-1 H^T g for every nu > |H|^2 (Lagrangian duality),
//     minimised over nu by golden section. Contains both; not the minimum (equal to an
//     input when the other is inside it). transformed: exact (move the centre, rotate the
//     frame) up to a certified rounding pad, plus, as aabb and sphere do, room for the
//     rounding of xf.apply in T (see inflated()), so it contains xf.apply(p) for p inside.
//   volume: unit-ball volume * prod a_k. surface_area: exact — 2D the perimeter
//     4 a E(e) (std::comp_ellint_2); 3D Legendre's formula with incomplete elliptic
//     integrals (std::ellint_1, std::ellint_2): for a >= b >= c, cos(phi) = c / a,
//     k^2 = (1 - c^2/b^2) / (1 - c^2/a^2),
//     S = 2 pi c^2 + 2 pi a b (E(k, phi) sin^2(phi) + F(k, phi) cos^2(phi)) / sin(phi).
//
// Empty ellipsoid: negative semi-axes (default constructed).

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <numbers>
#include <span>
#include <stdexcept>
#include <vector>

#include "spatial/bv/bounding_volume.hpp"
#include "spatial/bv/rounding.hpp"
#include "spatial/bv/principal_axes.hpp"
#include "spatial/core/input_checks.hpp"
#include "spatial/core/point.hpp"
#include "spatial/core/rigid_transform.hpp"

namespace spatial {

// What fit_khachiyan did (optional output).
struct khachiyan_report {
    std::size_t rounds = 0;            // active-set rounds (each: ascent + one pass over all points)
    std::size_t active_points = 0;     // final active set size
    std::size_t iterations = 0;        // ascent steps in total
    std::size_t fitted_dimension = 0;  // m: D minus the thin axes
    // volume / (lower bound on the MVEE volume) before rounding to T; <= 1 + tolerance unless
    // the iteration cap was hit. 1 for m = 0.
    double certified_ratio = 1;
};

namespace detail_ellipsoid {

template <std::size_t D>
using vec = std::array<double, D>;

inline double unit_ball_volume(std::size_t d) {
    return std::pow(std::numbers::pi, static_cast<double>(d) / 2) / std::tgamma(static_cast<double>(d) / 2 + 1);
}

using detail_rounding::round_down;  // spatial/bv/rounding.hpp
using detail_rounding::round_up;

// One-sided Jacobi SVD (Hestenes 1958) of an n x n matrix g (n <= 4), column-major in
// g[col][row]: on return g's columns are U_k * mu_k (mutually orthogonal), mu[k] their
// norms, v the accumulated right rotations (g_in v = g_out). High relative accuracy for
// column-scaled well-conditioned matrices (Demmel & Veselic 1992), which is how the fits
// use it (graded semi-axes).
template <std::size_t N, bool want_v = true>
void one_sided_jacobi(std::size_t n, std::array<std::array<double, N>, N>& g, std::array<double, N>& mu,
                      std::array<std::array<double, N>, N>& v) {
    if constexpr (want_v)
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = 0; j < n; ++j) v[i][j] = i == j ? 1.0 : 0.0;
    constexpr double eps2 = std::numeric_limits<double>::epsilon() * std::numeric_limits<double>::epsilon();
    for (int sweep = 0; sweep < 60; ++sweep) {
        bool rotated = false;
        for (std::size_t p = 0; p < n; ++p)
            for (std::size_t q = p + 1; q < n; ++q) {
                double alpha = 0, beta = 0, gamma = 0;
                for (std::size_t r = 0; r < n; ++r) {
                    alpha += g[p][r] * g[p][r];
                    beta += g[q][r] * g[q][r];
                    gamma += g[p][r] * g[q][r];
                }
                // Converged pair: orthogonal to working precision (Hestenes' criterion).
                if (gamma * gamma <= eps2 * alpha * beta) continue;
                rotated = true;
                const double zeta = (beta - alpha) / (2 * gamma);
                const double t = (zeta >= 0 ? 1.0 : -1.0) / (std::abs(zeta) + std::sqrt(1 + zeta * zeta));
                const double c = 1 / std::sqrt(1 + t * t), s = c * t;
                for (std::size_t r = 0; r < n; ++r) {
                    const double gp = g[p][r], gq = g[q][r];
                    g[p][r] = c * gp - s * gq;
                    g[q][r] = s * gp + c * gq;
                }
                if constexpr (want_v)
                    for (std::size_t r = 0; r < n; ++r) {
                        const double vp = v[r][p], vq = v[r][q];
                        v[r][p] = c * vp - s * vq;
                        v[r][q] = s * vp + c * vq;
                    }
            }
        if (!rotated) break;
    }
    for (std::size_t k = 0; k < n; ++k) {
        double s = 0;
        for (std::size_t r = 0; r < n; ++r) s += g[k][r] * g[k][r];
        mu[k] = std::sqrt(s);
    }
}

// Certified upper bound of max_{|z| <= 1} |g + H z|^2 (H is D x D, h[col][row]):
// Lagrangian duality gives, for every nu > |H|_2^2,
//   max <= phi(nu) = nu + |g|^2 + sum_k mu_k^2 gamma_k^2 / (nu - mu_k^2),
// with H = U diag(mu) V^T and gamma = U^T g; phi is convex, minimised by golden section
// over (|H|^2, |H|^2 + |H| |g|] (phi there is <= (|H| + |g|)^2). Relative rounding margin.
template <std::size_t D>
double max_quadratic_over_ball(const vec<D>& g, std::array<std::array<double, D>, D> h) {
    std::array<double, D> mu;
    std::array<std::array<double, D>, D> v;
    one_sided_jacobi<D, false>(D, h, mu, v);
    double g2 = 0, hmax = 0;
    for (std::size_t i = 0; i < D; ++i) g2 += g[i] * g[i];
    std::array<double, D> gam{};
    for (std::size_t k = 0; k < D; ++k) {
        hmax = std::max(hmax, mu[k]);
        if (mu[k] > 0) {
            double s = 0;
            for (std::size_t r = 0; r < D; ++r) s += h[k][r] * g[r];
            gam[k] = s / mu[k];
        }
    }
    const double eps = std::numeric_limits<double>::epsilon();
    const double gn = std::sqrt(g2);
    double best;
    if (hmax == 0 || gn == 0) {
        best = (hmax + gn) * (hmax + gn);
    } else {
        const double h2 = hmax * hmax;
        auto phi = [&](double nu) {
            double s = nu + g2;
            for (std::size_t k = 0; k < D; ++k) {
                if (gam[k] == 0 || mu[k] == 0) continue;
                const double den = nu - mu[k] * mu[k];
                if (!(den > 0)) return std::numeric_limits<double>::infinity();
                s += mu[k] * mu[k] * gam[k] * gam[k] / den;
            }
            return s;
        };
        double lo = h2, hi = h2 + hmax * gn;
        best = std::min(phi(hi), (hmax + gn) * (hmax + gn));
        const double gr = (std::sqrt(5.0) - 1) / 2;
        double x1 = hi - gr * (hi - lo), x2 = lo + gr * (hi - lo);
        double f1 = phi(x1), f2 = phi(x2);
        for (int it = 0; it < 80 && x1 < x2; ++it) {
            best = std::min({best, f1, f2});
            if (f1 < f2) {
                hi = x2, x2 = x1, f2 = f1;
                x1 = hi - gr * (hi - lo), f1 = phi(x1);
            } else {
                lo = x1, x1 = x2, f1 = f2;
                x2 = lo + gr * (hi - lo), f2 = phi(x2);
            }
        }
        best = std::min({best, f1, f2});
    }
    // The SVD and the sums round (relative ~ D eps of |g| + |H|).
    return best * (1 + 64 * eps) + 64 * eps * (gn + hmax) * (gn + hmax);
}

}  // namespace detail_ellipsoid

template <class T, std::size_t D>
struct ellipsoid {
    static_assert(D == 2 || D == 3, "ellipsoid<T, D>: D must be 2 or 3");
    using scalar_type = T;
    using point_type = point<T, D>;
    static constexpr std::size_t dimension = D;
    using vec = std::array<double, D>;
    using frame = std::array<vec, D>;  // rows

    point_type center{};
    std::array<std::array<T, D>, D> axes = identity_axes();  // rows u_k, orthonormal
    std::array<T, D> semi_axes = empty_semi_axes();          // a_k > 0; negative: empty

    static ellipsoid empty() { return {}; }
    bool is_empty() const {
        for (std::size_t k = 0; k < D; ++k)
            if (!(semi_axes[k] >= 0)) return true;
        return false;
    }

    // sum_k ((p - c) . u_k / a_k)^2 in double: <= 1 inside. Every fit measures with this.
    double quadratic_form(const point_type& p) const {
        vec rel;
        for (std::size_t i = 0; i < D; ++i) rel[i] = static_cast<double>(p[i]) - static_cast<double>(center[i]);
        double q = 0;
        for (std::size_t k = 0; k < D; ++k) {
            double y = 0;
            for (std::size_t i = 0; i < D; ++i) y += static_cast<double>(axes[k][i]) * rel[i];
            const double a = static_cast<double>(semi_axes[k]);
            if (a == 0) {  // a flat user-built ellipsoid: inside only on the flat
                if (y != 0) return std::numeric_limits<double>::infinity();
                continue;
            }
            const double t = y / a;
            q += t * t;
        }
        return q;
    }
    bool contains(const point_type& p) const { return !is_empty() && quadratic_form(p) <= 1; }

    // ---------------------------------------------------------------------------- fits

    static ellipsoid fit_pca(std::span<const point_type> pts) {
        if (pts.empty()) return empty();
        const frame_fit f = pca_frame(pts, "ellipsoid::fit_pca");
        vec a{};
        for (std::size_t k = 0; k < f.fat; ++k) a[k] = f.sigma[k];
        return finish(pts, f.mean, f.axes, a, f.fat);
    }

    static ellipsoid fit_khachiyan(std::span<const point_type> pts, double tolerance = 1e-3,
                                   khachiyan_report* report = nullptr) {
        if (!(tolerance > 0)) throw std::invalid_argument("ellipsoid::fit_khachiyan: tolerance must be > 0");
        tolerance = std::clamp(tolerance, 1e-12, 1.0);
        khachiyan_report rep;
        if (pts.empty()) {
            if (report) *report = rep;
            return empty();
        }
        const frame_fit f = pca_frame(pts, "ellipsoid::fit_khachiyan");
        const std::size_t m = f.fat;
        rep.fitted_dimension = m;
        if (m == 0) {
            if (report) *report = rep;
            return finish(pts, f.mean, f.axes, vec{}, 0);
        }
        // Whitening z_k = u_k . (p - mean) / sigma_k, k < m.
        auto whiten = [&](const point_type& p) {
            vec rel, z{};
            for (std::size_t i = 0; i < D; ++i) rel[i] = static_cast<double>(p[i]) - f.mean[i];
            for (std::size_t k = 0; k < m; ++k) {
                double s = 0;
                for (std::size_t i = 0; i < D; ++i) s += f.axes[k][i] * rel[i];
                z[k] = s / f.sigma[k];
            }
            return z;
        };
        const std::size_t n = pts.size();
        // Kumar-Yildirim style start: the extreme points along fixed directions.
        std::vector<vec> dirs;
        if (m == 1)
            dirs = {vec{1}};
        else if (m == 2)
            dirs = {vec{1, 0}, vec{0, 1}, vec{1, 1}, vec{1, -1}};
        else {
            const int tab[13][3] = {{1, 0, 0}, {0, 1, 0},  {0, 0, 1}, {1, 1, 1},  {1, 1, -1}, {1, -1, 1}, {1, -1, -1},
                                    {1, 1, 0}, {1, -1, 0}, {1, 0, 1}, {1, 0, -1}, {0, 1, 1},  {0, 1, -1}};
            for (const auto& t : tab) {
                vec d{};
                for (std::size_t i = 0; i < D && i < 3; ++i) d[i] = t[i];
                dirs.push_back(d);
            }
        }
        std::vector<double> dmin(dirs.size(), std::numeric_limits<double>::infinity()),
            dmax(dirs.size(), -std::numeric_limits<double>::infinity());
        std::vector<std::size_t> imin(dirs.size(), 0), imax(dirs.size(), 0);
        for (std::size_t i = 0; i < n; ++i) {
            const vec z = whiten(pts[i]);
            for (std::size_t d = 0; d < dirs.size(); ++d) {
                double s = 0;
                for (std::size_t k = 0; k < m; ++k) s += dirs[d][k] * z[k];
                if (s < dmin[d]) dmin[d] = s, imin[d] = i;
                if (s > dmax[d]) dmax[d] = s, imax[d] = i;
            }
        }
        std::vector<char> active(n, 0);
        khachiyan_solver solver(m);
        auto add = [&](std::size_t i) {
            if (active[i]) return;
            active[i] = 1;
            solver.add(whiten(pts[i]));
        };
        for (std::size_t d = 0; d < dirs.size(); ++d) add(imin[d]), add(imax[d]);
        // A (pathologically) affinely dependent start: add strided samples until it spans.
        for (std::size_t stride = std::max<std::size_t>(1, n / 64); !solver.start();
             stride = std::max<std::size_t>(1, stride / 4)) {
            for (std::size_t i = 0; i < n; i += stride) add(i);
            if (stride == 1 && !solver.start()) return fit_pca(pts);  // cannot happen for whitened data
        }
        const double md = static_cast<double>(m);
        const double s_goal = std::pow(1 + tolerance, 2 / md);       // certificate on all points
        const double s_inner = std::pow(1 + tolerance / 2, 2 / md);  // target on the active set
        std::size_t budget = 200000;
        std::vector<std::pair<double, std::size_t>> viol;
        double s_all = 0;
        whitened_ellipsoid w;
        while (true) {
            ++rep.rounds;
            budget -= std::min(budget, solver.ascend(1 + md * s_inner, budget));
            w = solver.ellipsoid_of_weights();
            // One pass over all points: the certificate and the violators.
            s_all = 0;
            viol.clear();
            for (std::size_t i = 0; i < n; ++i) {
                const double q = w.form(whiten(pts[i]));
                s_all = std::max(s_all, q);
                if (q > s_inner && !active[i]) viol.emplace_back(q, i);
            }
            if (!(s_all > s_goal) || viol.empty() || budget == 0) break;
            const std::size_t cap = std::max<std::size_t>(4 * m + 4, solver.size());
            if (viol.size() > cap) {
                std::nth_element(viol.begin(), viol.begin() + static_cast<std::ptrdiff_t>(cap), viol.end(),
                                 [](const auto& a, const auto& b) { return a.first > b.first; });
                viol.resize(cap);
            }
            for (const auto& [q, i] : viol) add(i);
        }
        rep.iterations = solver.iterations;
        rep.active_points = solver.size();
        rep.certified_ratio = std::pow(std::max(s_all, 0.0), md / 2);
        // Back to world coordinates: x = mean + U_fat^T S z, z = c + R y (|y|^2 <= s), with
        // R R^T = m Sigma(u) s. Semi-axes and axes from the SVD of S R (graded rows: the
        // one-sided Jacobi on (S R)^T = R^T S keeps their relative accuracy).
        std::array<std::array<double, D>, D> g{};  // column-major: g[col][row] = (R^T S)[row][col]
        for (std::size_t c = 0; c < m; ++c)
            for (std::size_t r = 0; r < m; ++r)
                g[c][r] = w.chol[c][r] * std::sqrt(s_all) * f.sigma[c];  // (R^T)[r][c] = R[c][r]
        std::array<double, D> mu{};
        std::array<std::array<double, D>, D> v{};
        one_sided_jacobi_m(m, g, mu, v);
        vec centre = f.mean;
        for (std::size_t k = 0; k < m; ++k)
            for (std::size_t i = 0; i < D; ++i) centre[i] += f.axes[k][i] * f.sigma[k] * w.centre[k];
        frame ax = f.axes;  // thin axes stay
        vec a{};
        // (S R) = V diag(mu) U^T from (R^T S) = U diag(mu) V^T: world axis j = U_fat^T v_j.
        for (std::size_t j = 0; j < m; ++j) {
            vec u{};
            for (std::size_t k = 0; k < m; ++k)
                for (std::size_t i = 0; i < D; ++i) u[i] += v[k][j] * f.axes[k][i];
            ax[j] = u;
            a[j] = mu[j];
        }
        orthonormalize(ax);
        if (report) *report = rep;
        return finish(pts, centre, ax, a, m);
    }

    // -------------------------------------------------------------------------- queries

    // max over l in [0, 1] of the Perram-Wertheim contact function, and the tolerance of the
    // decision (see the header comment). +inf when either is empty.
    struct contact {
        double value = std::numeric_limits<double>::infinity();  // max F found (a lower bound of max F)
        double upper = std::numeric_limits<double>::infinity();  // certified upper bound of max F
        double tolerance = 0;
        double lambda = 0.5;
    };
    contact contact_function(const ellipsoid& o) const { return contact_impl(o, false); }

    bool overlaps(const ellipsoid& o) const {
        if (is_empty() || o.is_empty()) return false;
        // Bounding / inscribed balls (the frames are orthonormal to T's precision).
        double r2 = 0, amax_a = 0, amax_b = 0, amin_a = std::numeric_limits<double>::infinity(), amin_b = amin_a;
        for (std::size_t i = 0; i < D; ++i) {
            const double d = static_cast<double>(o.center[i]) - static_cast<double>(center[i]);
            r2 += d * d;
        }
        for (std::size_t k = 0; k < D; ++k) {
            amax_a = std::max(amax_a, safe_axis(semi_axes[k]));
            amax_b = std::max(amax_b, safe_axis(o.semi_axes[k]));
            amin_a = std::min(amin_a, safe_axis(semi_axes[k]));
            amin_b = std::min(amin_b, safe_axis(o.semi_axes[k]));
        }
        const double slack = 16 * static_cast<double>(D) * std::numeric_limits<T>::epsilon();
        const double r = std::sqrt(r2);
        if (r > (amax_a + amax_b) * (1 + slack)) return false;
        if (r < (amin_a + amin_b) * (1 - slack)) return true;
        // Disjoint only on a certificate: some F(l) beyond 1 + its rounding bound.
        const contact c = contact_impl(o, true);
        return !(c.value > 1 + c.tolerance);
    }

private:
    contact contact_impl(const ellipsoid& o, bool decide) const {
        contact res;
        if (is_empty() || o.is_empty()) return res;
        const ellipsoid* p = this;
        const ellipsoid* q = &o;
        bool swapped = false;
        auto amin = [](const ellipsoid& e) {
            double v = std::numeric_limits<double>::infinity();
            for (std::size_t k = 0; k < D; ++k) v = std::min(v, safe_axis(e.semi_axes[k]));
            return v;
        };
        auto amax = [](const ellipsoid& e) {
            double v = 0;
            for (std::size_t k = 0; k < D; ++k) v = std::max(v, safe_axis(e.semi_axes[k]));
            return v;
        };
        // Map the one to the unit ball that keeps the other's image best conditioned.
        if (amax(*this) / amin(o) < amax(o) / amin(*this)) std::swap(p, q), swapped = true;
        const double kappa_g = amax(*q) / amin(*p);
        // G = diag(1 / a_p) U_p U_q^-1 diag(a_q), c' = diag(1 / a_p) U_p (c_q - c_p).
        Eigen::Matrix<double, int(D), int(D)> up, uq;
        for (std::size_t i = 0; i < D; ++i)
            for (std::size_t j = 0; j < D; ++j) {
                up(int(i), int(j)) = static_cast<double>(p->axes[i][j]);
                uq(int(i), int(j)) = static_cast<double>(q->axes[i][j]);
            }
        const Eigen::Matrix<double, int(D), int(D)> m = up * uq.inverse();
        std::array<std::array<double, D>, D> g;  // column-major
        vec rp{};
        double rnorm2 = 0;
        for (std::size_t i = 0; i < D; ++i) {
            const double r = static_cast<double>(q->center[i]) - static_cast<double>(p->center[i]);
            rnorm2 += r * r;
        }
        for (std::size_t i = 0; i < D; ++i) {
            double s = 0;
            for (std::size_t j = 0; j < D; ++j)
                s += up(int(i), int(j)) * (static_cast<double>(q->center[j]) - static_cast<double>(p->center[j]));
            rp[i] = s / safe_axis(p->semi_axes[i]);
            for (std::size_t j = 0; j < D; ++j)
                g[j][i] = m(int(i), int(j)) * safe_axis(q->semi_axes[j]) / safe_axis(p->semi_axes[i]);
        }
        std::array<double, D> mu;
        std::array<std::array<double, D>, D> v;
        detail_ellipsoid::one_sided_jacobi<D, false>(D, g, mu, v);
        std::array<double, D> w{}, m2{};
        for (std::size_t k = 0; k < D; ++k) {
            double s = 0;
            for (std::size_t r = 0; r < D; ++r) s += g[k][r] * rp[r];
            s = mu[k] > 0 ? s / mu[k] : 0;
            w[k] = s * s;
            m2[k] = mu[k] * mu[k];
        }
        auto f = [&](double l) {
            double s = 0;
            for (std::size_t k = 0; k < D; ++k) s += w[k] / ((1 - l) + l * m2[k]);
            return l * (1 - l) * s;
        };
        // F'(l) = sum_k w_k ((1 - l) - mu_k l) ((1 - l) + mu_k l) / den_k^2 (decreasing: F
        // is concave) and its derivative, for a safeguarded Newton iteration.
        auto fprime = [&](double l, double& d2) {
            double s = 0;
            d2 = 0;
            for (std::size_t k = 0; k < D; ++k) {
                const double den = (1 - l) + l * m2[k];
                const double num = ((1 - l) - mu[k] * l) * ((1 - l) + mu[k] * l);
                const double dnum = -2 * (1 - l) - 2 * m2[k] * l;
                s += w[k] * num / (den * den);
                d2 += w[k] * (dnum * den - 2 * num * (m2[k] - 1)) / (den * den * den);
            }
            return s;
        };
        // Rounding bound of F(l) (F ~ 1 near the decision): G and c' carry relative errors
        // ~ D eps of their magnitude bounds, acting through M(l) = (1 - l) I + l G G^T with
        // lambda_min(M) >= (1 - l) + l mu_min^2.
        double mu_min = mu[0];
        for (std::size_t k = 1; k < D; ++k) mu_min = std::min(mu_min, mu[k]);
        const double eps = std::numeric_limits<double>::epsilon();
        const double kappa_r = std::sqrt(rnorm2) / amin(*p);
        const double cst = 64.0 * static_cast<double>(D) * eps;
        auto tolerance_at = [&](double l, double value) {
            const double lam_min = std::max((1 - l) + l * mu_min * mu_min, 1e-300);
            return 1e-12 + cst * (std::max(value, 1.0) * (kappa_g * kappa_g * l / lam_min) +
                                  kappa_r * std::sqrt(std::max(value, 1.0) * l * (1 - l) / lam_min) + 1);
        };
        // The maximiser lies between the per-term maximisers l_k = 1 / (1 + mu_k).
        double lo = 1, hi = 0;
        for (std::size_t k = 0; k < D; ++k)
            if (w[k] > 0) {
                const double lk = 1 / (1 + mu[k]);
                lo = std::min(lo, lk);
                hi = std::max(hi, lk);
            }
        double l = 0.5, best = f(0.5);
        res.upper = std::numeric_limits<double>::infinity();
        if (lo < hi) {
            // Safeguarded Newton on F' = 0 within the bracket (bisection when a step leaves
            // it). Every iterate x gives certified bounds on max F (F is concave):
            // F(x) <= max F <= F(x) + F'(x) (end of the bracket on the rising side - x).
            // With `decide`, stop as soon as 1 + tolerance lies outside them.
            double x = lo + (hi - lo) / 2;
            for (int it = 0; it < 100; ++it) {
                double d2;
                const double slope = fprime(x, d2), fx = f(x);
                if (fx > best) best = fx, l = x;
                if (slope > 0)
                    lo = x;
                else if (slope < 0)
                    hi = x;
                res.upper = std::min(res.upper, fx + (slope > 0 ? slope * (hi - x) : slope * (lo - x)));
                if (decide && (best > 1 + tolerance_at(l, best) || res.upper <= 1 + tolerance_at(l, best))) break;
                if (slope == 0) break;
                double nx = d2 < 0 ? x - slope / d2 : lo + (hi - lo) / 2;
                if (!(nx > lo && nx < hi)) nx = lo + (hi - lo) / 2;
                if (!(nx > lo && nx < hi)) break;  // bracket exhausted
                const bool done = std::abs(nx - x) <= 1e-14 * std::min(x, 1 - x);
                x = nx;
                if (done) {
                    const double fn = f(x);
                    if (fn > best) best = fn, l = x;
                    break;
                }
            }
        } else if (lo == hi) {
            l = lo, best = f(lo), res.upper = best;
        }
        res.value = best;
        res.tolerance = tolerance_at(l, best);
        res.lambda = swapped ? 1 - l : l;
        return res;
    }

public:
    bool ray_interval(const point_type& o, const point_type& d, T& t0, T& t1) const {
        if (is_empty()) return false;
        vec op{}, dp{};
        for (std::size_t k = 0; k < D; ++k) {
            double so = 0, sd = 0;
            for (std::size_t i = 0; i < D; ++i) {
                so += static_cast<double>(axes[k][i]) * (static_cast<double>(o[i]) - static_cast<double>(center[i]));
                sd += static_cast<double>(axes[k][i]) * static_cast<double>(d[i]);
            }
            const double a = safe_axis(semi_axes[k]);
            op[k] = so / a;
            dp[k] = sd / a;
        }
        double a = 0, b = 0;
        for (std::size_t k = 0; k < D; ++k) a += dp[k] * dp[k], b -= op[k] * dp[k];
        if (!(a > 0) || !std::isfinite(a)) return false;
        const double tc = b / a;  // closest approach to the centre
        double f2 = 0;            // squared distance of the line from the centre (unit-ball frame)
        for (std::size_t k = 0; k < D; ++k) {
            const double f = op[k] + tc * dp[k];
            f2 += f * f;
        }
        const double disc = 1 - f2;
        if (disc < 0) return false;
        const double h = std::sqrt(disc / a);
        t0 = detail_ellipsoid::round_down<T>(tc - h);
        t1 = detail_ellipsoid::round_up<T>(tc + h);
        return true;
    }

    T distance_lower_bound(const point_type& p) const {
        if (is_empty()) return std::numeric_limits<T>::infinity();
        if (quadratic_form(p) <= 1) return 0;
        vec y, e;
        double rel2 = 0, emax = 0;
        for (std::size_t k = 0; k < D; ++k) {
            double s = 0;
            for (std::size_t i = 0; i < D; ++i) {
                const double r = static_cast<double>(p[i]) - static_cast<double>(center[i]);
                s += static_cast<double>(axes[k][i]) * r;
                if (k == 0) rel2 += r * r;
            }
            y[k] = std::abs(s);
            e[k] = safe_axis(semi_axes[k]);
            emax = std::max(emax, e[k]);
        }
        // Root of psi(t) = sum (e_k y_k / (t + e_k^2))^2 - 1 (decreasing, psi(0) > 0 outside).
        auto psi = [&](double t) {
            double s = -1;
            for (std::size_t k = 0; k < D; ++k) {
                const double r = e[k] * y[k] / (t + e[k] * e[k]);
                s += r * r;
            }
            return s;
        };
        double lo = 0, hi = 0;
        for (std::size_t k = 0; k < D; ++k) hi += (e[k] * y[k]) * (e[k] * y[k]);
        hi = std::sqrt(hi);
        for (int it = 0; it < 200; ++it) {
            const double mid = lo + (hi - lo) / 2;
            if (!(mid > lo && mid < hi)) break;
            if (psi(mid) > 0)
                lo = mid;
            else
                hi = mid;
        }
        const double t = lo + (hi - lo) / 2;
        // Weak duality: g(t) <= dist^2 for every t >= 0.
        double pos = 0;
        for (std::size_t k = 0; k < D; ++k) pos += y[k] * y[k] * t / (e[k] * e[k] + t);
        const double eps = std::numeric_limits<double>::epsilon();
        const double g = pos - t - 8 * eps * (pos + t);
        double lb = std::sqrt(std::max(0.0, g));
        // y carries ~D eps |p - c| of rounding; the stored frame is orthonormal to ~D eps_T.
        lb -= 4 * static_cast<double>(D) * eps * (std::sqrt(rel2) + emax);
        lb *= 1 - 4 * static_cast<double>(D) * std::numeric_limits<T>::epsilon();
        return lb > 0 ? detail_ellipsoid::round_down<T>(lb) : T(0);
    }

    // Contains both; the smallest of three candidates (see the header comment).
    ellipsoid merged(const ellipsoid& o) const {
        if (is_empty()) return o;
        if (o.is_empty()) return *this;
        const std::array<target, 2> tg = {as_target(), o.as_target()};
        ellipsoid best = scaled_to_contain(center_d(), frame_d(), axes_d(), tg);
        auto consider = [&](const ellipsoid& c) {
            if (!c.is_empty() && c.volume_d() < best.volume_d()) best = c;
        };
        consider(scaled_to_contain(o.center_d(), o.frame_d(), o.axes_d(), tg));
        // PCA frame of the 4D semi-axis end points of both.
        std::vector<vec> ends;
        for (const ellipsoid* e : {this, &o})
            for (std::size_t k = 0; k < D; ++k)
                for (int s : {-1, 1}) {
                    vec x;
                    for (std::size_t i = 0; i < D; ++i)
                        x[i] = static_cast<double>(e->center[i]) +
                               s * static_cast<double>(e->semi_axes[k]) * static_cast<double>(e->axes[k][i]);
                    ends.push_back(x);
                }
        vec mean{};
        for (const auto& x : ends)
            for (std::size_t i = 0; i < D; ++i) mean[i] += x[i] / static_cast<double>(ends.size());
        Eigen::Matrix<double, int(D), int(D)> cov = Eigen::Matrix<double, int(D), int(D)>::Zero();
        for (const auto& x : ends) {
            Eigen::Matrix<double, int(D), 1> r;
            for (std::size_t i = 0; i < D; ++i) r[int(i)] = x[i] - mean[i];
            cov += r * r.transpose();
        }
        cov /= static_cast<double>(ends.size());
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, int(D), int(D)>> es(cov);
        frame ax;
        vec a;
        const double top = std::sqrt(std::max(es.eigenvalues()[int(D) - 1], 0.0));
        for (std::size_t k = 0; k < D; ++k) {
            for (std::size_t i = 0; i < D; ++i) ax[k][i] = es.eigenvectors()(int(i), int(D - 1 - k));
            a[k] = std::max(std::sqrt(std::max(es.eigenvalues()[int(D - 1 - k)], 0.0)), 1e-9 * top);
        }
        if (top > 0 && es.info() == Eigen::Success) {
            orthonormalize(ax);
            consider(scaled_to_contain(mean, ax, a, tg));
        }
        return best;
    }

    // Exact: the centre moves, the frame rotates (plus a certified rounding pad).
    ellipsoid transformed(const rigid_transform<T, D>& xf) const {
        if (is_empty()) return *this;
        vec c{};
        frame ax{};
        for (std::size_t i = 0; i < D; ++i) {
            c[i] = static_cast<double>(xf.translation[i]);
            for (std::size_t j = 0; j < D; ++j)
                c[i] += static_cast<double>(xf.rotation[i][j]) * static_cast<double>(center[j]);
        }
        for (std::size_t k = 0; k < D; ++k)
            for (std::size_t i = 0; i < D; ++i)
                for (std::size_t j = 0; j < D; ++j)
                    ax[k][i] += static_cast<double>(xf.rotation[i][j]) * static_cast<double>(axes[k][j]);
        orthonormalize(ax);
        // The image, exactly: {R c + t + R U^-1 diag(a) z : |z| <= 1}.
        target tg = as_target();
        tg.centre = c;
        std::array<std::array<double, D>, D> l{};  // row-major
        for (std::size_t i = 0; i < D; ++i)
            for (std::size_t j = 0; j < D; ++j)
                for (std::size_t k = 0; k < D; ++k) l[i][j] += static_cast<double>(xf.rotation[i][k]) * tg.shape[k][j];
        tg.shape = l;
        ellipsoid e = scaled_to_contain(c, ax, axes_d(), std::array<target, 1>{tg});
        // Also contain xf.apply(p) as computed in T for every p inside (as aabb and sphere
        // do): each coordinate of R p + t rounds by at most (D + 1) eps_T (|t| + |R| |p|).
        double mag = 0, amax = 0;
        for (std::size_t k = 0; k < D; ++k) amax = std::max(amax, static_cast<double>(semi_axes[k]));
        for (std::size_t i = 0; i < D; ++i) {
            double r = std::abs(static_cast<double>(xf.translation[i]));
            for (std::size_t j = 0; j < D; ++j)
                r += std::abs(static_cast<double>(xf.rotation[i][j])) *
                     (std::abs(static_cast<double>(center[j])) + amax);
            mag = std::max(mag, r);
        }
        const double eps_t =
            std::max(static_cast<double>(std::numeric_limits<T>::epsilon()), std::numeric_limits<double>::epsilon());
        return e.inflated(2 * (static_cast<double>(D) + 1) * eps_t * mag * std::sqrt(static_cast<double>(D)));
    }

    // The same ellipsoid (centre, frame) grown to contain its Minkowski sum with a ball of
    // radius rho. Two rigorous rules, the smaller volume kept: (a) every semi-axis times
    // 1 + rho / a_min (triangle inequality in the ellipsoid norm); (b) for eps in (0, 1),
    // (e + b)^2 <= (1 + eps) e^2 + (1 + 1/eps) b^2 gives semi-axes
    // a'_k = max(a_k sqrt((1 + eps) / (1 - eps)), rho sqrt((1 + 1/eps) / eps)): fat axes
    // barely grow, thin ones become ~rho / eps (the Minkowski sum is not an ellipsoid).
    ellipsoid inflated(double rho) const {
        if (is_empty() || !(rho > 0)) return *this;
        vec a = axes_d();
        double amin = a[0];
        for (std::size_t k = 1; k < D; ++k) amin = std::min(amin, a[k]);
        vec best = a;
        double best_log = std::numeric_limits<double>::infinity();
        auto consider = [&](const vec& c) {
            double lv = 0;
            for (std::size_t k = 0; k < D; ++k) lv += std::log(c[k]);
            if (lv < best_log) best_log = lv, best = c;
        };
        vec iso;
        for (std::size_t k = 0; k < D; ++k) iso[k] = a[k] * (1 + rho / amin);
        consider(iso);
        for (double eps = 0.5; eps > 1e-12; eps /= 4) {
            vec c;
            for (std::size_t k = 0; k < D; ++k)
                c[k] = std::max(a[k] * std::sqrt((1 + eps) / (1 - eps)), rho * std::sqrt((1 + 1 / eps) / eps));
            consider(c);
        }
        ellipsoid e = *this;
        for (std::size_t k = 0; k < D; ++k)
            e.semi_axes[k] = detail_ellipsoid::round_up<T>(best[k] * (1 + 4 * std::numeric_limits<double>::epsilon()));
        return e;
    }

    T volume() const { return is_empty() ? T(0) : static_cast<T>(volume_d()); }

    T surface_area() const {  // perimeter in 2D
        if (is_empty()) return 0;
        std::array<double, D> s;
        for (std::size_t k = 0; k < D; ++k) s[k] = std::max(static_cast<double>(semi_axes[k]), 0.0);
        std::sort(s.begin(), s.end(), std::greater<double>());
        const double pi = std::numbers::pi;
        if constexpr (D == 2) {
            const double a = s[0], b = s[1];
            if (a == 0) return 0;
            const double r = b / a;
            const double e = std::sqrt(std::max(0.0, (1 - r) * (1 + r)));
            return static_cast<T>(4 * a * std::comp_ellint_2(e));
        } else {
            const double a = s[0], b = s[1], c = s[2];
            if (a == 0) return 0;
            if (c == 0) return static_cast<T>(2 * pi * a * b);  // a flat ellipse, both sides
            const double ca = c / a, cb = c / b;
            const double sin2 = (1 - ca) * (1 + ca);
            if (!(sin2 > 0)) return static_cast<T>(4 * pi * a * a);  // a ball
            const double sinphi = std::sqrt(sin2);
            const double phi = std::atan2(sinphi, ca);
            const double k = std::sqrt(std::clamp((1 - cb) * (1 + cb) / sin2, 0.0, 1.0));
            const double area = 2 * pi * c * c + 2 * pi * a * b *
                                                     (std::ellint_2(k, phi) * sin2 + std::ellint_1(k, phi) * ca * ca) /
                                                     sinphi;
            return static_cast<T>(area);
        }
    }

private:
    static constexpr std::array<T, D> empty_semi_axes() {
        std::array<T, D> a{};
        for (auto& x : a) x = T(-1);
        return a;
    }
    static constexpr std::array<std::array<T, D>, D> identity_axes() {
        std::array<std::array<T, D>, D> a{};
        for (std::size_t i = 0; i < D; ++i) a[i][i] = T(1);
        return a;
    }
    static double safe_axis(T a) { return std::max(static_cast<double>(a), std::numeric_limits<double>::min()); }

    double volume_d() const {
        double v = detail_ellipsoid::unit_ball_volume(D);
        for (std::size_t k = 0; k < D; ++k) v *= std::max(static_cast<double>(semi_axes[k]), 0.0);
        return v;
    }
    vec center_d() const {
        vec c;
        for (std::size_t i = 0; i < D; ++i) c[i] = static_cast<double>(center[i]);
        return c;
    }
    frame frame_d() const {
        frame f;
        for (std::size_t k = 0; k < D; ++k)
            for (std::size_t i = 0; i < D; ++i) f[k][i] = static_cast<double>(axes[k][i]);
        return f;
    }
    vec axes_d() const {
        vec a;
        for (std::size_t k = 0; k < D; ++k) a[k] = safe_axis(semi_axes[k]);
        return a;
    }

    // Gram-Schmidt on the rows (twice, for orthogonality to rounding), right-handed in 3D.
    static void orthonormalize(frame& f) {
        for (int pass = 0; pass < 2; ++pass)
            for (std::size_t k = 0; k < D; ++k) {
                for (std::size_t j = 0; j < k; ++j) {
                    double d = 0;
                    for (std::size_t i = 0; i < D; ++i) d += f[k][i] * f[j][i];
                    for (std::size_t i = 0; i < D; ++i) f[k][i] -= d * f[j][i];
                }
                double n = 0;
                for (std::size_t i = 0; i < D; ++i) n += f[k][i] * f[k][i];
                n = std::sqrt(n);
                if (!(n > 1e-8)) {  // lost direction: complete the frame
                    if constexpr (D == 2) {
                        f[1] = {-f[0][1], f[0][0]};
                    } else {
                        vec e{};
                        std::size_t best = 0;
                        for (std::size_t i = 1; i < D; ++i)
                            if (std::abs(f[0][i]) < std::abs(f[0][best])) best = i;
                        e[best] = 1;
                        f[k] = e;
                        --k;  // redo this row with the replacement
                        continue;
                    }
                    continue;
                }
                for (std::size_t i = 0; i < D; ++i) f[k][i] /= n;
            }
        if constexpr (D == 3) {
            const double det = f[0][0] * (f[1][1] * f[2][2] - f[1][2] * f[2][1]) -
                               f[0][1] * (f[1][0] * f[2][2] - f[1][2] * f[2][0]) +
                               f[0][2] * (f[1][0] * f[2][1] - f[1][1] * f[2][0]);
            if (det < 0)
                for (auto& x : f[2]) x = -x;
        }
    }

    // A target ellipsoid {centre + shape z : |z| <= 1} (shape row-major, D x D).
    struct target {
        vec centre;
        std::array<std::array<double, D>, D> shape;
    };
    // This ellipsoid as a target: shape = U^-1 diag(a) (exact for the stored, possibly not
    // exactly orthonormal, frame).
    target as_target() const {
        target t;
        t.centre = center_d();
        Eigen::Matrix<double, int(D), int(D)> u;
        for (std::size_t i = 0; i < D; ++i)
            for (std::size_t j = 0; j < D; ++j) u(int(i), int(j)) = static_cast<double>(axes[i][j]);
        const Eigen::Matrix<double, int(D), int(D)> ui = u.inverse();
        for (std::size_t i = 0; i < D; ++i)
            for (std::size_t j = 0; j < D; ++j) t.shape[i][j] = ui(int(i), int(j)) * safe_axis(semi_axes[j]);
        return t;
    }

    // The candidate (centre c, frame f, semi-axes a) rounded to T and scaled about its centre
    // by the smallest certified factor that makes it contain every target.
    template <std::size_t N>
    static ellipsoid scaled_to_contain(const vec& c, const frame& f, const vec& a, const std::array<target, N>& tg) {
        ellipsoid e;
        for (std::size_t i = 0; i < D; ++i) e.center[i] = static_cast<T>(c[i]);
        for (std::size_t k = 0; k < D; ++k)
            for (std::size_t i = 0; i < D; ++i) e.axes[k][i] = static_cast<T>(f[k][i]);
        double s = 0;
        for (const auto& t : tg) {
            // g = diag(1/a) U (centre - c_e), H = diag(1/a) U shape, with the rounded frame.
            vec g{};
            std::array<std::array<double, D>, D> h{};  // column-major
            for (std::size_t k = 0; k < D; ++k) {
                double sg = 0;
                for (std::size_t i = 0; i < D; ++i)
                    sg += static_cast<double>(e.axes[k][i]) * (t.centre[i] - static_cast<double>(e.center[i]));
                g[k] = sg / a[k];
                for (std::size_t j = 0; j < D; ++j) {
                    double sh = 0;
                    for (std::size_t i = 0; i < D; ++i) sh += static_cast<double>(e.axes[k][i]) * t.shape[i][j];
                    h[j][k] = sh / a[k];
                }
            }
            s = std::max(s, detail_ellipsoid::max_quadratic_over_ball<D>(g, h));
        }
        const double factor = std::sqrt(s) * (1 + 8 * std::numeric_limits<double>::epsilon());
        for (std::size_t k = 0; k < D; ++k) {
            e.semi_axes[k] = detail_ellipsoid::round_up<T>(a[k] * factor);
            if (!(e.semi_axes[k] > 0)) e.semi_axes[k] = std::numeric_limits<T>::min();
        }
        if (!std::isfinite(s)) return empty();
        return e;
    }

    // ---------------------------------------------------------------- fitting helpers

    struct frame_fit {
        vec mean{};
        frame axes{};
        vec sigma{};      // spread along each axis, re-measured (descending up to rounding)
        std::size_t fat;  // axes 0..fat-1 have sigma > 1e-12 * max sigma
    };
    static frame_fit pca_frame(std::span<const point_type> pts, const char* where) {
        const principal_frame<D> pf = principal_axes(pts);
        frame_fit f;
        f.mean = pf.mean;
        for (std::size_t i = 0; i < D; ++i)
            if (!std::isfinite(f.mean[i]))
                for (const auto& p : pts) detail::require_finite(p, where, "input point");
        for (std::size_t k = 0; k < D; ++k)
            for (std::size_t i = 0; i < D; ++i) f.axes[k][i] = pf.axes[k][i];
        // The variance along each computed axis, measured directly: accurate even where
        // the eigenvalue is not (eigenvalues carry absolute errors ~ eps * the largest).
        vec ss{};
        for (const auto& p : pts) {
            for (std::size_t k = 0; k < D; ++k) {
                double y = 0;
                for (std::size_t i = 0; i < D; ++i) y += f.axes[k][i] * (static_cast<double>(p[i]) - f.mean[i]);
                ss[k] += y * y;
            }
        }
        for (std::size_t i = 0; i < D; ++i)
            if (!std::isfinite(ss[i]))
                for (const auto& p : pts) detail::require_finite(p, where, "input point");
        double top = 0;
        for (std::size_t k = 0; k < D; ++k) {
            f.sigma[k] = std::sqrt(ss[k] / static_cast<double>(pts.size()));
            top = std::max(top, f.sigma[k]);
        }
        // Keep the fat axes first (principal_axes sorts by the eigenvalues).
        std::array<std::size_t, D> order;
        for (std::size_t k = 0; k < D; ++k) order[k] = k;
        std::stable_sort(order.begin(), order.end(),
                         [&](std::size_t a, std::size_t b) { return f.sigma[a] > f.sigma[b]; });
        frame ax;
        vec sg;
        for (std::size_t k = 0; k < D; ++k) ax[k] = f.axes[order[k]], sg[k] = f.sigma[order[k]];
        f.axes = ax;
        f.sigma = sg;
        f.fat = 0;
        for (std::size_t k = 0; k < D; ++k)
            if (top > 0 && f.sigma[k] > 1e-12 * top) ++f.fat;
        return f;
    }

    // Rounds centre and frame to T, sizes the thin axes (k >= fat), scales every semi-axis
    // by sqrt(max quadratic form) measured with the rounded frame, rounds up, and verifies
    // contains() on every point (growing by a few ulps in the rare case it fails).
    static ellipsoid finish(std::span<const point_type> pts, const vec& c, const frame& f, vec a, std::size_t fat) {
        ellipsoid e;
        double cmax = 0;
        for (std::size_t i = 0; i < D; ++i) {
            e.center[i] = static_cast<T>(c[i]);
            cmax = std::max(cmax, std::abs(static_cast<double>(e.center[i])));
        }
        for (std::size_t k = 0; k < D; ++k)
            for (std::size_t i = 0; i < D; ++i) e.axes[k][i] = static_cast<T>(f[k][i]);
        const double abs_floor = std::max(16 * static_cast<double>(std::numeric_limits<T>::epsilon()) * cmax,
                                          static_cast<double>(std::numeric_limits<T>::min()));
        auto offsets = [&](const point_type& p) {
            vec y{};
            for (std::size_t k = 0; k < D; ++k)
                for (std::size_t i = 0; i < D; ++i)
                    y[k] += static_cast<double>(e.axes[k][i]) *
                            (static_cast<double>(p[i]) - static_cast<double>(e.center[i]));
            return y;
        };
        double amax = 0;
        for (std::size_t k = 0; k < fat; ++k) amax = std::max(amax, a[k]);
        if (fat < D) {
            vec ymax{};
            for (const auto& p : pts) {
                const vec y = offsets(p);
                for (std::size_t k = fat; k < D; ++k) ymax[k] = std::max(ymax[k], std::abs(y[k]));
            }
            for (std::size_t k = fat; k < D; ++k)
                a[k] = std::max(1e-9 * amax, 10 * std::sqrt(static_cast<double>(D)) * ymax[k]);
        }
        for (std::size_t k = 0; k < D; ++k) a[k] = std::max(a[k], abs_floor);
        double qmax = 0;
        for (const auto& p : pts) {
            const vec y = offsets(p);
            double q = 0;
            for (std::size_t k = 0; k < D; ++k) q += (y[k] / a[k]) * (y[k] / a[k]);
            qmax = std::max(qmax, q);
        }
        const double scale = qmax > 0 ? std::sqrt(qmax) * (1 + 4 * std::numeric_limits<double>::epsilon()) : 1.0;
        for (std::size_t k = 0; k < D; ++k)
            e.semi_axes[k] =
                std::max(detail_ellipsoid::round_up<T>(a[k] * scale), detail_ellipsoid::round_up<T>(abs_floor));
        for (int attempt = 0; attempt < 200; ++attempt) {
            bool all = true;
            for (const auto& p : pts)
                if (!e.contains(p)) {
                    all = false;
                    break;
                }
            if (all) break;
            for (auto& s : e.semi_axes)
                s = s * (1 + 8 * std::numeric_limits<T>::epsilon() * static_cast<T>(1 + attempt));
        }
        return e;
    }

    // Khachiyan / Todd-Yildirim ascent on lifted points Q_i = (z_i, 1) in R^(m+1).
    struct whitened_ellipsoid {
        vec centre{};                                 // c(u)
        std::array<std::array<double, D>, D> chol{};  // R: R R^T = m Sigma(u), lower, R[row][col]
        std::array<std::array<double, D>, D> inv{};   // R^-1 (lower)
        std::size_t m = 0;
        double form(const vec& z) const {  // (z - c)^T (m Sigma)^-1 (z - c) = |R^-1 (z - c)|^2
            double q = 0;
            for (std::size_t r = 0; r < m; ++r) {
                double s = 0;
                for (std::size_t c = 0; c <= r; ++c) s += inv[r][c] * (z[c] - centre[c]);
                q += s * s;
            }
            return q;
        }
    };
    struct khachiyan_solver {
        using mat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, D + 1, D + 1>;
        using col = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, D + 1, 1>;
        std::size_t m, n1;
        std::vector<std::array<double, D + 1>> q;  // lifted points
        std::vector<double> u, omega;
        mat xinv;
        std::size_t iterations = 0;
        bool started = false;
        explicit khachiyan_solver(std::size_t dim) : m(dim), n1(dim + 1), xinv(int(dim + 1), int(dim + 1)) {}
        std::size_t size() const { return q.size(); }
        double lifted_form(std::size_t i, const mat& x) const {
            double s = 0;
            for (std::size_t r = 0; r < n1; ++r)
                for (std::size_t c = 0; c < n1; ++c) s += q[i][r] * x(int(r), int(c)) * q[i][c];
            return s;
        }
        void add(const vec& z) {
            std::array<double, D + 1> l{};
            for (std::size_t k = 0; k < m; ++k) l[k] = z[k];
            l[m] = 1;
            q.push_back(l);
            u.push_back(0);
            omega.push_back(started ? lifted_form(q.size() - 1, xinv) : 0);
        }
        // X(u) and its inverse from the weights; false when X is (numerically) singular.
        bool refresh() {
            mat x = mat::Zero(int(n1), int(n1));
            for (std::size_t i = 0; i < q.size(); ++i) {
                if (u[i] == 0) continue;
                for (std::size_t r = 0; r < n1; ++r)
                    for (std::size_t c = 0; c < n1; ++c) x(int(r), int(c)) += u[i] * q[i][r] * q[i][c];
            }
            Eigen::LLT<mat> llt(x);
            if (llt.info() != Eigen::Success) return false;
            double dmin = std::numeric_limits<double>::infinity(), dmax = 0;
            for (std::size_t r = 0; r < n1; ++r) {
                dmin = std::min(dmin, std::abs(llt.matrixLLT()(int(r), int(r))));
                dmax = std::max(dmax, std::abs(llt.matrixLLT()(int(r), int(r))));
            }
            if (!(dmin > 1e-7 * dmax)) return false;
            xinv = llt.solve(mat::Identity(int(n1), int(n1)));
            for (std::size_t i = 0; i < q.size(); ++i) omega[i] = lifted_form(i, xinv);
            return true;
        }
        // Uniform weights on the current set; false if they do not span.
        bool start() {
            for (auto& w : u) w = 1.0 / static_cast<double>(u.size());
            started = refresh();
            return started;
        }
        // Ascent until max omega <= target or `budget` steps; returns the steps taken.
        std::size_t ascend(double target, std::size_t budget) {
            const double nd = static_cast<double>(n1);
            std::size_t steps = 0;
            for (; steps < budget; ++steps) {
                std::size_t jp = 0, jm = 0;
                double wp = -std::numeric_limits<double>::infinity(), wm = std::numeric_limits<double>::infinity();
                for (std::size_t i = 0; i < q.size(); ++i) {
                    if (omega[i] > wp) wp = omega[i], jp = i;
                    if (u[i] > 0 && omega[i] < wm) wm = omega[i], jm = i;
                }
                if (wp <= target) break;
                // Wolfe-Atwood (Todd & Yildirim): an away step from the least useful support
                // point when it is further from optimality than the worst point, else the
                // Khachiyan/Frank-Wolfe step toward the worst point. The optimal step for
                // log det along e_j is beta = (omega_j - n1) / (n1 (omega_j - 1)); an away
                // step is clipped at dropping the point (u_j = 0).
                bool away = false, drop = false;
                double beta = 0;
                if (1 - wm / nd > wp / nd - 1 && u[jm] < 1) {
                    const double floor_beta = -u[jm] / (1 - u[jm]);
                    beta = wm > 1 ? (wm - nd) / (nd * (wm - 1)) : floor_beta;
                    if (beta <= floor_beta) beta = floor_beta, drop = true;
                    // Skip it if it would (nearly) make X singular: the update divides by
                    // 1 + beta / (1 - beta) omega_j.
                    away = 1 + beta / (1 - beta) * wm > 1e-8;
                }
                if (away) {
                    step(jm, beta);
                    if (drop) u[jm] = 0;
                } else {
                    step(jp, (wp - nd) / (nd * (wp - 1)));
                }
                ++iterations;
                if (drop || iterations % 256 == 0) refresh();  // bound the drift of X^-1
            }
            refresh();
            return steps;
        }
        // u <- (1 - beta) u + beta e_j with the Sherman-Morrison update of X^-1 and omega.
        void step(std::size_t j, double beta) {
            const double gam = beta / (1 - beta);
            const double wj = omega[j];
            col qj = col::Zero(static_cast<int>(n1));
            for (std::size_t r = 0; r < n1; ++r) qj[int(r)] = q[j][r];
            const col v = xinv * qj;
            const double den = 1 + gam * wj;
            for (std::size_t i = 0; i < q.size(); ++i) {
                double kap = 0;
                for (std::size_t r = 0; r < n1; ++r) kap += q[i][r] * v[int(r)];
                omega[i] = (omega[i] - gam * kap * kap / den) / (1 - beta);
            }
            xinv = (xinv - (gam / den) * v * v.transpose()) / (1 - beta);
            for (auto& w : u) w *= 1 - beta;
            u[j] += beta;
            if (u[j] < 0) u[j] = 0;
        }
        whitened_ellipsoid ellipsoid_of_weights() const {
            whitened_ellipsoid w;
            w.m = m;
            double us = 0;
            for (double x : u) us += x;
            for (std::size_t i = 0; i < q.size(); ++i)
                for (std::size_t k = 0; k < m; ++k) w.centre[k] += u[i] * q[i][k] / us;
            Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, D, D> sig =
                Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, D, D>::Zero(int(m), int(m));
            for (std::size_t i = 0; i < q.size(); ++i) {
                if (u[i] == 0) continue;
                for (std::size_t r = 0; r < m; ++r)
                    for (std::size_t c = 0; c < m; ++c)
                        sig(int(r), int(c)) += u[i] / us * (q[i][r] - w.centre[r]) * (q[i][c] - w.centre[c]);
            }
            sig *= static_cast<double>(m);
            Eigen::LLT<decltype(sig)> llt(sig);
            const auto l = llt.matrixL().toDenseMatrix();
            const auto li = l.inverse();
            for (std::size_t r = 0; r < m; ++r)
                for (std::size_t c = 0; c < m; ++c) {
                    w.chol[r][c] = l(int(r), int(c));
                    w.inv[r][c] = li(int(r), int(c));
                }
            return w;
        }
    };

    static void one_sided_jacobi_m(std::size_t m, std::array<std::array<double, D>, D>& g, std::array<double, D>& mu,
                                   std::array<std::array<double, D>, D>& v) {
        detail_ellipsoid::one_sided_jacobi<D>(m, g, mu, v);
    }
};

static_assert(bounding_volume<ellipsoid<double, 3>>);
static_assert(bounding_volume<ellipsoid<float, 2>>);

}  // namespace spatial
