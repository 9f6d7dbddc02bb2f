#pragma once
// The geometric questions a container asks of a stored object, answered uniformly for points
// and for bounded objects (object_concepts.hpp). One definition used by every structure AND by
// the brute-force oracle, so exact answers compare bit for bit.
//
//   object_lower(o, i), object_upper(o, i)   the bounding box (a point is its own box)
//   object_center(o, i)                      the box centre (the key of object partitioning)
//   object_squared_distance(o, p)            exact if O has squared_distance(p), else the
//                                            squared distance to its box (0 inside)
//   object_overlaps_box(o, lo, hi)           closed-box test; exact if O has overlaps_box,
//                                            else box against box
//   object_in_ball(o, c, r)                  object_squared_distance(o, c) <= r^2
//   require_finite_object(o, where)          rejects NaN/inf bounds (and inverted boxes);
//                                            is_finite_object(o) the same as a test
// All O(1) for the ready object types.

#include <cmath>
#include <cstddef>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "spatial/core/distance.hpp"
#include "spatial/core/input_checks.hpp"
#include "spatial/core/object_concepts.hpp"

namespace spatial {

template <stored_object O>
constexpr typename O::scalar_type object_lower(const O& o, std::size_t i) {
    if constexpr (bounded_object<O>) return o.get_min_bound()[i];
    else return o[i];
}
template <stored_object O>
constexpr typename O::scalar_type object_upper(const O& o, std::size_t i) {
    if constexpr (bounded_object<O>) return o.get_max_bound()[i];
    else return o[i];
}
// Midpoint of the box, computed so that it never leaves [lower, upper] (no overflow for
// huge coordinates, no rounding outside the box).
template <stored_object O>
constexpr typename O::scalar_type object_center(const O& o, std::size_t i) {
    if constexpr (bounded_object<O>) {
        const auto lo = o.get_min_bound()[i], hi = o.get_max_bound()[i];
        const auto c = lo + (hi - lo) / 2;
        return c < lo ? lo : (c > hi ? hi : c);
    } else {
        return o[i];
    }
}

// Squared distance from p to the closed box [lo, hi] of the object (0 inside).
template <stored_object O>
typename O::scalar_type object_box_squared_distance(const O& o, const point_type_of<O>& p) {
    using T = typename O::scalar_type;
    T s = 0;
    for (std::size_t i = 0; i < O::dimension; ++i) {
        const T lo = object_lower(o, i), hi = object_upper(o, i);
        const T d = p[i] < lo ? lo - p[i] : (p[i] > hi ? p[i] - hi : T(0));
        s += d * d;
    }
    return s;
}

template <stored_object O>
typename O::scalar_type object_squared_distance(const O& o, const point_type_of<O>& p) {
    if constexpr (!bounded_object<O>) return squared_distance(o, p);
    else if constexpr (requires { { o.squared_distance(p) } -> std::convertible_to<typename O::scalar_type>; })
        return o.squared_distance(p);
    else return object_box_squared_distance(o, p);
}

template <stored_object O>
bool object_box_overlaps_box(const O& o, const point_type_of<O>& lo, const point_type_of<O>& hi) {
    for (std::size_t i = 0; i < O::dimension; ++i)
        if (object_upper(o, i) < lo[i] || object_lower(o, i) > hi[i]) return false;
    return true;
}

// Do the bounding boxes of two objects (of any stored types, same dimension) overlap? Closed:
// touching boxes overlap. The broad phases' final candidate test. O(D).
template <stored_object A, stored_object B>
bool object_boxes_overlap(const A& a, const B& b) {
    static_assert(A::dimension == B::dimension, "object_boxes_overlap: objects of different dimensions");
    for (std::size_t i = 0; i < A::dimension; ++i)
        if (object_upper(a, i) < object_lower(b, i) || object_upper(b, i) < object_lower(a, i)) return false;
    return true;
}

template <stored_object O>
bool object_overlaps_box(const O& o, const point_type_of<O>& lo, const point_type_of<O>& hi) {
    if constexpr (!bounded_object<O>) return in_closed_box(o, lo, hi);
    else if constexpr (requires { { o.overlaps_box(lo, hi) } -> std::same_as<bool>; })
        return object_box_overlaps_box(o, lo, hi) && o.overlaps_box(lo, hi);
    else return object_box_overlaps_box(o, lo, hi);
}

template <stored_object O>
bool object_in_ball(const O& o, const point_type_of<O>& center, typename O::scalar_type radius) {
    return object_squared_distance(o, center) <= radius * radius;
}

namespace detail {
// The first coordinate at which o is rejected: a point's NaN or infinite coordinate, an
// object's NaN, infinite or inverted bound; O::dimension when there is none.
template <stored_object O>
std::size_t first_non_finite_coordinate(const O& o) noexcept {
    for (std::size_t i = 0; i < O::dimension; ++i) {
        if constexpr (!bounded_object<O>) {
            if (!std::isfinite(o[i])) return i;
        } else {
            const auto lo = o.get_min_bound()[i], hi = o.get_max_bound()[i];
            if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo <= hi)) return i;
        }
    }
    return O::dimension;
}
// What require_finite_object accepts, as a test (for a batch checked on every core, whose first
// rejected object is then reported by require_finite_object). Without a branch per coordinate:
// every insertion and every move of every structure runs it, and a finite bound lies in
// [-max, max], which neither a NaN nor an infinity does, so three comparisons per axis decide.
template <stored_object O>
bool is_finite_object(const O& o) noexcept {
    using T = typename O::scalar_type;
    constexpr T top = std::numeric_limits<T>::max();
    bool ok = true;
    for (std::size_t i = 0; i < O::dimension; ++i) {
        if constexpr (!bounded_object<O>) {
            ok &= -top <= o[i];
            ok &= o[i] <= top;
        } else {
            const auto lo = o.get_min_bound()[i], hi = o.get_max_bound()[i];
            ok &= -top <= lo;
            ok &= lo <= hi;
            ok &= hi <= top;
        }
    }
    return ok;
}
// The message for an object with extent that is_finite_object rejects: out of line, so that
// the check stays small where it is inlined.
template <stored_object O, class Where>
[[noreturn, gnu::noinline, gnu::cold]] void reject_object(const O& o, Where where) {
    const std::size_t i = first_non_finite_coordinate(o);
    std::ostringstream os;
    os << where << ": object has a non-finite or inverted bound at coordinate " << i << ": ["
       << o.get_min_bound()[i] << ", " << o.get_max_bound()[i] << "] (NaN and infinity are rejected)";
    throw std::invalid_argument(os.str());
}
template <stored_object O, class Where>
void require_finite_object(const O& o, Where where) {
    if constexpr (!bounded_object<O>) {
        require_finite(o, where, "point");
    } else if (!is_finite_object(o)) [[unlikely]] {
        reject_object(o, where);
    }
}
}  // namespace detail

}  // namespace spatial

namespace spatial {

// Calls f(point_type) for a finite set of points whose convex hull contains the object: what
// a bounding volume is fitted to when a BVH node's volume is built from its objects. Uses the
// object's own for_each_hull_point(f) when it has one (triangle: its vertices, box: its
// corners), else the 2^D corners of its bounding box (always correct, looser for round shapes).
template <stored_object O, class F>
void object_hull_points(const O& o, F&& f) {
    if constexpr (!bounded_object<O>) {
        f(o);
    } else if constexpr (requires { o.for_each_hull_point(f); }) {
        o.for_each_hull_point(f);
    } else {
        using P = point_type_of<O>;
        constexpr std::size_t D = O::dimension;
        for (std::size_t mask = 0; mask < (std::size_t(1) << D); ++mask) {
            P p{};
            for (std::size_t i = 0; i < D; ++i) p[i] = (mask >> i) & 1 ? o.get_max_bound()[i] : o.get_min_bound()[i];
            f(p);
        }
    }
}

}  // namespace spatial
