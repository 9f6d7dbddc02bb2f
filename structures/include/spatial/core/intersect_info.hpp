#pragma once
// spatial::intersect_info — the result record of a ray cast, as the course defines it.
//
// Before a cast set hit_time to the largest parameter of interest (default: +infinity).
// A cast returns true iff an object is hit at t < hit_time; then hit_time and
// hit_location describe the nearest such hit. Containers additionally report which
// object was hit through their `intersect_object` member.

#include <limits>

namespace spatial {

template <class Point>
struct intersect_info {
    using scalar_type = typename Point::scalar_type;
    scalar_type hit_time = std::numeric_limits<scalar_type>::infinity();
    Point hit_location{};
};

}  // namespace spatial
