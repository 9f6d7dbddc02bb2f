#pragma once
// Squared Euclidean distance and box tests on any point_object. One definition, used by
// every container and by the brute-force oracle, so exact answers compare bit-for-bit.

#include <array>
#include <cstddef>
#include <limits>

namespace spatial {

// The distance below which a squared-distance test in T cannot tell an offset from zero: a
// coordinate difference under sqrt(denorm_min) squares to 0 (underflow), so an object that
// close to a ball of radius 0 or to a thin ray passes the object's own test. Every pad or slack
// that must never prune what that test accepts adds this constant to its terms relative to the
// magnitudes, which are 0 at the origin (found by fuzzing, docs/fuzzing.md). It is
// 2 sqrt(denorm_min) rounded up to a power of two: 2^-536 for double (about 4.4e-162), 2^-73
// for float; a difference d >= r + it has d^2 - r^2 >= 4 denorm_min, more than the rounding
// of both squares.
template <class T>
inline constexpr T underflow_slack = [] {
    T x = 1;
    for (int e = 0; e < (std::numeric_limits<T>::digits - std::numeric_limits<T>::min_exponent) / 2 - 1; ++e) x /= 2;
    return x;
}();

template <class P, class Q>
constexpr typename P::scalar_type squared_distance(const P& a, const Q& b) {
    typename P::scalar_type s = 0;
    for (std::size_t i = 0; i < P::dimension; ++i) {
        const auto d = a[i] - b[i];
        s += d * d;
    }
    return s;
}

template <class P>
constexpr bool in_closed_box(const P& p, const P& lo, const P& hi) {
    for (std::size_t i = 0; i < P::dimension; ++i)
        if (p[i] < lo[i] || p[i] > hi[i]) return false;
    return true;
}

// Squared distance from x to the closed box [lo, hi] (0 inside; +inf for an empty box with
// lo = +inf, hi = -inf). The one arithmetic of every axis-aligned box: the box object, the
// aabb, kd_tree node extents and octree loose cells, so their bounds agree bit for bit.
// x, lo and hi are anything indexable by 0 .. D-1 (points, std::arrays). Not forced inline:
// [[gnu::always_inline]] here changed how GCC 12 compiles kd_tree's object kNN and ray cast
// (measured on the assembly); left to the inliner, they compile exactly as before.
template <class T, std::size_t D, class X, class Lo, class Hi>
constexpr T box_squared_distance(const X& x, const Lo& lo, const Hi& hi) {
    T s = 0;
    for (std::size_t i = 0; i < D; ++i) {
        const T d = x[i] < lo[i] ? lo[i] - x[i] : (x[i] > hi[i] ? x[i] - hi[i] : T(0));
        s += d * d;
    }
    return s;
}

// A point's coordinates as a std::array (the trees keep keys and queries in this form).
template <class P>
constexpr std::array<typename P::scalar_type, P::dimension> point_coords(const P& p) {
    std::array<typename P::scalar_type, P::dimension> c;
    for (std::size_t i = 0; i < P::dimension; ++i) c[i] = p[i];
    return c;
}

}  // namespace spatial
