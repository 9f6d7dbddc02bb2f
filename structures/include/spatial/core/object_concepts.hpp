#pragma once
// Concepts for the objects a container stores (the course's "black box" interface).
//
// point_object<P>: what kd_tree and brute_force need of a stored point type P:
//   * std::regular-like: copyable and equality comparable (find/count/erase-by-value use ==);
//   * P::scalar_type (float or double) and P::dimension;
//   * p[i] returning the i-th coordinate;
//   * p.intersect(origin, direction, thickness, info) -> bool, the thick-ray test, where
//     origin and direction are themselves P and info is an intersect_info<P>.
// Any user type that provides these works; spatial::point<T, D> is the ready one.

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

}  // namespace spatial
