#pragma once
// spatial::detail::cell_key / cell_box — integer cell coordinates of a grid and inclusive
// boxes of them, with the few operations the grids' storage and queries share (count,
// clipping, iteration over a box's cells).

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>

namespace spatial::detail {

template <std::size_t D>
using cell_key = std::array<std::int64_t, D>;

// The cells of a cube of `edge` cells a side: edge^D.
template <std::size_t D>
constexpr double cells_in_cube(double edge) {
    double c = 1;
    for (std::size_t i = 0; i < D; ++i) c *= edge;
    return c;
}

// A box of cells [lo, hi] (inclusive); empty when lo > hi on some axis.
template <std::size_t D>
struct cell_box {
    cell_key<D> lo{}, hi{};
    bool empty() const {
        for (std::size_t i = 0; i < D; ++i)
            if (lo[i] > hi[i]) return true;
        return false;
    }
    bool contains(const cell_key<D>& c) const {
        for (std::size_t i = 0; i < D; ++i)
            if (c[i] < lo[i] || c[i] > hi[i]) return false;
        return true;
    }
    bool overlaps(const cell_box& o) const {
        for (std::size_t i = 0; i < D; ++i)
            if (o.hi[i] < lo[i] || o.lo[i] > hi[i]) return false;
        return true;
    }
    // Number of cells, as a double (cell boxes of a hashed grid can be astronomically large).
    double count() const {
        if (empty()) return 0;
        double n = 1;
        for (std::size_t i = 0; i < D; ++i) n *= static_cast<double>(hi[i] - lo[i]) + 1;
        return n;
    }
    cell_box clipped(const cell_box& o) const {
        cell_box r;
        for (std::size_t i = 0; i < D; ++i) {
            r.lo[i] = std::max(lo[i], o.lo[i]);
            r.hi[i] = std::min(hi[i], o.hi[i]);
        }
        return r;
    }
};

// Calls f(cell) for every cell of a non-empty box, last axis slowest.
template <std::size_t D, class F>
void for_each_cell(const cell_box<D>& b, F&& f) {
    if (b.empty()) return;
    cell_key<D> c = b.lo;
    while (true) {
        f(c);
        std::size_t i = 0;
        while (i < D) {
            if (c[i] < b.hi[i]) {
                ++c[i];
                break;
            }
            c[i] = b.lo[i];
            ++i;
        }
        if (i == D) return;
    }
}

}  // namespace spatial::detail
