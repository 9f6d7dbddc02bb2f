#pragma once
// spatial::sphere<T, D> — bounding ball (a disc in 2D). Fitting methods, increasing in cost
// and tightness:
//   fit_centroid_farthest: centre = centroid, radius = farthest point. O(n D).
//   fit_ritter: Ritter's approximate ball (Ritter 1990, "An efficient bounding sphere",
//     Graphics Gems): seed with a far pair, grow to swallow outliers. O(n D), typically
//     within 5-20% of the minimum radius.
//   fit_minimum: the minimum enclosing ball, Welzl's algorithm (Welzl 1991) in Gartner's
//     move-to-front form with pivoting (Gartner 1999, "Fast and robust smallest enclosing
//     balls"): each round finds the point farthest outside the current ball in one O(n)
//     pass and re-solves move-to-front on the short front of the list; a handful of rounds
//     in practice, recursion depth <= D + 1. A support
//     point that is (nearly) affinely dependent on the current support is not pushed (as in
//     Gartner's pivoting), so degenerate input (duplicates, collinear, coplanar) never
//     produces NaN; the final enclosing pass keeps containment exact.
// Every fit ends with one pass that sets the radius to the farthest point from the final
// centre, rounded up so that contains() holds for every input point in floating point.
// Overlap and ray tests are exact up to rounding.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <array>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <vector>

#include "spatial/bv/bounding_volume.hpp"
#include "spatial/bv/gauss_jordan.hpp"
#include "spatial/core/distance.hpp"
#include "spatial/core/point.hpp"
#include "spatial/core/rigid_transform.hpp"

namespace spatial {

template <class T, std::size_t D>
struct sphere {
    SPATIAL_POINT_MEMBER_TYPES(T, D);

    point_type center{};
    T radius = -1;  // negative: the empty ball

    bool is_empty() const { return radius < 0; }

    static sphere fit_centroid_farthest(std::span<const point_type> pts) {
        if (pts.empty()) return {};
        point_type c{};
        // Centroid relative to the first point: no loss of precision at large offsets.
        for (const auto& p : pts)
            for (std::size_t i = 0; i < D; ++i) c[i] += p[i] - pts[0][i];
        for (std::size_t i = 0; i < D; ++i) c[i] = pts[0][i] + c[i] / static_cast<T>(pts.size());
        return enclose_from(c, pts);
    }

    static sphere fit_ritter(std::span<const point_type> pts) {
        if (pts.empty()) return {};
        // Seed: from point 0 the farthest point a, from a the farthest point b.
        auto farthest = [&](const point_type& from) {
            std::size_t best = 0;
            T bd = -1;
            for (std::size_t i = 0; i < pts.size(); ++i) {
                const T d = squared_distance(pts[i], from);
                if (d > bd) bd = d, best = i;
            }
            return pts[best];
        };
        const point_type a = farthest(pts[0]);
        const point_type b = farthest(a);
        point_type c;
        for (std::size_t i = 0; i < D; ++i) c[i] = a[i] + (b[i] - a[i]) / 2;
        T r = std::sqrt(squared_distance(a, b)) / 2;
        // Grow: a point outside moves the centre toward it by half the excess.
        for (const auto& p : pts) {
            const T d2 = squared_distance(p, c);
            if (d2 <= r * r) continue;
            const T d = std::sqrt(d2);
            const T nr = (r + d) / 2;
            const T shift = (d - nr) / d;
            for (std::size_t i = 0; i < D; ++i) c[i] += (p[i] - c[i]) * shift;
            r = nr;
        }
        return enclose_from(c, pts);
    }

    static sphere fit_minimum(std::span<const point_type> pts) {
        if (pts.empty()) return {};
        // Work relative to the first point (precision at large offsets).
        const point_type origin = pts[0];
        std::vector<std::array<double, D>> q(pts.size());
        for (std::size_t i = 0; i < pts.size(); ++i)
            for (std::size_t d = 0; d < D; ++d) q[i][d] = static_cast<double>(pts[i][d]) - static_cast<double>(origin[d]);
        detail_min_ball mb(q);
        mb.solve();
        point_type c;
        for (std::size_t d = 0; d < D; ++d) c[d] = static_cast<T>(static_cast<double>(origin[d]) + mb.center[d]);
        return enclose_from(c, pts);
    }

    bool contains(const point_type& p) const { return !is_empty() && squared_distance(p, center) <= radius * radius; }
    bool overlaps(const sphere& o) const {
        if (is_empty() || o.is_empty()) return false;
        const T s = radius + o.radius;
        return squared_distance(center, o.center) <= s * s;
    }
    // Robust line/ball intersection: the discriminant from the perpendicular offset rather
    // than b^2 - ac (Haines, Guenther & Akenine-Moller, Ray Tracing Gems 2019, ch. 7).
    bool ray_interval(const point_type& o, const point_type& d, T& t0, T& t1) const {
        if (is_empty()) return false;
        T a = 0, b = 0;
        for (std::size_t i = 0; i < D; ++i) {
            a += d[i] * d[i];
            b += d[i] * (center[i] - o[i]);
        }
        if (!(a > 0)) return false;
        T f2 = 0;  // squared distance from the centre to the line
        for (std::size_t i = 0; i < D; ++i) {
            const T f = (center[i] - o[i]) - (b / a) * d[i];
            f2 += f * f;
        }
        const T disc = radius * radius - f2;
        if (disc < 0) return false;
        const T h = std::sqrt(disc / a);
        t0 = b / a - h;
        t1 = b / a + h;
        return true;
    }
    T distance_lower_bound(const point_type& p) const {
        return std::max(T(0), std::sqrt(squared_distance(p, center)) - radius);
    }
    // The smallest ball containing both balls, its radius then taken from the ROUNDED centre:
    // far enough to reach each ball from there (padded). The centre is rounded to the nearest
    // representable point, which moves it by up to half an ulp of its coordinates; for two
    // points one ulp apart that is the whole radius, and the exact radius from the exact centre
    // left one of them outside (soak finding: a bvh<sphere> missed intersecting pairs).
    sphere merged(const sphere& o) const {
        if (is_empty()) return o;
        if (o.is_empty()) return *this;
        const T d = std::sqrt(squared_distance(center, o.center));
        if (d + o.radius <= radius) return *this;
        if (d + radius <= o.radius) return o;
        sphere s;
        s.radius = (d + radius + o.radius) / 2;
        const T w = (s.radius - radius) / d;  // d > 0 here
        for (std::size_t i = 0; i < D; ++i) s.center[i] = center[i] + (o.center[i] - center[i]) * w;
        const T reach_this = std::sqrt(squared_distance(s.center, center)) + radius;
        const T reach_other = std::sqrt(squared_distance(s.center, o.center)) + o.radius;
        s.radius = padded(std::max(s.radius, std::max(reach_this, reach_other)));
        return s;
    }
    // Exact: a rigid motion moves the centre and keeps the radius (one ulp of slack for the
    // rounding of the moved centre).
    sphere transformed(const rigid_transform<T, D>& xf) const {
        if (is_empty()) return *this;
        sphere s;
        s.center = xf.apply(center);
        T m = std::abs(radius);
        for (std::size_t i = 0; i < D; ++i) m = std::max(m, std::abs(s.center[i]));
        s.radius = radius + m * std::numeric_limits<T>::epsilon() * 4;
        return s;
    }
    T volume() const {  // unit-ball volume pi^(D/2) / Gamma(D/2 + 1) times r^D
        if (is_empty()) return 0;
        const double unit = std::pow(std::numbers::pi, D / 2.0) / std::tgamma(D / 2.0 + 1);
        return static_cast<T>(unit * std::pow(static_cast<double>(radius), static_cast<double>(D)));
    }
    T surface_area() const {  // D * unit-ball volume * r^(D-1): 2 pi r in 2D, 4 pi r^2 in 3D
        if (is_empty()) return 0;
        const double unit = std::pow(std::numbers::pi, D / 2.0) / std::tgamma(D / 2.0 + 1);
        return static_cast<T>(static_cast<double>(D) * unit * std::pow(static_cast<double>(radius), static_cast<double>(D) - 1));
    }

private:
    // Move-to-front Welzl over a list of points, in double precision. The support (points
    // on the boundary of the current ball) is kept as an orthogonal-ish basis: the centre
    // of the circumball of s0..sk lies in their affine hull and is found by solving the
    // k x k Gram system 2 (v_i . v_j) l_j = |v_i|^2 with v_i = s_i - s0.
    struct detail_min_ball {
        using vec = std::array<double, D>;
        std::vector<vec>& pts;
        std::vector<std::size_t> order;  // move-to-front list of point indices
        vec support[D + 1];
        std::size_t support_size = 0;
        vec center{};
        double r2 = -1;
        double scale = 0;  // squared extent, for relative tolerances

        explicit detail_min_ball(std::vector<vec>& p) : pts(p), order(p.size()) {
            for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
            for (const auto& x : pts)
                for (std::size_t d = 0; d < D; ++d) scale = std::max(scale, x[d] * x[d]);
            scale = std::max(scale, 1e-300);
        }
        static double dist2(const vec& a, const vec& b) {
            double s = 0;
            for (std::size_t d = 0; d < D; ++d) s += (a[d] - b[d]) * (a[d] - b[d]);
            return s;
        }
        // Circumball of the current support; false if it is (nearly) affinely dependent.
        bool circumball(vec& c, double& rr) const {
            if (support_size == 0) return false;
            const vec& s0 = support[0];
            const std::size_t k = support_size - 1;
            if (k == 0) {
                c = s0;
                rr = 0;
                return true;
            }
            double a[D][D + 1];
            vec v[D];
            for (std::size_t i = 0; i < k; ++i)
                for (std::size_t d = 0; d < D; ++d) v[i][d] = support[i + 1][d] - s0[d];
            for (std::size_t i = 0; i < k; ++i) {
                for (std::size_t j = 0; j < k; ++j) {
                    double g = 0;
                    for (std::size_t d = 0; d < D; ++d) g += v[i][d] * v[j][d];
                    a[i][j] = 2 * g;
                }
                double n2 = 0;
                for (std::size_t d = 0; d < D; ++d) n2 += v[i][d] * v[i][d];
                a[i][k] = n2;
            }
            // Gaussian elimination with partial pivoting; a tiny pivot means the support is
            // affinely dependent.
            if (!detail::gauss_jordan(a, k, [&](double pivot) { return !(std::abs(pivot) <= 1e-12 * scale); }))
                return false;
            c = s0;
            for (std::size_t i = 0; i < k; ++i) {
                const double l = a[i][k] / a[i][i];
                for (std::size_t d = 0; d < D; ++d) c[d] += l * v[i][d];
            }
            rr = dist2(c, s0);
            return std::isfinite(rr);
        }
        bool push(const vec& p) {
            support[support_size++] = p;
            vec c;
            double rr;
            if (!circumball(c, rr)) {
                --support_size;
                return false;
            }
            center = c;
            r2 = rr;
            return true;
        }
        void move_to_front(std::size_t i) {
            const std::size_t idx = order[i];
            std::copy_backward(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(i),
                               order.begin() + static_cast<std::ptrdiff_t>(i) + 1);
            order[0] = idx;
        }
        double excess(std::size_t idx) const { return r2 < 0 ? 1 : dist2(pts[idx], center) - r2; }
        // Gartner's mtf_mb: the smallest ball of the first `end` list entries with the
        // current support on its boundary.
        void mtf(std::size_t end) {
            if (support_size == D + 1) return;
            for (std::size_t i = 0; i < end; ++i) {
                const std::size_t idx = order[i];
                if (excess(idx) > 1e-13 * scale) {
                    if (push(pts[idx])) {
                        mtf(i);
                        --support_size;
                        move_to_front(i);
                    }
                }
            }
        }
        // Gartner's pivot_mb: keep the important points in a front prefix of the list;
        // each round scans ALL points for the largest excess, puts that pivot on the
        // boundary, re-solves move-to-front on the front prefix, and moves the pivot into
        // the front. Stops when nothing is outside (or the ball stops growing, which only
        // rounding can cause; the final enclosing pass then covers the rest).
        void solve() {
            r2 = -1;
            std::size_t front = 1;
            mtf(front);
            while (true) {
                std::size_t pivot = 0;
                double max_e = 0;
                for (std::size_t i = 0; i < order.size(); ++i) {
                    const double e = excess(order[i]);
                    if (e > max_e) max_e = e, pivot = i;
                }
                if (!(max_e > 1e-13 * scale)) break;
                const double old_r2 = r2;
                if (!push(pts[order[pivot]])) break;
                mtf(std::min(front, pivot));
                --support_size;
                move_to_front(pivot);
                if (pivot >= front) ++front;
                if (!(r2 > old_r2)) break;
            }
            if (r2 < 0) center = pts[0], r2 = 0;
        }
    };

    static sphere enclose_from(const point_type& c, std::span<const point_type> pts) {
        T m = 0;
        for (const auto& p : pts) m = std::max(m, squared_distance(p, c));
        T r = std::sqrt(m);
        while (r * r < m) r = std::nextafter(r, std::numeric_limits<T>::infinity());
        sphere s;
        s.center = c;
        s.radius = padded(r);
        return s;
    }

    // A radius grown by 8 ulps of itself and one more step (0 becomes the smallest denormal).
    // contains() and overlaps() compare ROUNDED squared distances: a point the rounded test puts
    // on a ball's surface may be a few ulps outside it, and two balls holding the same such
    // point then "touch" by a few ulps too little and do not overlap. With this margin every
    // rounding of the two tests stays inside it (soak finding: a bvh<sphere> missed the pair of
    // two equal points in different leaves).
    static T padded(T r) {
        return std::nextafter(r + r * (8 * std::numeric_limits<T>::epsilon()), std::numeric_limits<T>::infinity());
    }
};

static_assert(bounding_volume<sphere<double, 3>>);
static_assert(bounding_volume<sphere<float, 2>>);

}  // namespace spatial
