#pragma once
// Morton (Z-order) ordering of a point set, for "spatially coherent insertion stream"
// benchmarks: consecutive points in Z-order are usually close in space, which is what a
// hinted insert (start from the previous point's leaf/cell) is meant to exploit.
//
// Each coordinate is quantised to B = min(32, 64 / D) bits over the set's bounding box and
// the bits are interleaved, most significant level first (Morton 1966). Equal keys keep
// their input order, so the result is fully determined by the input.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "spatial/core/point.hpp"

namespace datasets {

// Bits per axis in a 64-bit Morton key of dimension D.
template <std::size_t D>
inline constexpr unsigned morton_bits_per_axis = D >= 2 ? static_cast<unsigned>(64 / D) : 32u;

// Interleaves q[0..D) into one key; axis 0 takes the least significant bit of each level.
// Only the low morton_bits_per_axis<D> bits of each q[d] are used. O(D * B).
template <std::size_t D>
constexpr std::uint64_t morton_interleave(const std::array<std::uint32_t, D>& q) noexcept {
    constexpr unsigned bits = morton_bits_per_axis<D>;
    std::uint64_t key = 0;
    for (unsigned b = bits; b-- > 0;) {
        for (std::size_t d = D; d-- > 0;) key = (key << 1) | ((q[d] >> b) & 1u);
    }
    return key;
}

// The points reordered along the Z-order curve of their bounding box.
// Throws std::invalid_argument for a NaN or infinite coordinate (naming point and value).
// O(n log n) time, O(n) extra memory.
template <class T, std::size_t D>
std::vector<spatial::point<T, D>> spatially_sorted(std::vector<spatial::point<T, D>> pts) {
    static_assert(D >= 1 && D <= 64, "spatially_sorted: 1 <= D <= 64");
    if (pts.size() < 2) return pts;

    std::array<double, D> lo{}, hi{};
    lo.fill(std::numeric_limits<double>::infinity());
    hi.fill(-std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < pts.size(); ++i) {
        for (std::size_t d = 0; d < D; ++d) {
            const double x = static_cast<double>(pts[i][d]);
            if (!std::isfinite(x)) {
                throw std::invalid_argument("spatially_sorted: point " + std::to_string(i) +
                                            " has non-finite coordinate " + std::to_string(d) +
                                            " = " + std::to_string(x));
            }
            lo[d] = std::min(lo[d], x);
            hi[d] = std::max(hi[d], x);
        }
    }

    constexpr unsigned bits = morton_bits_per_axis<D>;
    const double max_cell = std::ldexp(1.0, static_cast<int>(bits)) - 1.0;
    std::array<double, D> scale{};
    for (std::size_t d = 0; d < D; ++d) {
        // A flat axis (all coordinates equal) contributes nothing to the order.
        scale[d] = hi[d] > lo[d] ? max_cell / (hi[d] - lo[d]) : 0.0;
    }

    std::vector<std::pair<std::uint64_t, std::size_t>> keys(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) {
        std::array<std::uint32_t, D> q{};
        for (std::size_t d = 0; d < D; ++d) {
            const double cell = std::floor((static_cast<double>(pts[i][d]) - lo[d]) * scale[d]);
            q[d] = static_cast<std::uint32_t>(std::clamp(cell, 0.0, max_cell));
        }
        keys[i] = {morton_interleave<D>(q), i};
    }
    // (key, index) pairs are unique, so the order is total and needs no stable sort.
    std::sort(keys.begin(), keys.end());

    std::vector<spatial::point<T, D>> out;
    out.reserve(pts.size());
    for (const auto& [key, index] : keys) out.push_back(pts[index]);
    return out;
}

}  // namespace datasets
