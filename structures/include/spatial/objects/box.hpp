#pragma once
// spatial::objects::box<T, D> — an axis-aligned box object (the course's non-point object):
// get_min_bound / get_max_bound / split, a thick-ray test, exact point distance.
//
// A box is closed: points on its faces belong to it, and rays touching a face or an edge hit
// it. Ray test (thickness 0): slab test (Kay & Kajiya 1986) with zero and negative-zero
// direction components handled without 0 * inf; an origin inside or on the box hits at t = 0.
// Thickness > 0: the first contact of the capsule (thick_ray.hpp). split(): the course's
// interface — the boxes of the parts on either side of a plane; exact for axis-aligned planes,
// conservative (each side gets the whole box) for oblique ones. An empty part is returned as an
// inverted box (lo > hi on some axis); see is_empty().

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

#include "spatial/core/distance.hpp"
#include "spatial/core/point.hpp"
#include "spatial/objects/thick_ray.hpp"

namespace spatial::objects {

template <class T, std::size_t D>
struct box {
    SPATIAL_POINT_MEMBER_TYPES(T, D);

    std::array<T, D> lo{}, hi{};

    box() = default;
    // The box spanned by two corners (in any order).
    box(const point_type& a, const point_type& b) {
        for (std::size_t i = 0; i < D; ++i) {
            lo[i] = std::min(a[i], b[i]);
            hi[i] = std::max(a[i], b[i]);
            // std::min and std::max return their first argument when the second is NaN: a NaN
            // corner b gave the finite point box of a, which containers accepted.
            if (std::isnan(a[i]) || std::isnan(b[i])) lo[i] = hi[i] = std::numeric_limits<T>::quiet_NaN();
        }
    }
    static box inverted() {
        box b;
        b.lo.fill(std::numeric_limits<T>::infinity());
        b.hi.fill(-std::numeric_limits<T>::infinity());
        return b;
    }

    const T* get_min_bound() const { return lo.data(); }
    const T* get_max_bound() const { return hi.data(); }
    bool is_empty() const {
        for (std::size_t i = 0; i < D; ++i)
            if (!(lo[i] <= hi[i])) return true;
        return false;
    }
    friend bool operator==(const box&, const box&) = default;

    point_type center() const {
        point_type c;
        for (std::size_t i = 0; i < D; ++i) c[i] = lo[i] + (hi[i] - lo[i]) / 2;
        return c;
    }

    T squared_distance(const point_type& p) const {
        return box_squared_distance<T, D>(p, lo, hi);
    }
    bool overlaps_box(const point_type& a, const point_type& b) const {
        for (std::size_t i = 0; i < D; ++i)
            if (hi[i] < a[i] || lo[i] > b[i]) return false;
        return true;
    }
    template <class F>
    void for_each_hull_point(F&& f) const {
        for (std::size_t mask = 0; mask < (std::size_t(1) << D); ++mask) {
            point_type p;
            for (std::size_t i = 0; i < D; ++i) p[i] = (mask >> i) & 1 ? hi[i] : lo[i];
            f(p);
        }
    }

    template <class Info>
    bool intersect(const point_type& origin, const point_type& direction, T thickness, Info& info) const {
        T t;
        if (thickness > T(0)) {
            if (!detail::first_capsule_contact(lo.data(), hi.data(), D, origin, direction, thickness, info.hit_time,
                                               [&](T s) { return squared_distance(at(origin, direction, s)); }, t))
                return false;
        } else {
            T t0, t1;
            if (!detail::clip_to_grown_box(lo.data(), hi.data(), T(0), origin, direction, D, t0, t1)) return false;
            if (t1 < T(0)) return false;
            t = std::max(t0, T(0));
            if (!(t < info.hit_time)) return false;
        }
        info.hit_time = t;
        info.hit_location = at(origin, direction, t);
        return true;
    }

    // The course's split: left gets the part with normal . x <= offset, right the rest.
    void split(const T* normal, T offset, box& left, box& right) const {
        std::size_t axis = D, nonzero = 0;
        for (std::size_t i = 0; i < D; ++i)
            if (normal[i] != 0) {
                axis = i;
                ++nonzero;
            }
        left = right = *this;
        if (nonzero != 1) {  // oblique plane: conservative, unless the box is on one side
            T lo_dot = 0, hi_dot = 0;  // range of normal . x over the box
            for (std::size_t i = 0; i < D; ++i) {
                lo_dot += std::min(normal[i] * lo[i], normal[i] * hi[i]);
                hi_dot += std::max(normal[i] * lo[i], normal[i] * hi[i]);
            }
            if (hi_dot < offset) right = inverted();
            if (lo_dot > offset) left = inverted();
            return;
        }
        const T s = offset / normal[axis];  // the plane is x[axis] = s
        box& below = normal[axis] > 0 ? left : right;
        box& above = normal[axis] > 0 ? right : left;
        if (s < lo[axis]) below = inverted();
        else below.hi[axis] = std::min(hi[axis], s);
        if (s > hi[axis]) above = inverted();
        else above.lo[axis] = std::max(lo[axis], s);
    }

private:
    static point_type at(const point_type& o, const point_type& d, T t) {
        point_type p;
        for (std::size_t i = 0; i < D; ++i) p[i] = o[i] + t * d[i];
        return p;
    }
};

}  // namespace spatial::objects
