#pragma once
// harness::peer_registry — the ONE list of the peers (other libraries) the harness measures
// against, with their name, library, suites, configuration and size limit. Their construction
// lives in their adapters (harness/adapters/<peer>/, each behind its own CMake option); the
// suites take the adapters' factories and look each peer's limits and settings up here, so no
// suite names a peer. Adding a peer: its adapter, its CMake block, its factory (adapters.hpp for
// point peers), one line here, docs (docs/adding-a-structure.md, "A peer"); tests/adapters_test
// then runs it against brute force and checks it reports the capabilities its line lists.
//
// The bv suite's two "structures" (our fits and CGAL's) are listed here too, so that every
// value of the CSV `structure` column has one description.

#include <string>
#include <vector>

#include "harness/structure_registry.hpp"

namespace harness {

inline const std::vector<structure_info>& registered_peers() {
    using spatial::motion_strategy;
    const auto any = size_class::any;
    const auto slow = size_class::slow;
    const auto peer_tree = complexity_of::tree();
    static const std::vector<structure_info> peers{
        {"nanoflann", "nanoflann", "", "peer", "nanoflann 1.4.3", "static kd-tree (KDTreeSingleIndexAdaptor)", any, 0, motion_strategy::automatic, {{"leaf_max_size", "10"}}, peer_tree, in::knn | in::structures, {"knn", "approximate_knn", "radius"}},
        {"nanoflann_dynamic", "nanoflann", "", "peer", "nanoflann 1.4.3", "dynamic kd-tree forest (KDTreeSingleIndexDynamicAdaptor), dynamic workloads", any, 0, motion_strategy::automatic, {{"leaf_max_size", "10"}}, peer_tree, in::knn, {"knn", "approximate_knn", "radius", "dynamic", "bulk_insert", "dynamic_variant"}},
        {"cgal_kd_tree", "cgal_kd_tree", "", "peer", "CGAL 5.5", "Kd_tree, sliding midpoint", any, 0, motion_strategy::automatic, {{"bucket_size", "10"}, {"points_cache", "off"}}, peer_tree, in::knn | in::structures, {"knn", "approximate_knn", "radius", "dynamic", "bulk_insert", "rebuilds_on_query"}},
        {"boost_rtree", "boost_rtree", "", "peer", "Boost.Geometry 1.74", "R*-tree, bulk-loaded (packing constructor)", any, 0, motion_strategy::automatic, {{"params", "rstar<16>"}, {"build", "packed"}}, peer_tree, in::knn | in::structures, {"knn", "radius"}},
        {"boost_rtree_quadratic", "boost_rtree", "", "peer", "Boost.Geometry 1.74", "quadratic R-tree built by insertion, dynamic workloads", any, 0, motion_strategy::automatic, {{"params", "quadratic<16>"}, {"build", "insert"}}, peer_tree, in::knn, {"knn", "radius", "dynamic", "dynamic_variant"}},
        {"embree", "embree", "", "peer", "Embree 3.13", "rtcIntersect1 on a triangle mesh", any, 0, motion_strategy::automatic, {{"build_quality", "medium"}}, peer_tree, in::raycast},
        {"embree_robust", "embree", "", "peer", "Embree 3.13", "rtcIntersect1, RTC_SCENE_FLAG_ROBUST", any, 0, motion_strategy::automatic, {{"build_quality", "medium"}, {"flags", "robust"}}, peer_tree, in::raycast},
        {"embree_user", "embree", "", "peer", "Embree 3.13", "user geometry (boxes, thick points)", any, 0, motion_strategy::automatic, {}, peer_tree, in::raycast_objects},
        {"cgal_aabb_tree", "cgal_aabb_tree", "", "peer", "CGAL 5.5", "AABB_tree first_intersection", any, 0, motion_strategy::automatic, {}, peer_tree, in::raycast},
        {"cgal_box_intersection", "cgal_box_intersection", "", "peer", "CGAL 5.5", "box_self_intersection_d, rebuilt each query", any, 0, motion_strategy::rebuild, {{"cutoff", "10"}}, peer_tree, in::collide_static | in::collide_moving},
        // FCL's SaP: building 1e5 boxes takes ~4 s and its incremental update ~0.85 s per step
        // at 1e4 (~21 s at 1e5, superlinear inside FCL): timed as a slow structure.
        {"fcl_dynamic_aabb_tree", "fcl", "", "peer", "FCL 0.7", "DynamicAABBTreeCollisionManager", any, 0, motion_strategy::automatic, {}, peer_tree, in::collide_static | in::collide_moving},
        {"fcl_sap", "fcl", "", "peer", "FCL 0.7", "SaPCollisionManager", slow, 0, motion_strategy::automatic, {}, peer_tree, in::collide_static | in::collide_moving},
        // FCL's spatial hashing: 5.6 s build + 19 s query at 1e6 (hash buckets per cell).
        {"fcl_spatial_hashing", "fcl", "", "peer", "FCL 0.7", "SpatialHashingCollisionManager", any, 100000, motion_strategy::automatic, {}, complexity_of::grid(), in::collide_static | in::collide_moving},
        // Boost's node capacity is a template argument: one configuration, as boost_rtree.
        {"boost_rtree_collide", "boost_rtree", "", "peer", "Boost.Geometry 1.74", "R*-tree, bulk-loaded (packing constructor), one intersects query per box; update: remove + insert", any, 0, motion_strategy::reinsert, {{"params", "rstar<16>"}, {"build", "packed"}}, peer_tree, in::collide_static | in::collide_moving},
        {"embree_collide", "embree", "", "peer", "Embree 3.13", "rtcCollide on user geometry", any, 0, motion_strategy::automatic, {{"build_quality", "medium"}}, peer_tree, in::collide_static | in::collide_moving},
        {"spatialbench", "spatialbench", "", "library", "spatialbench", "our bounding-volume fits (bv suite)", any, 0, motion_strategy::automatic, {}, complexity_of::tree(), in::bv},
        {"cgal", "cgal", "", "peer", "CGAL 5.5", "CGAL's bounding-volume fits (bv suite)", any, 0, motion_strategy::automatic, {}, complexity_of::tree(), in::bv},
    };
    return peers;
}

// The peer called `name`, or nullptr.
inline const structure_info* find_peer(const std::string& name) {
    for (const auto& p : registered_peers())
        if (p.name == name) return &p;
    return nullptr;
}

// A peer's limits in a suite part (true when the registry does not list it: an adapter
// without a registry line is a mistake the registry test reports, not a silent skip here).
inline bool peer_within_limits(const std::string& name, std::size_t n, std::size_t slow_max_n, std::size_t oracle_max_n) {
    const structure_info* p = find_peer(name);
    return !p || within_limits(*p, n, slow_max_n, oracle_max_n);
}

}  // namespace harness
