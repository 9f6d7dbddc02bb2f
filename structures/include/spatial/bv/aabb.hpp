#pragma once
// spatial::aabb<T, D> — axis-aligned bounding box, the cheapest volume of the study.
// Fit: min/max per axis, O(n D) (exact: the tightest axis-aligned box). Overlap: interval
// test per axis, exact. Ray: slab test (Kay & Kajiya 1986) written so that zero and
// negative-zero direction components and origins on a slab plane behave (no 0 * inf NaN).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <stdexcept>

#include "spatial/bv/bounding_volume.hpp"
#include "spatial/core/distance.hpp"
#include "spatial/core/point.hpp"
#include "spatial/core/rigid_transform.hpp"

namespace spatial {

template <class T, std::size_t D>
struct aabb {
    SPATIAL_POINT_MEMBER_TYPES(T, D);

    point_type lo, hi;  // lo[i] <= hi[i] for a non-empty box

    // Bitwise-equal corners (-0 == +0 as for any double).
    friend constexpr bool operator==(const aabb&, const aabb&) = default;

    // The empty box (contains nothing; merging with it is the identity).
    static aabb empty() {
        aabb b;
        b.lo.coords.fill(std::numeric_limits<T>::infinity());
        b.hi.coords.fill(-std::numeric_limits<T>::infinity());
        return b;
    }
    bool is_empty() const {
        for (std::size_t i = 0; i < D; ++i)
            if (!(lo[i] <= hi[i])) return true;
        return false;
    }

    static aabb fit(std::span<const point_type> pts) {
        aabb b = empty();
        for (const auto& p : pts) b.expand(p);
        return b;
    }
    void expand(const point_type& p) {
        for (std::size_t i = 0; i < D; ++i) {
            lo[i] = std::min(lo[i], p[i]);
            hi[i] = std::max(hi[i], p[i]);
        }
    }

    bool contains(const point_type& p) const {
        for (std::size_t i = 0; i < D; ++i)
            if (p[i] < lo[i] || p[i] > hi[i]) return false;
        return true;
    }
    bool overlaps(const aabb& o) const {  // exact; touching boxes overlap
        for (std::size_t i = 0; i < D; ++i)
            if (o.hi[i] < lo[i] || hi[i] < o.lo[i]) return false;
        return true;
    }
    bool ray_interval(const point_type& o, const point_type& d, T& t0, T& t1) const {
        t0 = -std::numeric_limits<T>::infinity();
        t1 = std::numeric_limits<T>::infinity();
        for (std::size_t i = 0; i < D; ++i) {
            if (d[i] == 0) {  // parallel to the slab: inside it or never
                if (o[i] < lo[i] || o[i] > hi[i]) return false;
                continue;
            }
            T a = (lo[i] - o[i]) / d[i], b = (hi[i] - o[i]) / d[i];
            if (a > b) std::swap(a, b);
            t0 = std::max(t0, a);
            t1 = std::min(t1, b);
            if (t0 > t1) return false;
        }
        return !is_empty();
    }
    T distance_lower_bound(const point_type& p) const {  // exact Euclidean distance to the box
        return std::sqrt(box_squared_distance<T, D>(p, lo, hi));
    }
    aabb merged(const aabb& o) const {
        aabb b;
        for (std::size_t i = 0; i < D; ++i) {
            b.lo[i] = std::min(lo[i], o.lo[i]);
            b.hi[i] = std::max(hi[i], o.hi[i]);
        }
        return b;
    }
    // Box of the rotated box (Arvo 1990, "Transforming axis-aligned bounding boxes", Graphics
    // Gems): per output axis, the centre moves by R c + t and the half-extent is sum |R_ij| e_j.
    // Exact as a box of the moved box; looser than refitting the moved points.
    aabb transformed(const rigid_transform<T, D>& xf) const {
        if (is_empty()) return *this;
        aabb b;
        for (std::size_t i = 0; i < D; ++i) {
            T c = xf.translation[i], e = 0;
            for (std::size_t j = 0; j < D; ++j) {
                c += xf.rotation[i][j] * (lo[j] + (hi[j] - lo[j]) / 2);
                e += std::abs(xf.rotation[i][j]) * ((hi[j] - lo[j]) / 2);
            }
            // Round outward by a few ulps: the moved box must contain the moved corners.
            const T pad = (std::abs(c) + e) * std::numeric_limits<T>::epsilon() * 4;
            b.lo[i] = c - e - pad;
            b.hi[i] = c + e + pad;
        }
        return b;
    }
    T volume() const {  // area in 2D
        if (is_empty()) return 0;
        T v = 1;
        for (std::size_t i = 0; i < D; ++i) v *= hi[i] - lo[i];
        return v;
    }
    T surface_area() const {  // perimeter in 2D; sum over faces in higher D
        if (is_empty()) return 0;
        T s = 0;
        for (std::size_t i = 0; i < D; ++i) {
            T face = 1;
            for (std::size_t j = 0; j < D; ++j)
                if (j != i) face *= hi[j] - lo[j];
            s += 2 * face;
        }
        return s;
    }
};

static_assert(bounding_volume<aabb<double, 3>>);
static_assert(bounding_volume<aabb<float, 2>>);

}  // namespace spatial
