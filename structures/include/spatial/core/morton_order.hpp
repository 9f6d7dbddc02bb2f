#pragma once
// spatial::morton_encoder / spatial::morton_order — the Morton (Z-order) code of a position
// quantised in a box, and the permutation that visits a set of points in that order
// (G. M. Morton, "A computer oriented geodetic data base and a new technique in file
// sequencing", IBM, 1966). Points close in Z-order are close in space, so work done in that
// order touches the same part of a spatial index again and again while it is still in cache:
// the reason batched queries may reorder (knn_batch.hpp) and the example morton_array sorts
// its objects.
//
// Codes interleave 63 / D bits per axis (D = 3: 21 bits; D = 1: 52). Each coordinate is quantised in the
// box's extent on its axis; a box with zero extent on an axis puts every point in cell 0 there.
// Costs: encoding O(D * bits) per point; morton_order O(n) to encode plus an LSD radix sort of
// the 64-bit codes, O(n) with 6 passes of 11 bits (stable: equal codes keep their input order,
// so the permutation is a function of the input alone).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <utility>
#include <vector>

#include "spatial/core/point.hpp"

namespace spatial {

template <class T, std::size_t D>
class morton_encoder {
public:
    static_assert(D >= 1 && D <= 63, "morton_encoder: 1 to 63 dimensions");
    // 63 / D bits, at most 52 so that the top cell index 2^bits - 1 is exact in a double (D = 1).
    static constexpr unsigned bits_per_axis = 63 / D < 52 ? 63 / D : 52;

    // Quantises in [lo, hi] (inclusive); positions outside are clamped to the box.
    morton_encoder(const std::array<T, D>& lo, const std::array<T, D>& hi) {
        const double cells = std::ldexp(1.0, static_cast<int>(bits_per_axis)) - 1;
        for (std::size_t i = 0; i < D; ++i) {
            lo_[i] = static_cast<double>(lo[i]);
            const double extent = static_cast<double>(hi[i]) - lo_[i];
            // extent may overflow to +inf (lo = -1e308, hi = 1e308): the scale is then 0 and
            // that axis does not order the points, which is still a valid order. An extent of a
            // few denormals makes the scale +inf: the points at lo go to cell 0, the others to
            // the last cell.
            scale_[i] = extent > 0 && std::isfinite(extent) ? cells / extent : 0.0;
        }
    }

    // The box of `coords` of every element of a range of points.
    static morton_encoder bounding(std::span<const point<T, D>> pts) {
        std::array<T, D> lo, hi;
        lo.fill(std::numeric_limits<T>::max());
        hi.fill(std::numeric_limits<T>::lowest());
        for (const auto& p : pts)
            for (std::size_t i = 0; i < D; ++i) {
                lo[i] = std::min(lo[i], p[i]);
                hi[i] = std::max(hi[i], p[i]);
            }
        if (pts.empty()) lo = hi = std::array<T, D>{};
        return morton_encoder(lo, hi);
    }

    std::uint64_t code(const std::array<T, D>& c) const {
        const double cells = std::ldexp(1.0, static_cast<int>(bits_per_axis)) - 1;
        std::uint64_t out = 0;
        for (std::size_t i = 0; i < D; ++i) {
            const double at = (static_cast<double>(c[i]) - lo_[i]) * scale_[i];
            // NaN goes to cell 0: 0 * inf where an extent of a few denormals makes the scale
            // overflow, inf * 0 where the extent overflows (std::clamp would pass NaN through,
            // and its conversion to an integer is undefined).
            const auto q = static_cast<std::uint64_t>(at > 0 ? std::min(at, cells) : 0.0);
            out |= spread(q) << i;
        }
        return out;
    }
    std::uint64_t code(const point<T, D>& p) const { return code(p.coords); }

private:
    // The bits of q (bits_per_axis of them) moved D positions apart: bit b goes to b * D.
    static std::uint64_t spread(std::uint64_t q) {
        if constexpr (D == 1) return q;
        else if constexpr (D == 2) {  // the "part1by1" magic numbers: 5 shift-and-mask steps
            q &= 0x7fffffffull;
            q = (q | (q << 16)) & 0x0000ffff0000ffffull;
            q = (q | (q << 8)) & 0x00ff00ff00ff00ffull;
            q = (q | (q << 4)) & 0x0f0f0f0f0f0f0f0full;
            q = (q | (q << 2)) & 0x3333333333333333ull;
            q = (q | (q << 1)) & 0x5555555555555555ull;
            return q;
        } else if constexpr (D == 3) {  // "part1by2": 21 bits into 63
            q &= 0x1fffffull;
            q = (q | (q << 32)) & 0x001f00000000ffffull;
            q = (q | (q << 16)) & 0x001f0000ff0000ffull;
            q = (q | (q << 8)) & 0x100f00f00f00f00full;
            q = (q | (q << 4)) & 0x10c30c30c30c30c3ull;
            q = (q | (q << 2)) & 0x1249249249249249ull;
            return q;
        } else {
            std::uint64_t out = 0;
            for (unsigned b = 0; b < bits_per_axis; ++b) out |= ((q >> b) & 1u) << (b * D);
            return out;
        }
    }

    std::array<double, D> lo_{}, scale_{};
};

// The indices of `pts` sorted by Morton code in the points' bounding box (ties in input order).
// Throws std::length_error past 2^32 - 1 points (the indices are 32-bit).
template <class T, std::size_t D>
std::vector<std::uint32_t> morton_order(std::span<const point<T, D>> pts) {
    if (pts.size() > std::numeric_limits<std::uint32_t>::max())
        throw std::length_error("spatial::morton_order: more than 2^32-1 points");
    const auto encoder = morton_encoder<T, D>::bounding(pts);
    struct keyed {
        std::uint64_t code;
        std::uint32_t index;
    };
    std::vector<keyed> a(pts.size()), b(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) a[i] = {encoder.code(pts[i]), static_cast<std::uint32_t>(i)};
    // LSD radix sort, 11-bit digits (a 2048-entry count fits L1): each pass is stable.
    constexpr unsigned digit = 11, passes = (63 + digit - 1) / digit;
    std::vector<std::size_t> count(std::size_t{1} << digit);
    for (unsigned p = 0; p < passes; ++p) {
        const unsigned shift = p * digit;
        std::fill(count.begin(), count.end(), 0);
        for (const keyed& k : a) ++count[(k.code >> shift) & ((1u << digit) - 1)];
        if (count[(a.empty() ? 0 : a[0].code >> shift) & ((1u << digit) - 1)] == a.size()) continue;  // one bucket
        std::size_t sum = 0;
        for (auto& c : count) sum += std::exchange(c, sum);
        for (const keyed& k : a) b[count[(k.code >> shift) & ((1u << digit) - 1)]++] = k;
        a.swap(b);
    }
    std::vector<std::uint32_t> order(a.size());
    for (std::size_t i = 0; i < a.size(); ++i) order[i] = a[i].index;
    return order;
}

}  // namespace spatial
