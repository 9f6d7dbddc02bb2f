#pragma once
// spatial::objects::sphere<T, D> — a solid ball object (a disc in 2D): centre and radius.
//
// The ball is closed and solid: a ray starting inside hits at t = 0. Its bounding box is
// centre -/+ radius rounded outward by one ulp (a single rounding of c - r or c + r errs by at
// most half an ulp), so the box always contains the ball even where c +/- r is inexact.
// Ray test: the thick ray (capsule of radius tau) touches the ball of radius r exactly when the
// thin ray touches the ball of radius r + tau, so both are one quadratic. It is solved in the
// numerically stable closest-approach form (Haines, Günther & Akenine-Möller, "Precision
// Improvements for Ray/Sphere Intersection", Ray Tracing Gems, 2019): the squared distance
// of the ray's closest point is computed from the vector c - (o + t* d), not from b^2 - ac,
// which cancels catastrophically for small spheres far from the origin.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>

#include "spatial/bv/rounding.hpp"
#include "spatial/core/point.hpp"
#include "spatial/objects/box.hpp"

namespace spatial::objects {

template <class T, std::size_t D>
class sphere {
public:
    SPATIAL_POINT_MEMBER_TYPES(T, D);

    sphere() { update_bounds(); }
    // Throws std::invalid_argument for a negative or NaN radius (a NaN centre is reported by
    // the container that stores it, like any non-finite object).
    sphere(const point_type& center, T radius) : center_(center), radius_(radius) {
        if (!(radius >= T(0)))
            throw std::invalid_argument("objects::sphere: the radius must be >= 0 (got a negative or NaN radius)");
        update_bounds();
    }

    const point_type& center() const { return center_; }
    T radius() const { return radius_; }
    const T* get_min_bound() const { return lo_.data(); }
    const T* get_max_bound() const { return hi_.data(); }
    friend bool operator==(const sphere& a, const sphere& b) {
        return a.center_ == b.center_ && a.radius_ == b.radius_;
    }

    // max(0, |p - c| - r)^2: 0 inside.
    T squared_distance(const point_type& p) const {
        T s = 0;
        for (std::size_t i = 0; i < D; ++i) s += (p[i] - center_[i]) * (p[i] - center_[i]);
        const T d = std::sqrt(s) - radius_;
        return d > T(0) ? d * d : T(0);
    }
    // The ball meets the closed box iff the box's nearest point to the centre is within r.
    bool overlaps_box(const point_type& a, const point_type& b) const {
        T s = 0;
        for (std::size_t i = 0; i < D; ++i) {
            const T d = center_[i] < a[i] ? a[i] - center_[i] : (center_[i] > b[i] ? center_[i] - b[i] : T(0));
            s += d * d;
        }
        return s <= radius_ * radius_;
    }

    template <class Info>
    bool intersect(const point_type& origin, const point_type& direction, T thickness, Info& info) const {
        const T R = radius_ + (thickness > T(0) ? thickness : T(0));
        T a = 0, b = 0;  // a = d.d, b = (o - c).d
        for (std::size_t i = 0; i < D; ++i) {
            a += direction[i] * direction[i];
            b += (origin[i] - center_[i]) * direction[i];
        }
        if (!(a > T(0))) return false;  // zero direction: containers reject it before calling
        const T t_closest = -b / a;
        T h2 = 0;  // squared distance from the centre to the line's closest point
        for (std::size_t i = 0; i < D; ++i) {
            const T e = origin[i] + t_closest * direction[i] - center_[i];
            h2 += e * e;
        }
        const T R2 = R * R;
        if (h2 > R2) return false;
        const T half_chord = std::sqrt((R2 - h2) / a);
        const T t_exit = t_closest + half_chord;
        if (t_exit < T(0)) return false;
        // The origin itself may be inside although rounding put t_entry slightly below 0.
        const T t = std::max(t_closest - half_chord, T(0));
        if (!(t < info.hit_time)) return false;
        info.hit_time = t;
        for (std::size_t i = 0; i < D; ++i) info.hit_location[i] = origin[i] + t * direction[i];
        return true;
    }

    // The course's split: bounding boxes of the parts with normal . x <= offset (left) and
    // >= offset (right). Exact caps (rounded outward) for axis-aligned planes; for oblique
    // planes each side that the ball reaches gets the ball's whole box.
    void split(const T* normal, T offset, box<T, D>& left, box<T, D>& right) const {
        const box<T, D> whole = bounding_box();
        std::size_t axis = D, nonzero = 0;
        T norm2 = 0;
        for (std::size_t i = 0; i < D; ++i) {
            norm2 += normal[i] * normal[i];
            if (normal[i] != 0) {
                axis = i;
                ++nonzero;
            }
        }
        if (nonzero != 1) {
            T cn = 0;
            for (std::size_t i = 0; i < D; ++i) cn += normal[i] * center_[i];
            const T reach = radius_ * std::sqrt(norm2);
            left = cn - reach <= offset ? whole : box<T, D>::inverted();
            right = cn + reach >= offset ? whole : box<T, D>::inverted();
            return;
        }
        const T s = offset / normal[axis];  // the plane x[axis] = s
        box<T, D>& below = normal[axis] > 0 ? left : right;
        box<T, D>& above = normal[axis] > 0 ? right : left;
        below = cap(axis, s, /*keep_below=*/true);
        above = cap(axis, s, /*keep_below=*/false);
    }

    box<T, D> bounding_box() const {
        box<T, D> b;
        b.lo = lo_;
        b.hi = hi_;
        return b;
    }

private:
    void update_bounds() {
        for (std::size_t i = 0; i < D; ++i) {
            lo_[i] = radius_ == T(0) ? center_[i] : detail_rounding::next_down(center_[i] - radius_);
            hi_[i] = radius_ == T(0) ? center_[i] : detail_rounding::next_up(center_[i] + radius_);
        }
    }

    // Box of the part of the ball on one side of x[axis] = s.
    box<T, D> cap(std::size_t axis, T s, bool keep_below) const {
        box<T, D> b = bounding_box();
        const T c = center_[axis];
        if (keep_below ? s < lo_[axis] : s > hi_[axis]) return box<T, D>::inverted();
        if (keep_below) b.hi[axis] = std::min(b.hi[axis], s);
        else b.lo[axis] = std::max(b.lo[axis], s);
        // The cap is narrower than the ball only when the plane does not pass the centre.
        const bool narrower = keep_below ? s < c : s > c;
        if (narrower) {
            const T h = keep_below ? c - s : s - c;  // distance from the centre to the plane, > 0
            const T rho2 = radius_ * radius_ - h * h;
            const T rho = detail_rounding::next_up(std::sqrt(std::max(rho2, T(0))) *
                                                   (T(1) + 4 * std::numeric_limits<T>::epsilon()));
            for (std::size_t i = 0; i < D; ++i) {
                if (i == axis) continue;
                b.lo[i] = std::max(b.lo[i], detail_rounding::next_down(center_[i] - rho));
                b.hi[i] = std::min(b.hi[i], detail_rounding::next_up(center_[i] + rho));
            }
        }
        return b;
    }

    point_type center_{};
    T radius_ = 0;
    std::array<T, D> lo_{}, hi_{};
};

}  // namespace spatial::objects
