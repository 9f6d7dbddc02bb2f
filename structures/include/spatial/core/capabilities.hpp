#pragma once
// Optional capabilities of a spatial container, each a named concept (the model: CGAL's
// concept pages, one concept each with the classes that model it). `spatial_container`
// (container_concept.hpp) is what EVERY structure offers; these are what some offer beyond
// it. Generic code — the harness, the scene runner, your own — asks for a concept by name
// instead of probing members, so what a structure can do is written down in one place.
// docs/contract.md lists the models of each concept.

#include <concepts>
#include <cstddef>
#include <span>
#include <utility>
#include <vector>

#include "spatial/collide/pairs.hpp"
#include "spatial/core/container_concept.hpp"
#include "spatial/core/knn_batch.hpp"
#include "spatial/core/knn_result_set.hpp"
#include "spatial/core/motion.hpp"
#include "spatial/core/query_stats.hpp"

namespace spatial {

// The (handle, new value) pairs a batched motion takes.
template <class C>
using motion_batch = std::vector<std::pair<typename C::iterator, typename C::value_type>>;

// Moves ONE stored object in place: `c.update(it, v)` replaces *it by v and returns the same
// handle. Models: bvh (refits the path), collision_grid and sweep_and_prune (O(1)).
// Structures without it move an object by erase + insert.
template <class C>
concept single_motion = requires(C c, typename C::iterator it, const typename C::value_type& v) {
    { c.update(it, v) } -> std::same_as<typename C::iterator>;
};

// Moves MANY stored objects at once, cheaper than one by one: `c.update(first, last)` over
// (handle, new value) pairs; handles stay valid. Models: bvh, collision_grid.
template <class C>
concept batched_motion = requires(C c, motion_batch<C>& moves) { c.update(moves.begin(), moves.end()); };

// Batched motion with a chosen strategy (refit, rebuild, reinsert, automatic) that reports
// the strategy it applied. Models: bvh.
template <class C>
concept motion_with_strategy =
    batched_motion<C> && requires(C c, motion_batch<C>& moves, motion_strategy s) {
        { c.update(moves.begin(), moves.end(), s) } -> std::same_as<motion_strategy>;
    };

// Collision pairs within the container and with another one (collide/pairs.hpp: each pair
// once, sorted; exact or candidates). Models: every structure of the library (brute_force,
// kd_tree, octree, uniform_grid, hashed_grid, bvh<BV>) and collision_grid, sweep_and_prune.
template <class C>
concept pair_search = requires(const C c, pair_filter f) {
    { c.self_pairs(f) } -> std::same_as<std::vector<std::pair<typename C::iterator, typename C::iterator>>>;
    { c.pairs_with(c, f) } -> std::same_as<std::vector<std::pair<typename C::iterator, typename C::iterator>>>;
};

// Self pairs streamed to a callback without materialising the list (a simulation loop's
// form). Models: collision_grid.
template <class C>
concept streamed_self_pairs = requires(const C c, pair_filter f, void (*emit)(typename C::iterator, typename C::iterator)) {
    c.for_each_self_pair(f, emit);
};

// Ray preparation: `c.prepare_rays()` builds now what the first ray cast after a change
// would build (bvh<aabb>: the wide ray layout), so that cost is counted as build time.
// Models: bvh.
template <class C>
concept ray_preparation = requires(const C c) { c.prepare_rays(); };

// kNN answers as (squared distance, slot) candidates written into a caller's buffer, without
// the iterator vector: the benchmark's allocation-free form. Models: kd_tree.
template <class C>
concept candidate_knn = requires(const C c, const typename C::point_type& q, typename C::size_type k,
                                 typename C::scalar_type eps, std::vector<neighbor_candidate<typename C::scalar_type>>& out) {
    c.find_nearest_candidates(q, k, eps, out);
};

// Ball answers as (squared distance, slot) candidates written into a caller's buffer, in no
// particular order: the distances the search computed, without the iterator vector (the
// benchmark's radius queries, as candidate_knn is for its kNN). Models: kd_tree.
template <class C>
concept candidate_ball = requires(const C c, const typename C::point_type& q, typename C::scalar_type r,
                                  std::vector<neighbor_candidate<typename C::scalar_type>>& out) {
    c.find_in_ball_candidates(q, r, out);
};

// Batched kNN (core/knn_batch.hpp): c.find_nearest_batch(queries, k, eps, order, policy)
// answers every query, optionally in Morton order and on several threads. Models: kd_tree.
template <class C>
concept batched_knn = requires(const C c, std::span<const typename C::point_type> qs, typename C::size_type k,
                               typename C::scalar_type eps) {
    { c.find_nearest_batch(qs, k, eps, query_order::morton, par).per_query() } -> std::convertible_to<std::size_t>;
};

// Query statistics in the one shared form (core/query_stats.hpp): the last query's nodes
// visited and objects tested. Models: bvh<BV>, kd_tree with kd_tree_config<..., true>.
template <class C>
concept reports_query_stats = requires(const C c) {
    { c.last_query_stats() } -> std::convertible_to<const query_stats&>;
};

// Node tightness of a hierarchy: (sum of inner node areas, sum of leaf areas) relative to the
// root, the SAH's cost terms. Models: bvh<BV>.
template <class C>
concept reports_node_areas = requires(const C c) {
    { c.node_surface_areas() } -> std::convertible_to<std::pair<double, double>>;
};

}  // namespace spatial
