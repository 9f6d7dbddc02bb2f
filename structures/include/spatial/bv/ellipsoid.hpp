#pragma once
// spatial::ellipsoid<T, D> — bounding ellipsoid (an ellipse in 2D): a centre c, an
// orthonormal frame (rows of `axes`, u_k) and semi-axis lengths a_k:
//     x inside  <=>  sum_k ((x - c) . u_k / a_k)^2 <= 1.
// Every query evaluates exactly this form with the STORED (rounded) u_k and a_k, so the
// stored numbers define the set; the frame is orthonormal to T's precision.
//
// Fitting methods, fit_pca (principal axes, O(n D^2)) and fit_khachiyan (the minimum-volume
// enclosing ellipsoid to a certified relative volume tolerance), both containing every input
// point in floating point: ellipsoid_fit.hpp, where their method, guarantee and cost are
// described.
//
// Queries:
//   overlaps   EXACT up to rounding, by the Perram-Wertheim contact function (Perram &
//     Wertheim 1985): ellipsoid_overlap.hpp describes the evaluation and its tolerance.
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
#include "spatial/bv/ellipsoid_math.hpp"
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


template <class T, std::size_t D>
struct ellipsoid {
    static_assert(D == 2 || D == 3, "ellipsoid<T, D>: D must be 2 or 3");
    SPATIAL_POINT_MEMBER_TYPES(T, D);
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
    // Both contain every point (ellipsoid_fit.hpp describes methods, guarantees and costs).
    // Principal axes, scaled to contain: O(n D^2), no tightness guarantee.
    static ellipsoid fit_pca(std::span<const point_type> pts);
    // The minimum-volume enclosing ellipsoid to a relative volume tolerance (Khachiyan 1996;
    // Todd & Yildirim 2007); `report`, when given, receives what the ascent did.
    static ellipsoid fit_khachiyan(std::span<const point_type> pts, double tolerance = 1e-3,
                                   khachiyan_report* report = nullptr);

    // -------------------------------------------------------------------------- queries

    // max over l in [0, 1] of the Perram-Wertheim contact function, and the tolerance of the
    // decision (see ellipsoid_overlap.hpp). +inf when either is empty.
    struct contact {
        double value = std::numeric_limits<double>::infinity();  // max F found (a lower bound of max F)
        double upper = std::numeric_limits<double>::infinity();  // certified upper bound of max F
        double tolerance = 0;
        double lambda = 0.5;
    };
    contact contact_function(const ellipsoid& o) const { return contact_impl(o, false); }
    // Exact up to rounding: no false negatives, false positives only within the tolerance band.
    bool overlaps(const ellipsoid& o) const;

private:
    contact contact_impl(const ellipsoid& o, bool decide) const;

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
        // A candidate whose scaling overflowed is empty (scaled_to_contain); it must not win,
        // not even as the first one (the merge of a ball of the smallest normal radius with a
        // far ellipsoid was empty: found by fuzzing, docs/fuzzing.md).
        auto consider = [&](const ellipsoid& c) {
            if (!c.is_empty() && (best.is_empty() || c.volume_d() < best.volume_d())) best = c;
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
            // Infinite when g or h overflowed (max_quadratic_over_ball): empty below.
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

    // ------------------------------------------------------ fitting helpers (ellipsoid_fit.hpp)

    struct frame_fit {
        vec mean{};
        frame axes{};
        vec sigma{};      // spread along each axis, re-measured (descending up to rounding)
        std::size_t fat;  // axes 0..fat-1 have sigma > 1e-12 * max sigma
    };
    static frame_fit pca_frame(std::span<const point_type> pts, const char* where);

    static ellipsoid finish(std::span<const point_type> pts, const vec& c, const frame& f, vec a, std::size_t fat);

    // The Khachiyan ascent's state and its result in whitened coordinates (ellipsoid_fit.hpp).
    struct whitened_ellipsoid;
    struct khachiyan_solver;

    static void one_sided_jacobi_m(std::size_t m, std::array<std::array<double, D>, D>& g, std::array<double, D>& mu,
                                   std::array<std::array<double, D>, D>& v);
};

}  // namespace spatial

#include "spatial/bv/ellipsoid_fit.hpp"
#include "spatial/bv/ellipsoid_overlap.hpp"

namespace spatial {
static_assert(bounding_volume<ellipsoid<double, 3>>);
static_assert(bounding_volume<ellipsoid<float, 2>>);
}  // namespace spatial
