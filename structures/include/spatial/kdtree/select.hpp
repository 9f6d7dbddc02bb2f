#pragma once
// floyd_rivest_select: place the k-th smallest element (by key) at position k of [first, n),
// with smaller-or-equal keys before it and greater-or-equal after — std::nth_element's
// contract, with fewer comparisons.
//
// Floyd & Rivest, "Algorithm 489: SELECT", CACM 18(3), 1975: recursively select within a
// small random-free sample window around the expected rank to get two pivots that bracket
// the k-th element with high probability, then partition once. Expected comparisons are
// n + min(k, n - k) + o(n) (~1.5 n for the median) against ~3 n for introselect. Like
// quickselect its worst case is quadratic, so after a budget of rounds it hands over to
// std::nth_element, which bounds the worst case by O(n log n).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>

namespace spatial::detail {

template <class E, class Key>
void floyd_rivest_select(E* a, std::ptrdiff_t left, std::ptrdiff_t right, std::ptrdiff_t k, Key key,
                         int budget = 64) {
    using std::swap;
    while (right > left) {
        // Guard against the quadratic worst case: after `budget` rounds, finish with
        // std::nth_element (introselect, O(n log n) worst case).
        if (--budget < 0) {
            std::nth_element(a + left, a + k, a + right + 1,
                             [&key](const E& x, const E& y) { return key(x) < key(y); });
            return;
        }
        if (right - left > 600) {
            // Recurse on a window of about n^(2/3) elements around the expected position of
            // the k-th element, so that a[k] becomes an excellent pivot.
            const double n = static_cast<double>(right - left + 1);
            const double i = static_cast<double>(k - left + 1);
            const double z = std::log(n);
            const double s = 0.5 * std::exp(2 * z / 3);
            const double sd = 0.5 * std::sqrt(z * s * (n - s) / n) * (i - n / 2 < 0 ? -1 : 1);
            const auto lo = static_cast<std::ptrdiff_t>(static_cast<double>(k) - i * s / n + sd);
            const auto hi = static_cast<std::ptrdiff_t>(static_cast<double>(k) + (n - i) * s / n + sd);
            floyd_rivest_select(a, lo > left ? lo : left, hi < right ? hi : right, k, key, budget);
        }
        // Hoare-style partition of [left, right] around t = key(a[k]).
        const auto t = key(a[k]);
        std::ptrdiff_t i = left, j = right;
        swap(a[left], a[k]);
        if (key(a[right]) > t) swap(a[right], a[left]);
        while (i < j) {
            swap(a[i], a[j]);
            ++i;
            --j;
            while (key(a[i]) < t) ++i;
            while (key(a[j]) > t) --j;
        }
        if (key(a[left]) == t) {
            swap(a[left], a[j]);
        } else {
            ++j;
            swap(a[j], a[right]);
        }
        // a[j] == t is in its final place; continue on the side holding k.
        if (j <= k) left = j + 1;
        if (k <= j) right = j - 1;
    }
}

}  // namespace spatial::detail
