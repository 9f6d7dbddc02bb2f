#pragma once
// spatial::point<T, D> — the ready-made point object of the course's black-box interface.
//
// A point is a D-dimensional coordinate tuple that models `spatial::point_object`
// (see object_concepts.hpp): it is regular (copyable, equality comparable), exposes
// `scalar_type`, `dimension` and `operator[]`, and can be hit by a "thick" ray through
// `intersect(origin, direction, thickness, info)`.

#include <array>
#include <cmath>
#include <cstddef>
#include <ostream>
#include <type_traits>

#include "spatial/core/intersect_info.hpp"

// The member types of every geometric type over point<T, D> (bounding volumes, ready-made
// objects, rigid transforms), written once: scalar_type, point_type and dimension, as the
// concepts (object_concepts.hpp, bv/bounding_volume.hpp) read them.
#define SPATIAL_POINT_MEMBER_TYPES(T, D)           \
    using scalar_type = T;                         \
    using point_type = ::spatial::point<T, D>;     \
    static constexpr std::size_t dimension = D

namespace spatial {

template <class T, std::size_t D>
struct point {
    static_assert(std::is_floating_point_v<T>, "point<T, D>: T must be float or double");
    static_assert(D >= 1, "point<T, D>: D must be at least 1");

    using scalar_type = T;
    static constexpr std::size_t dimension = D;

    std::array<T, D> coords{};

    constexpr T& operator[](std::size_t i) noexcept { return coords[i]; }
    constexpr const T& operator[](std::size_t i) const noexcept { return coords[i]; }

    friend constexpr bool operator==(const point&, const point&) = default;

    // Ray/point test of the course's interface. The ray is the half-line
    // origin + t * direction, t >= 0, thickened into a capsule of radius `thickness`.
    // The point is hit at the ray parameter of closest approach t* (clamped to 0) when its
    // distance to the ray is <= thickness and t* < info.hit_time; then info receives
    // hit_time = t* and hit_location = origin + t* * direction (the point on the ray).
    // `direction` need not be normalised; t is measured in multiples of it.
    template <class Info>
    bool intersect(const point& origin, const point& direction, T thickness, Info& info) const {
        T dd = 0, pd = 0;
        for (std::size_t i = 0; i < D; ++i) {
            dd += direction[i] * direction[i];
            pd += (coords[i] - origin[i]) * direction[i];
        }
        if (!(dd > T(0))) return false;  // degenerate ray: containers reject it before calling
        T t = pd > T(0) ? pd / dd : T(0);
        if (!(t < info.hit_time)) return false;
        T dist2 = 0;
        for (std::size_t i = 0; i < D; ++i) {
            const T c = origin[i] + t * direction[i] - coords[i];
            dist2 += c * c;
        }
        if (!(dist2 <= thickness * thickness)) return false;
        info.hit_time = t;
        for (std::size_t i = 0; i < D; ++i) info.hit_location[i] = origin[i] + t * direction[i];
        return true;
    }

    friend std::ostream& operator<<(std::ostream& os, const point& p) {
        os << '(';
        for (std::size_t i = 0; i < D; ++i) os << (i ? ", " : "") << p[i];
        return os << ')';
    }
};

template <class T> using point2 = point<T, 2>;
template <class T> using point3 = point<T, 3>;

}  // namespace spatial
