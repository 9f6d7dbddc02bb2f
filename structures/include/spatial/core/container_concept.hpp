#pragma once
// spatial::spatial_container — the ONE interface every structure implements (the course's
// Project 2/3 contract). Each container's header static_asserts it for a sample point type;
// the typed contract suite in
// tests/ exercises it. Semantics, complexity and iterator rules are in docs/contract.md.

#include <concepts>
#include <cstddef>
#include <iterator>
#include <vector>

#include "spatial/core/intersect_info.hpp"

namespace spatial {

template <class C>
concept spatial_container =
    requires {
        typename C::value_type;
        typename C::point_type;
        typename C::scalar_type;
        typename C::size_type;
        typename C::iterator;
        typename C::const_iterator;
    } && std::forward_iterator<typename C::iterator> &&
    requires(C c, const C cc, const typename C::value_type& v, typename C::const_iterator pos,
             const typename C::point_type& p, typename C::scalar_type s, typename C::size_type n,
             intersect_info<typename C::point_type>& info,
             std::vector<typename C::value_type>& batch) {
        // insertion
        { c.insert(v) } -> std::same_as<typename C::iterator>;
        { c.insert(pos, v) } -> std::same_as<typename C::iterator>;  // hinted
        c.insert(batch.begin(), batch.end());                        // bulk
        // erasure
        { c.erase(pos) } -> std::same_as<typename C::iterator>;
        { c.erase(v) } -> std::same_as<typename C::size_type>;  // erases ALL equal, returns count
        c.erase(pos, pos);                                       // bulk range
        // lookup
        { c.find(v) } -> std::same_as<typename C::iterator>;
        { cc.count(v) } -> std::same_as<typename C::size_type>;
        // ray cast (true iff a hit before info.hit_time), also telling which object
        { cc.intersect(p, p, info) } -> std::same_as<bool>;
        { cc.intersect(p, p, s, info) } -> std::same_as<bool>;
        { cc.intersect_object(p, p, s, info) } -> std::same_as<typename C::iterator>;
        // nearest neighbours, sorted by distance; eps-approximate; ranges
        { cc.find_nearest(p, n) } -> std::same_as<std::vector<typename C::iterator>>;
        { cc.find_nearest(p, n, s) } -> std::same_as<std::vector<typename C::iterator>>;
        { cc.find_in_ball(p, s) } -> std::same_as<std::vector<typename C::iterator>>;
        { cc.find_in_box(p, p) } -> std::same_as<std::vector<typename C::iterator>>;
        // STL basics
        { cc.size() } -> std::same_as<typename C::size_type>;
        { cc.empty() } -> std::same_as<bool>;
        c.clear();
        { cc.begin() } -> std::same_as<typename C::iterator>;
        { cc.end() } -> std::same_as<typename C::iterator>;
        { cc.memory_bytes() } -> std::convertible_to<std::size_t>;
    };

}  // namespace spatial
