#pragma once
// The thick ray (a capsule of radius r around the half-line origin + t * direction, t >= 0)
// against any CONVEX object that can report its squared distance to a point. Used by the
// object types for thickness > 0 (thickness 0 has exact closed forms in each type).
//
// f(t) = squared distance from the ray point at t to the object is convex in t (distance to a
// convex set is convex, and so is its square). The first t with f(t) <= r^2 is found by:
//   1. clipping the ray to the object's bounding box grown by r (outside it f > r^2);
//   2. if f <= r^2 at the clip entry, that is the answer;
//   3. else a golden-section search for the minimum of f on the clipped interval (f is
//      unimodal), then bisection on the decreasing part for f = r^2.
// Cost: O(log(range / ulp)) distance evaluations, about 200 at most. Deterministic: the
// oracle and every structure call the same function and get the same bits.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace spatial::objects::detail {

// Clip the line origin + t dir to the box [lo - r, hi + r]: returns false when it misses;
// else [t0, t1] (t may be negative). Zero direction components (either sign) are parallel
// slabs, tested without dividing.
template <class T, class P>
bool clip_to_grown_box(const T* lo, const T* hi, T r, const P& origin, const P& dir, std::size_t D, T& t0, T& t1) {
    t0 = -std::numeric_limits<T>::infinity();
    t1 = std::numeric_limits<T>::infinity();
    for (std::size_t i = 0; i < D; ++i) {
        const T a_lo = lo[i] - r, a_hi = hi[i] + r;
        if (dir[i] == 0) {
            if (origin[i] < a_lo || origin[i] > a_hi) return false;
            continue;
        }
        T a = (a_lo - origin[i]) / dir[i], b = (a_hi - origin[i]) / dir[i];
        if (a > b) std::swap(a, b);
        t0 = std::max(t0, a);
        t1 = std::min(t1, b);
        if (t0 > t1) return false;
    }
    return true;
}

// First t in [0, t_limit) at which squared_distance_at(t) <= r * r, for a convex object whose
// bounding box is [lo, hi]. Returns false if there is none.
template <class T, class P, class DistanceAt>
bool first_capsule_contact(const T* lo, const T* hi, std::size_t D, const P& origin, const P& dir, T r,
                           T t_limit, DistanceAt&& squared_distance_at, T& t_hit) {
    T ta, tb;
    if (!clip_to_grown_box(lo, hi, r, origin, dir, D, ta, tb)) return false;
    ta = std::max(ta, T(0));
    if (!(ta <= tb) || !(ta < t_limit)) return false;
    const T r2 = r * r;
    if (squared_distance_at(ta) <= r2) {
        t_hit = ta;
        return true;
    }
    // Golden-section search for the minimum of the convex f on [ta, tb].
    const T inv_phi = T(0.6180339887498949);
    T a = ta, b = tb;
    T c = b - inv_phi * (b - a), d = a + inv_phi * (b - a);
    T fc = squared_distance_at(c), fd = squared_distance_at(d);
    for (int it = 0; it < 160 && fc > r2 && fd > r2; ++it) {
        if (fc <= fd) {
            b = d;
            d = c;
            fd = fc;
            c = b - inv_phi * (b - a);
            if (!(c > a && c < d)) break;
            fc = squared_distance_at(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + inv_phi * (b - a);
            if (!(d > c && d < b)) break;
            fd = squared_distance_at(d);
        }
    }
    T inside;  // a parameter with f <= r^2, if any was found
    if (fc <= r2) inside = c;
    else if (fd <= r2) inside = d;
    else return false;
    // Bisection on [ta, inside]: f(ta) > r^2 >= f(inside), f decreasing there.
    T out = ta;
    for (int it = 0; it < 200; ++it) {
        const T mid = out + (inside - out) / 2;
        if (!(mid > out && mid < inside)) break;
        if (squared_distance_at(mid) <= r2) inside = mid;
        else out = mid;
    }
    if (!(inside < t_limit)) return false;
    t_hit = inside;
    return true;
}

}  // namespace spatial::objects::detail
