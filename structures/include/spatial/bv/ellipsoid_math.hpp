#pragma once
// spatial::ellipsoid — the small dense linear algebra the ellipsoid's fits and queries share,
// in double: the volume of the unit ball, a one-sided Jacobi SVD of a tiny matrix with high
// relative accuracy (Hestenes 1958; Demmel & Veselic 1992), and a certified upper bound on
// the maximum of a quadratic over the unit ball (Lagrangian duality), plus the directed
// rounding to T (bv/rounding.hpp).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>

#include "spatial/bv/rounding.hpp"

namespace spatial {

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
// An infinite or NaN entry (a frame so small that dividing by its semi-axes overflowed) has no
// finite bound: +infinity, which the caller treats as overflow. The SVD of such a matrix is NaN,
// and std::max(0, NaN) is 0: the bound came out as |g|^2, tiny, and the merged ellipsoid missed
// the far one (found by fuzzing, docs/fuzzing.md).
template <std::size_t D>
double max_quadratic_over_ball(const vec<D>& g, std::array<std::array<double, D>, D> h) {
    for (std::size_t i = 0; i < D; ++i) {
        if (!std::isfinite(g[i])) return std::numeric_limits<double>::infinity();
        for (std::size_t j = 0; j < D; ++j)
            if (!std::isfinite(h[i][j])) return std::numeric_limits<double>::infinity();
    }
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

}  // namespace spatial
