#pragma once
// spatial::ray<P>: a half-line origin + t * direction (t >= 0) in the coordinates of point
// type P, for callers who prefer one value over the course's (origin, direction) pair.
// `cast(container, ray, info)` forwards to the container's intersect_object; the ray's
// thickness (0 = an exact line) is the capsule radius of point::intersect.

#include <cstddef>

#include "spatial/core/input_checks.hpp"
#include "spatial/core/intersect_info.hpp"

namespace spatial {

template <class P>
struct ray {
    using scalar_type = typename P::scalar_type;
    P origin{};
    P direction{};
    scalar_type thickness = 0;

    // The point at parameter t (requires P to be default-constructible with writable [i]).
    P at(scalar_type t) const {
        P p = origin;
        for (std::size_t i = 0; i < P::dimension; ++i) p[i] = origin[i] + t * direction[i];
        return p;
    }
};

// Nearest object of `c` hit by `r` before info.hit_time, or c.end().
template <class Container, class P>
auto cast(const Container& c, const ray<P>& r, intersect_info<P>& info) {
    return c.intersect_object(r.origin, r.direction, r.thickness, info);
}

}  // namespace spatial
