#pragma once
// Factories for the peer libraries put behind harness::point_index<T, D>.
//
// Only declarations live here: each factory is defined and explicitly instantiated for
// T in {float, double} x D in {2, 3} inside its adapter's .cpp (harness/adapters/<peer>/),
// so nanoflann's and CGAL's headers never enter another translation unit (CGAL's take
// ~10 s to compile and CGAL::CGAL adds -frounding-math to whatever includes them).
//
// A factory exists only when its adapter library was built; the libraries define
// SPATIAL_HAVE_NANOFLANN / SPATIAL_HAVE_CGAL (PUBLIC compile definitions), so callers link
// `spatial_adapters` and test the macros, or call make_peer_indices() below. Unused peers
// cost nothing: nothing of them is compiled or linked unless a factory is called.
//
// Semantics every adapter keeps (see point_index.hpp): ids are positions in the build array
// or the ids passed to insert(); knn output is sorted by increasing distance and holds
// SQUARED distances; eps multiplies DISTANCE; radius balls are closed (|p - q| <= r).
// Each adapter converts its peer's conventions; the notes are next to each factory.

#include <cstddef>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "harness/peer_registry.hpp"
#include "harness/configured.hpp"
#include "harness/point_index.hpp"
#include "harness/tuning_sweep.hpp"

namespace harness {

// nanoflann 1.4 KDTreeSingleIndexAdaptor (static index, L2_Simple_Adaptor; settings:
// leaf_max_size). name() "nanoflann"; capabilities knn | approximate_knn | radius.
// build() copies the points into the adapter (the dataset adaptor references the copy) and
// builds the tree. Conversions: nanoflann's eps multiplies SQUARED distance, so it is given
// (1 + eps)^2 - 1; radiusSearch keeps d^2 < radius, so it is given nextafter(r^2, +inf) to
// make the ball closed; k = 0 returns nothing (nanoflann's result set needs capacity >= 1).
template <class T, std::size_t D>
std::unique_ptr<point_index<T, D>> make_nanoflann_index(const key_values& settings);

// nanoflann 1.4 KDTreeSingleIndexDynamicAdaptor (logarithmic method: a forest of static
// trees of sizes 2^i, lazy deletion; settings: leaf_max_size). name() "nanoflann_dynamic"; capabilities knn |
// approximate_knn | radius | dynamic | bulk_insert.
// nanoflann 1.4.3 identifies points by a dataset index that it assumes is DENSE and
// NEVER REUSED (addPoints writes its bookkeeping at position `number of points added so
// far`, reinserting a removed index resurrects its stale copy, removePoint ignores indices
// beyond that count). Caller ids may be sparse and reused, so the adapter gives every
// insertion a fresh slot (0, 1, 2, ... never reused), stores the point at that slot, and
// maps id <-> slot. Erased slots stay in nanoflann's trees (its deletion is lazy), so
// memory grows with the number of insertions, not of live points; memory_bytes shows it.
template <class T, std::size_t D>
std::unique_ptr<point_index<T, D>> make_nanoflann_dynamic_index(const key_values& settings);

// CGAL 5.5 Kd_tree (Sliding_midpoint splitter, extended nodes; settings: bucket_size,
// points_cache on|off) over a point type that carries its id. name() "cgal_kd_tree"; capabilities knn |
// approximate_knn | radius | dynamic | bulk_insert.
// build() inserts all points and calls tree.build() so the build is timed (CGAL would
// otherwise build lazily inside the first query). knn: Orthogonal_k_neighbor_search, whose
// eps already multiplies distance. radius: Fuzzy_sphere with epsilon 0, which is closed
// without the points cache; with it, CGAL 5.5 keeps d^2 < r^2 (an open ball), so the ball gets
// the smallest radius whose square exceeds r^2 and the answer is cut back to d^2 <= r^2.
// insert(): tree.insert() — CGAL drops the tree and rebuilds it lazily at the next query.
// erase(): tree.remove() with an equality on the id, so the right one of several
// coincident points is removed (with the points cache, which CGAL 5.5 cannot keep right
// through remove() or a rebuild in place, insert() and erase() only update the adapter's
// table and the next query builds a new tree of the live points); it needs the point's coordinates, kept in an id -> point
// table that prepare_dynamic() builds (untimed; else the first dynamic operation does), so
// static workloads do not pay for it. last_nodes_visited() is reported for knn.
template <class T, std::size_t D>
std::unique_ptr<point_index<T, D>> make_cgal_kd_tree_index(const key_values& settings);

// Boost.Geometry 1.74 rtree over (point, id) values, node capacity 16: "boost_rtree" is an
// R*-tree bulk-loaded by the packing constructor (knn | radius; the static workloads),
// "boost_rtree_quadratic" a quadratic-split tree built by insertion (knn | radius | dynamic |
// dynamic_variant: the dynamic workloads). kNN answers are sorted by the adapter (Boost's
// come unordered); radius is a closed box query filtered by distance. No approximate kNN.
// memory_bytes() counts the tree's allocations through its allocator.
template <class T, std::size_t D>
std::unique_ptr<point_index<T, D>> make_boost_rtree_index();
template <class T, std::size_t D>
std::unique_ptr<point_index<T, D>> make_boost_rtree_quadratic_index();

// The explicit instantiations of a point-peer factory for T in {float, double} x D in {2, 3},
// written once in the adapter's .cpp (inside namespace harness).
#define SPATIAL_INSTANTIATE_POINT_PEER_FACTORY(factory)                        \
    template std::unique_ptr<point_index<float, 2>> factory<float, 2>();      \
    template std::unique_ptr<point_index<float, 3>> factory<float, 3>();      \
    template std::unique_ptr<point_index<double, 2>> factory<double, 2>();    \
    template std::unique_ptr<point_index<double, 3>> factory<double, 3>()
// The same for a factory that takes its settings (registry line, or a tuning sweep's).
#define SPATIAL_INSTANTIATE_CONFIGURABLE_POINT_PEER_FACTORY(factory)                                  \
    template std::unique_ptr<point_index<float, 2>> factory<float, 2>(const key_values&);          \
    template std::unique_ptr<point_index<float, 3>> factory<float, 3>(const key_values&);          \
    template std::unique_ptr<point_index<double, 2>> factory<double, 2>(const key_values&);        \
    template std::unique_ptr<point_index<double, 3>> factory<double, 3>(const key_values&)

// Every peer index compiled into this build, in a fixed order (static before dynamic): each
// in its registry configuration and, when `sweep`, in every configuration of its tuning sweep.
template <class T, std::size_t D>
std::vector<std::unique_ptr<point_index<T, D>>> make_peer_indices(bool sweep = false) {
    std::vector<std::unique_ptr<point_index<T, D>>> out;
    (void)sweep;
#if defined(SPATIAL_HAVE_NANOFLANN) && SPATIAL_HAVE_NANOFLANN
    add_peer_configurations(out, "nanoflann", make_nanoflann_index<T, D>, sweep);
    add_peer_configurations(out, "nanoflann_dynamic", make_nanoflann_dynamic_index<T, D>, sweep);
#endif
#if defined(SPATIAL_HAVE_CGAL) && SPATIAL_HAVE_CGAL
    add_peer_configurations(out, "cgal_kd_tree", make_cgal_kd_tree_index<T, D>, sweep);
#endif
#if defined(SPATIAL_HAVE_BOOST_GEOMETRY) && SPATIAL_HAVE_BOOST_GEOMETRY
    // Node capacity and split are template arguments of Boost's rtree: one configuration each.
    out.push_back(make_boost_rtree_index<T, D>());
    out.push_back(make_boost_rtree_quadratic_index<T, D>());
#endif
    return out;
}

}  // namespace harness
