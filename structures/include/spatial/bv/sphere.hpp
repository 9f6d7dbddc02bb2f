#pragma once
// spatial::sphere<T, D> — bounding ball (a disc in 2D). Fitting methods, increasing in cost
// and tightness:
//   fit_centroid_farthest: centre = centroid, radius = farthest point. O(n D).
//   fit_ritter: Ritter's approximate ball (Ritter 1990, "An efficient bounding sphere",
//     Graphics Gems): seed with a far pair, grow to swallow outliers. O(n D), typically
//     within 5-20% of the minimum radius.
//   (exact minimum enclosing ball, Welzl 1991: planned, see issue 3.)
// Every fit ends with one pass that sets the radius to the farthest point from the final
// centre, rounded up so that contains() holds for every input point in floating point.
// Overlap and ray tests are exact up to rounding.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <span>
#include <stdexcept>

#include "spatial/bv/bounding_volume.hpp"
#include "spatial/core/distance.hpp"
#include "spatial/core/point.hpp"

namespace spatial {

template <class T, std::size_t D>
struct sphere {
    using scalar_type = T;
    using point_type = point<T, D>;
    static constexpr std::size_t dimension = D;

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
    // The smallest ball containing both balls.
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
        s.radius = std::nextafter(s.radius, std::numeric_limits<T>::infinity());
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
    static sphere enclose_from(const point_type& c, std::span<const point_type> pts) {
        T m = 0;
        for (const auto& p : pts) m = std::max(m, squared_distance(p, c));
        T r = std::sqrt(m);
        while (r * r < m) r = std::nextafter(r, std::numeric_limits<T>::infinity());
        sphere s;
        s.center = c;
        s.radius = r;
        return s;
    }
};

static_assert(bounding_volume<sphere<double, 3>>);
static_assert(bounding_volume<sphere<float, 2>>);

}  // namespace spatial
