#pragma once
// Answers of two containers compared without caring which of several equal objects each one
// returned: by distance (kNN, where ties make identity ambiguous), by object signature (the
// bounds per axis: contents, ranges, pairs). Shared by the tests (through test_support.hpp)
// and the operations fuzzer (fuzz/operations), hence free of GoogleTest.

#include <algorithm>
#include <cstddef>
#include <type_traits>
#include <utility>
#include <vector>

#include "spatial/core/knn_result_set.hpp"
#include "spatial/core/object_geometry.hpp"
#include "spatial/core/slot_storage.hpp"

namespace spatial_test {

// Sorted squared distances from q of a list of iterators.
template <class P, class Its>
std::vector<double> distances_from(const P& q, const Its& its) {
    std::vector<double> d;
    for (const auto& it : its) d.push_back(static_cast<double>(spatial::object_squared_distance(*it, q)));
    std::sort(d.begin(), d.end());
    return d;
}

// A ball answered both ways by a container with find_in_ball_candidates (spatial::candidate_ball):
// {the candidates, find_in_ball's iterators}, each as sorted (slot, squared distance) pairs, the
// iterators' distances recomputed from their objects. Equal when the visitor form reports the
// same elements with the distances their objects have.
using slot_distances = std::vector<std::pair<std::size_t, double>>;
template <class C>
std::pair<slot_distances, slot_distances> ball_both_ways(const C& c, const typename C::point_type& center,
                                                         typename C::scalar_type r) {
    std::vector<spatial::neighbor_candidate<typename C::scalar_type>> found;
    c.find_in_ball_candidates(center, r, found);
    slot_distances as_candidates, as_iterators;
    for (const auto& x : found) as_candidates.push_back({x.slot, static_cast<double>(x.distance_squared)});
    for (const auto& it : c.find_in_ball(center, r))
        as_iterators.push_back({it.slot(), static_cast<double>(spatial::object_squared_distance(*it, center))});
    std::sort(as_candidates.begin(), as_candidates.end());
    std::sort(as_iterators.begin(), as_iterators.end());
    return {as_candidates, as_iterators};
}

// An object's signature: its lower bounds, then its upper bounds (a point's coordinates twice).
// Equal objects have equal signatures.
template <class O>
std::vector<double> signature(const O& x) {
    std::vector<double> v;
    for (std::size_t i = 0; i < O::dimension; ++i) v.push_back(static_cast<double>(spatial::object_lower(x, i)));
    for (std::size_t i = 0; i < O::dimension; ++i) v.push_back(static_cast<double>(spatial::object_upper(x, i)));
    return v;
}

// The sorted signatures of the objects a list of iterators refers to (a multiset).
template <class Its>
std::vector<std::vector<double>> signatures_of(const Its& its) {
    std::vector<std::vector<double>> v;
    for (const auto& it : its) v.push_back(signature(*it));
    std::sort(v.begin(), v.end());
    return v;
}

// Contents of a container as a sorted list of signatures (a multiset).
template <class C>
std::vector<std::vector<double>> contents(const C& c) {
    std::vector<std::vector<double>> v;
    for (const auto& p : c) v.push_back(signature(p));
    std::sort(v.begin(), v.end());
    return v;
}

// A list of pairs of container iterators as their (slot, slot) pairs, in the list's order.
using slot_pair = std::pair<spatial::slot_index, spatial::slot_index>;
template <class Pairs>
std::vector<slot_pair> slots_of(const Pairs& pairs) {
    std::vector<slot_pair> out;
    for (const auto& [a, b] : pairs) out.emplace_back(a.slot(), b.slot());
    return out;
}

// A list of object pairs as a sorted multiset of pairs of object signatures (the lower
// signature first). Containers allocate slots in their own order (kd_tree's bulk build stores
// objects in leaf order), so pair sets are compared across containers this way; identical
// objects are interchangeable.
template <class Pairs>
std::vector<std::pair<std::vector<double>, std::vector<double>>> signature_pairs(const Pairs& pairs) {
    std::vector<std::pair<std::vector<double>, std::vector<double>>> out;
    for (const auto& [a, b] : pairs) {
        auto x = signature(*a), y = signature(*b);
        if (y < x) std::swap(x, y);
        out.emplace_back(std::move(x), std::move(y));
    }
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace spatial_test
