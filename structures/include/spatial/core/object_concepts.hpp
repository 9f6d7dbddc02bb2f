#pragma once
// Concepts for the objects a container stores (the course's "black box" interface).
//
// point_object<P>: a stored point:
//   * std::regular-like: copyable and equality comparable (find/count/erase-by-value use ==);
//   * P::scalar_type (float or double) and P::dimension;
//   * p[i] returning the i-th coordinate;
//   * p.intersect(origin, direction, thickness, info) -> bool, the thick-ray test, where
//     origin and direction are themselves P and info is an intersect_info<P>.
//
// bounded_object<O>: a stored object with extent (box, triangle, sphere, or a user type):
//   * copyable, equality comparable, O::scalar_type, O::dimension;
//   * O::point_type, a point_object of the same scalar and dimension (query points, ray
//     origins and directions are point_type);
//   * const T* get_min_bound() const, const T* get_max_bound() const: its axis-aligned
//     bounding box, D values each;
//   * o.intersect(origin, direction, thickness, info) -> bool with origin and direction of
//     point_type and info an intersect_info<point_type>: true iff the ray, thickened into a
//     capsule of radius `thickness`, first touches the object at some t < info.hit_time;
//     then it writes hit_time and hit_location.
// Optional members a container uses when present (object_geometry.hpp falls back otherwise):
//   * squared_distance(const point_type&) -> T: exact squared distance from a point to the
//     object (0 inside). Without it, kNN and ball queries use the bounding box's distance,
//     i.e. they treat the object as its box (documented in docs/contract.md).
//   * overlaps_box(const point_type& lo, const point_type& hi) -> bool: exact object/box test.
//     Without it, the bounding boxes are compared.
//   * split(normal, offset, box& left, box& right): the course's interface — the bounding
//     boxes of the object's parts on either side of the plane {x : normal . x = offset}.
//
// A container stores either kind: `stored_object<O>`.

#include <concepts>
#include <cstddef>
#include <type_traits>

#include "spatial/core/intersect_info.hpp"

namespace spatial {

template <class P>
concept point_object =
    std::copyable<P> && std::equality_comparable<P> &&
    std::is_floating_point_v<typename P::scalar_type> &&
    requires(const P& p, std::size_t i, typename P::scalar_type thickness,
             intersect_info<P>& info) {
        { P::dimension } -> std::convertible_to<std::size_t>;
        { p[i] } -> std::convertible_to<typename P::scalar_type>;
        { p.intersect(p, p, thickness, info) } -> std::same_as<bool>;
    };

template <class O>
concept bounded_object =
    std::copyable<O> && std::equality_comparable<O> &&
    std::is_floating_point_v<typename O::scalar_type> && point_object<typename O::point_type> &&
    std::same_as<typename O::scalar_type, typename O::point_type::scalar_type> &&
    (O::dimension == O::point_type::dimension) &&
    requires(const O& o, const typename O::point_type& p, typename O::scalar_type thickness,
             intersect_info<typename O::point_type>& info) {
        { o.get_min_bound() } -> std::convertible_to<const typename O::scalar_type*>;
        { o.get_max_bound() } -> std::convertible_to<const typename O::scalar_type*>;
        { o.intersect(p, p, thickness, info) } -> std::same_as<bool>;
    };

// What every container accepts as value_type.
template <class O>
concept stored_object = point_object<O> || bounded_object<O>;

namespace detail {
template <class O>
struct point_type_of_impl {
    using type = O;
};
template <bounded_object O>
struct point_type_of_impl<O> {
    using type = typename O::point_type;
};
}  // namespace detail

// The point type of queries on a container of O: O itself for points, O::point_type else.
template <stored_object O>
using point_type_of = typename detail::point_type_of_impl<O>::type;

}  // namespace spatial
