#pragma once
// What the operations fuzzer stores and asks: coordinates drawn from a table of hard cases
// rather than from raw bytes, so that the interesting inputs are one byte away instead of one
// in 2^64 (libFuzzer docs, "Structure-aware fuzzing": make the fuzzer's mutations land on
// meaningful values). The hard cases: +0 and -0, denormals (the smallest, and one whose square
// underflows), the smallest normal, 1e-30 and 1e30 (and their negatives), numbers one ulp
// either side of 1, thirds; equal points (an existing point again, a small lattice), collinear
// points (on the line through two stored ones), coplanar sets (one coordinate of a stored
// point replaced), boxes of zero width; rays along the axes (with +0 / -0 components), rays
// through a stored point or box corner, diagonals.
// Every value drawn here is finite and at most about 5e30 in magnitude, so squared distances
// stay finite: what the contract says must be rejected is drawn separately (invalid_inputs.hpp).

#include <array>
#include <cstddef>
#include <limits>
#include <span>

#include "fuzz_input.hpp"
#include "spatial/core/object_concepts.hpp"
#include "spatial/core/object_geometry.hpp"

namespace spatial_fuzz {

inline constexpr std::array<double, 24> hard_coordinates{
    0.0,     -0.0,   1.0,    -1.0,   0.5,    -0.5, 0.25, 2.0, 3.0, 1.0 / 3.0, 0.1, 7.0,
    1e-30,   -1e-30, 1e30,   -1e30,
    0x0.0000000000001p-1022,   // the smallest denormal
    -0x0.0000000000001p-1022,
    0x1p-1022,                 // the smallest normal number
    1e-310,                    // a denormal
    0x1.0000000000001p0,       // one ulp above 1
    0x1.fffffffffffffp-1,      // one ulp below 1
    1e15 + 0.5, -123456.789};
// Non-negative sizes: box extents, ball radii, ray thicknesses.
inline constexpr std::array<double, 9> hard_sizes{0.0, 0x0.0000000000001p-1022, 1e-30, 1e-3, 0.25, 0.5, 1.0, 2.0, 1e30};
inline constexpr std::array<double, 5> hard_eps{0.0, 1e-30, 0.5, 1.0, 1e30};
// Where a ray cast starts looking (intersect_info::hit_time on entry): no limit, or a bound.
inline constexpr std::array<double, 6> hard_hit_limits{std::numeric_limits<double>::infinity(), 0.0, 1e-30, 0.5, 1.0, 1e30};

template <class O>
class value_source {
public:
    using Q = spatial::point_type_of<O>;
    using T = typename O::scalar_type;
    static constexpr std::size_t D = O::dimension;

    explicit value_source(fuzz_input& in) : in_(in) {}

    T coordinate() { return static_cast<T>(in_.pick(hard_coordinates)); }
    T size() { return static_cast<T>(in_.pick(hard_sizes)); }
    T eps() { return static_cast<T>(in_.pick(hard_eps)); }
    T hit_limit() { return static_cast<T>(in_.pick(hard_hit_limits)); }

    // A point; `anchors` are points on the stored objects (see mirror::anchors).
    Q point(std::span<const Q> anchors) {
        const std::size_t mode = in_.below(anchors.empty() ? 2 : 5);
        Q p{};
        switch (mode) {
            case 0:
                for (std::size_t i = 0; i < D; ++i) p[i] = coordinate();
                return p;
            case 1:  // a small lattice: equal points, coplanar and collinear sets by themselves
                for (std::size_t i = 0; i < D; ++i) p[i] = static_cast<T>(in_.below(4));
                return p;
            case 2: return anchor(anchors);  // an equal point
            case 3: {  // collinear with two stored points
                static constexpr std::array<double, 5> along{0.5, 2.0, -1.0, 1.0 / 3.0, 1e-30};
                const Q a = anchor(anchors), b = anchor(anchors);
                const double t = in_.pick(along);
                for (std::size_t i = 0; i < D; ++i)
                    p[i] = static_cast<T>(static_cast<double>(a[i]) + t * (static_cast<double>(b[i]) - static_cast<double>(a[i])));
                return p;
            }
            default: {  // coplanar: a stored point with one coordinate replaced
                p = anchor(anchors);
                p[in_.below(D)] = coordinate();
                return p;
            }
        }
    }

    // A stored value: the point itself, or a box spanned by a point and an extent per axis (zero
    // widths included) or by two points.
    O object(std::span<const Q> anchors) {
        const Q a = point(anchors);
        if constexpr (spatial::point_object<O>) {
            return a;
        } else {
            if (in_.flag()) return O(a, point(anchors));
            Q b = a;
            for (std::size_t i = 0; i < D; ++i) b[i] = static_cast<T>(a[i] + size());
            return O(a, b);
        }
    }

    // A ray direction from `origin`: along an axis (the other components +0 or -0), through a
    // stored point or corner, a diagonal, or table coordinates. May be the zero vector (the
    // caller finds out: the oracle rejects it).
    Q direction(const Q& origin, std::span<const Q> anchors) {
        Q d{};
        switch (in_.below(anchors.empty() ? 3 : 4)) {
            case 0:
                for (std::size_t i = 0; i < D; ++i) d[i] = in_.flag() ? T(0) : T(-0.0);
                d[in_.below(D)] = in_.flag() ? T(1) : T(-1);
                return d;
            case 1:
                for (std::size_t i = 0; i < D; ++i) d[i] = in_.flag() ? T(1) : T(-1);
                return d;
            case 2:
                for (std::size_t i = 0; i < D; ++i) d[i] = coordinate();
                return d;
            default: {
                const Q target = anchor(anchors);
                for (std::size_t i = 0; i < D; ++i) d[i] = target[i] - origin[i];
                return d;
            }
        }
    }

private:
    Q anchor(std::span<const Q> anchors) { return anchors[in_.below(anchors.size())]; }

    fuzz_input& in_;
};

}  // namespace spatial_fuzz
