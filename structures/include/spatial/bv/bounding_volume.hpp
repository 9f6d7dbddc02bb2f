#pragma once
// spatial::bounding_volume — what a BVH (issue 4) is templated on. Each volume type is one
// header in this folder; all of them model this concept for their scalar T and dimension D.
//
//   contains(p)                 p inside or on the boundary
//   overlaps(other)             never a false negative (conservative types document their
//                               false-positive behaviour)
//   ray_interval(o, d, t0, t1)  the parameter interval [t0, t1] where o + t d is inside;
//                               false if the line misses it (t may be negative)
//   distance_lower_bound(p)     <= the distance from p to any point inside (0 inside)
//   merged(other)               a volume of the same type containing both
//   volume(), surface_area()    (area and perimeter in 2D)
//   transformed(xf)             a volume of the same type containing the image of this one
//                               under the rigid motion xf (exact for every type except aabb,
//                               which re-boxes the rotated box: Arvo 1990)

#include <concepts>
#include <cstddef>

#include "spatial/core/rigid_transform.hpp"

namespace spatial {

template <class BV>
concept bounding_volume = requires(const BV& bv, const typename BV::point_type& p, typename BV::scalar_type& t) {
    typename BV::scalar_type;
    typename BV::point_type;
    { BV::dimension } -> std::convertible_to<std::size_t>;
    { bv.contains(p) } -> std::same_as<bool>;
    { bv.overlaps(bv) } -> std::same_as<bool>;
    { bv.ray_interval(p, p, t, t) } -> std::same_as<bool>;
    { bv.distance_lower_bound(p) } -> std::convertible_to<typename BV::scalar_type>;
    { bv.merged(bv) } -> std::same_as<BV>;
    { bv.volume() } -> std::convertible_to<typename BV::scalar_type>;
    { bv.surface_area() } -> std::convertible_to<typename BV::scalar_type>;
    { bv.transformed(rigid_transform<typename BV::scalar_type, BV::dimension>{}) } -> std::same_as<BV>;
};

}  // namespace spatial
