#pragma once
// spatial::collide::objects_intersect(a, b) — the narrow phase: do two stored objects (closed
// sets) intersect? One overload set for the library's objects, mixed types included:
//
//   box–box            exact (coordinate comparisons)
//   triangle–triangle  exact (orientation signs; collide/exact_intersection.hpp), 2D and 3D
//   point–point        exact (equal coordinates)
//   point–X            exact for box and triangle (the point inside the closed set), sphere:
//                      squared distance <= r^2 in floating point
//   sphere–sphere      |c1 - c2|^2 <= (r1 + r2)^2 in floating point
//   sphere–box, sphere–triangle   squared distance from the centre <= r^2 (floating point)
//   triangle–box       the triangle's separating-axis test (floating point)
// Any other stored_object pair (user types) falls back to its bounding boxes overlapping:
// conservative, documented as such — a user type gets exactness by overloading
// objects_intersect in its own namespace (found by argument-dependent lookup).
// Cost: O(1) per pair (triangle–triangle: 6 filtered orientations for most disjoint pairs).

#include <cstddef>

#include "spatial/collide/exact_intersection.hpp"
#include "spatial/core/object_concepts.hpp"
#include "spatial/core/object_geometry.hpp"
#include "spatial/objects/box.hpp"
#include "spatial/objects/sphere.hpp"
#include "spatial/objects/triangle.hpp"

namespace spatial::collide {

namespace detail {
template <class T, std::size_t D>
auto as_exact(const point<T, D>& p) {
    std::array<double, D> a;
    for (std::size_t i = 0; i < D; ++i) a[i] = static_cast<double>(p[i]);
    return a;
}
}  // namespace detail

template <class T, std::size_t D>
bool objects_intersect(const objects::box<T, D>& a, const objects::box<T, D>& b) {
    for (std::size_t i = 0; i < D; ++i)
        if (a.hi[i] < b.lo[i] || b.hi[i] < a.lo[i]) return false;
    return true;
}

template <class T, std::size_t D>
bool objects_intersect(const objects::triangle<T, D>& a, const objects::triangle<T, D>& b) {
    using detail::as_exact;
    return triangles_intersect(as_exact(a.vertex(0)), as_exact(a.vertex(1)), as_exact(a.vertex(2)), as_exact(b.vertex(0)),
                               as_exact(b.vertex(1)), as_exact(b.vertex(2)));
}

template <class T, std::size_t D>
bool objects_intersect(const objects::sphere<T, D>& a, const objects::sphere<T, D>& b) {
    T d2 = 0;
    for (std::size_t i = 0; i < D; ++i) {
        const T d = a.center()[i] - b.center()[i];
        d2 += d * d;
    }
    const T r = a.radius() + b.radius();
    return d2 <= r * r;
}

template <class T, std::size_t D>
bool objects_intersect(const point<T, D>& a, const point<T, D>& b) {
    for (std::size_t i = 0; i < D; ++i)
        if (a[i] != b[i]) return false;
    return true;
}

// A point in a closed triangle: coplanar (3D) and inside. Exact.
template <class T, std::size_t D>
bool objects_intersect(const point<T, D>& p, const objects::triangle<T, D>& t) {
    using detail::as_exact;
    const auto x = as_exact(p);
    return triangles_intersect(x, x, x, as_exact(t.vertex(0)), as_exact(t.vertex(1)), as_exact(t.vertex(2)));
}
template <class T, std::size_t D>
bool objects_intersect(const point<T, D>& p, const objects::box<T, D>& b) {
    for (std::size_t i = 0; i < D; ++i)
        if (p[i] < b.lo[i] || p[i] > b.hi[i]) return false;
    return true;
}
template <class T, std::size_t D>
bool objects_intersect(const point<T, D>& p, const objects::sphere<T, D>& s) {
    return s.squared_distance(p) <= 0;
}

template <class T, std::size_t D>
bool objects_intersect(const objects::sphere<T, D>& s, const objects::box<T, D>& b) {
    return b.squared_distance(s.center()) <= s.radius() * s.radius();
}
template <class T, std::size_t D>
bool objects_intersect(const objects::sphere<T, D>& s, const objects::triangle<T, D>& t) {
    return t.squared_distance(s.center()) <= s.radius() * s.radius();
}
template <class T, std::size_t D>
bool objects_intersect(const objects::triangle<T, D>& t, const objects::box<T, D>& b) {
    point<T, D> lo, hi;
    for (std::size_t i = 0; i < D; ++i) lo[i] = b.lo[i], hi[i] = b.hi[i];
    return t.overlaps_box(lo, hi);
}

// Mixed pairs in the other order.
template <class T, std::size_t D>
bool objects_intersect(const objects::triangle<T, D>& t, const point<T, D>& p) { return objects_intersect(p, t); }
template <class T, std::size_t D>
bool objects_intersect(const objects::box<T, D>& b, const point<T, D>& p) { return objects_intersect(p, b); }
template <class T, std::size_t D>
bool objects_intersect(const objects::sphere<T, D>& s, const point<T, D>& p) { return objects_intersect(p, s); }
template <class T, std::size_t D>
bool objects_intersect(const objects::box<T, D>& b, const objects::sphere<T, D>& s) { return objects_intersect(s, b); }
template <class T, std::size_t D>
bool objects_intersect(const objects::triangle<T, D>& t, const objects::sphere<T, D>& s) { return objects_intersect(s, t); }
template <class T, std::size_t D>
bool objects_intersect(const objects::box<T, D>& b, const objects::triangle<T, D>& t) { return objects_intersect(t, b); }

// Anything else: the bounding boxes overlap (conservative).
template <stored_object A, stored_object B>
bool objects_intersect(const A& a, const B& b) {
    return object_boxes_overlap(a, b);
}

// The call every structure makes: finds user overloads by argument-dependent lookup, the
// overloads above otherwise.
template <class A, class B>
bool narrow_phase(const A& a, const B& b) {
    using spatial::collide::objects_intersect;
    return objects_intersect(a, b);
}

}  // namespace spatial::collide
