#pragma once
// spatial::collide::box_bounds<T, D> — a closed axis-aligned box as plain arrays, the unit of
// work of the broad phases (cell_sort_grid, collision_grid, the trees' pair descents; also
// the kd-tree's node extents), and the one closed-overlap test they all use. Exact:
// comparisons only, nothing rounded, so two objects inside two boxes can overlap only if the
// boxes do.

#include <array>
#include <cstddef>
#include <limits>

namespace spatial::collide {

template <class T, std::size_t D>
struct box_bounds {
    std::array<T, D> lo{}, hi{};

    // Inverted (lo = +inf, hi = -inf): contains nothing, overlaps nothing, and grow()
    // starts from it.
    static box_bounds empty() {
        box_bounds b;
        b.lo.fill(std::numeric_limits<T>::infinity());
        b.hi.fill(-std::numeric_limits<T>::infinity());
        return b;
    }
    bool is_empty() const { return !(lo[0] <= hi[0]); }
    void grow(const box_bounds& o) {
        for (std::size_t i = 0; i < D; ++i) {
            lo[i] = o.lo[i] < lo[i] ? o.lo[i] : lo[i];
            hi[i] = o.hi[i] > hi[i] ? o.hi[i] : hi[i];
        }
    }
    void grow(const std::array<T, D>& p) {
        for (std::size_t i = 0; i < D; ++i) {
            lo[i] = p[i] < lo[i] ? p[i] : lo[i];
            hi[i] = p[i] > hi[i] ? p[i] : hi[i];
        }
    }
    bool contains(const box_bounds& o) const {
        for (std::size_t i = 0; i < D; ++i)
            if (o.lo[i] < lo[i] || o.hi[i] > hi[i]) return false;
        return true;
    }
};

// Closed overlap (touching counts); false when either box is empty.
template <class T, std::size_t D>
bool closed_boxes_overlap(const box_bounds<T, D>& a, const box_bounds<T, D>& b) {
    for (std::size_t i = 0; i < D; ++i)
        if (a.hi[i] < b.lo[i] || b.hi[i] < a.lo[i]) return false;
    return true;
}

}  // namespace spatial::collide
