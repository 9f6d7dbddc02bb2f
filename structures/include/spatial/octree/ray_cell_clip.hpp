#pragma once
// Conservative clipping of a (thick) ray's parameter interval to an axis-aligned cell, shared
// by the octree and the grids (and its pad by the kd-tree's split planes). "Conservative" means: every parameter t at which the exact
// object tests (O::intersect) could report a hit for an object inside the cell survives the
// clip, despite rounding. The cell is grown by the ray thickness r plus a few ulps of the
// magnitudes involved, and the resulting parameters are widened by a relative gamma (the
// error-bound style of Pharr, Jakob & Humphreys, PBRT 3e, sec. 3.9). Zero direction components
// of either sign are handled without dividing (no 0 * inf).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "spatial/core/distance.hpp"

namespace spatial::detail {

template <class T>
struct ray_clip_params {
    static constexpr T gamma = 16 * std::numeric_limits<T>::epsilon();
    // Absolute padding for a slab bound `bound` on an axis where the origin is `origin`; the
    // underflow slack keeps it positive at 0 (core/distance.hpp).
    static T pad(T r, T bound, T origin) {
        return r + gamma * (std::abs(bound) + std::abs(origin) + r) + underflow_slack<T>;
    }
};

// Restricts [t0, t1] to the parameters where lo <= o + t v <= hi on one axis, with the slab
// grown by r (+ rounding slack). Returns false if the interval became empty.
template <class T>
bool clip_slab(T o, T v, T lo, T hi, T r, T& t0, T& t1) {
    using cp = ray_clip_params<T>;
    const T a = lo - cp::pad(r, lo, o), b = hi + cp::pad(r, hi, o);
    if (v == 0) {  // +0 and -0 alike: parallel to the slab
        if (o < a || o > b) return false;
        return t0 <= t1;
    }
    T ta = (a - o) / v, tb = (b - o) / v;
    if (ta > tb) std::swap(ta, tb);
    ta -= cp::gamma * std::abs(ta);
    tb += cp::gamma * std::abs(tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    return t0 <= t1;
}

// Clips [t0, t1] to the box [lo, hi] (D axes) grown by r. Returns false when empty.
template <class T, std::size_t D, class Coords>
bool clip_box(const Coords& o, const Coords& v, const Coords& lo, const Coords& hi, T r, T& t0, T& t1) {
    for (std::size_t i = 0; i < D; ++i)
        if (!clip_slab<T>(o[i], v[i], lo[i], hi[i], r, t0, t1)) return false;
    return true;
}

}  // namespace spatial::detail
