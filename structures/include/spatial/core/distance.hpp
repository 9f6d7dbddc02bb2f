#pragma once
// Squared Euclidean distance and box tests on any point_object. One definition, used by
// every container and by the brute-force oracle, so exact answers compare bit-for-bit.

#include <cstddef>

namespace spatial {

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

}  // namespace spatial
