#pragma once
// Factories for the peer broad phases put behind harness::collide_index. Declarations only:
// each is defined in its adapter's .cpp, so CGAL's, FCL's, Embree's and Boost.Geometry's
// headers (and FCL's Eigen types) stay inside their adapter libraries. A factory exists when
// its library was built (SPATIAL_HAVE_CGAL / SPATIAL_HAVE_FCL / SPATIAL_HAVE_EMBREE /
// SPATIAL_HAVE_BOOST_GEOMETRY);
// make_peer_collide_indices() lists whichever exist, each in its registry configuration and,
// on request, in every configuration of its tuning sweep (harness/tuning_sweep.hpp). A
// factory that takes settings reads them from the full settings it is given and rejects a
// value it cannot run with std::invalid_argument naming the setting.
//
// Every peer returns exactly the closed-box answer (harness::closed_boxes_overlap): each
// checks its candidates with that exact double test, and where the peer's own arithmetic or
// tie handling could LOSE a touching pair, its input boxes are grown so that it cannot (see
// each factory). tests/adapters_collide_test.cpp compares all of them with brute force.

#include <memory>
#include <vector>

#include "harness/collide_index.hpp"
#include "harness/tuning_sweep.hpp"

namespace harness {

// CGAL 5.5 box_self_intersection_d / box_intersection_d (Zomorodian and Edelsbrunner's
// segment-tree streaming algorithm, "Fast software for box intersections", SoCG 2000) with
// Box_intersection_d::CLOSED topology over Box_with_handle_d<double, 3, const collide_box*>:
// the id is the address of the box's own copy, so it maps back to the index and is the same
// in CGAL's internal copy. Setting: cutoff (a positive count; CGAL's default 10), below which
// a block of boxes is scanned pairwise. Exact in double: no candidate filtering needed. No incremental
// structure: update() refreshes the copy; each query is a full sort-and-sweep,
// O(n log^3 n + k). name() "cgal_box_intersection". memory_bytes(): the box copy and CGAL's
// working sequence (box_self_intersection_d also copies that sequence during each query).
std::unique_ptr<collide_index> make_cgal_box_intersection_collide_index(const key_values& settings);

// FCL 0.7 broad-phase managers (CollisionObjectd over a Boxd placed at the box centre, whose
// world AABB is then overwritten with our box exactly; FCL's computeAABB would round
// c +- side/2). Candidates go through the exact closed test in the (plain function pointer)
// callback. update() sets the new AABBs and calls the manager's update(), FCL's incremental
// path. Bipartite queries build a second manager of the same kind over `others`.
//   dynamic_aabb_tree  DynamicAABBTreeCollisionManager: AABBs exact (FCL's AABB::overlap is
//                      closed, so nothing is lost). name() "fcl_dynamic_aabb_tree".
//   sap                SaPCollisionManager: endpoint ties are ordered arbitrarily, so AABBs
//                      are grown by a relative 2^-40 (touching pairs overlap strictly).
//                      FCL's incremental update is used when every box translated; any other
//                      change (FCL's update_ would loop forever) re-registers all boxes in
//                      bulk. name() "fcl_sap".
//   spatial_hashing    SpatialHashingCollisionManager: a box covers cells
//                      [floor(lo/c), ceil(hi/c)), so boxes touching on a cell boundary share
//                      none; grown like sap. Cell size 2 x the median box extent (at least
//                      the scene's side / (4 cbrt(n) + 1)), scene limits the boxes' bounds
//                      plus a cell, rebuilt when update() moves a box out of them.
//                      name() "fcl_spatial_hashing".
// memory_bytes(): objects, their Box geometries and our object table; plus the dynamic
// tree's 2n-1 nodes, SaP's per-object endpoint records and sorted endpoint arrays, the spatial
// hash's bucket array. Not counted: FCL's node-based containers (the dynamic tree's object
// table, SaP's object map and overlap-pair list, the spatial hash's bucket lists).
// Bipartite queries allocate a second object set and manager for `others` per call.
enum class fcl_manager_kind { dynamic_aabb_tree, sap, spatial_hashing };
std::unique_ptr<collide_index> make_fcl_collide_index(fcl_manager_kind kind);

// Embree 3.13 rtcCollide over one RTC_GEOMETRY_TYPE_USER geometry whose float bounds are our
// double boxes rounded OUTWARD (no overlapping pair is lost to float rounding). rtcCollide
// reports every primitive pair of overlapping BVH leaves, both orders for a scene with
// itself: the callback keeps i < j and applies the exact closed double test (and the caller's
// exact test). Setting: build_quality medium (Embree's default; update() rebuilds) | high |
// low (the geometry at REFIT: update() refits). update() re-commits the geometry and the
// scene. Bipartite queries build a second scene over `others`.
// name() "embree_collide". memory_bytes(): what Embree allocated (device memory monitor).
std::unique_ptr<collide_index> make_embree_collide_index(const key_values& settings);

// Boost.Geometry 1.74 rtree: an R*-tree (Beckmann, Kriegel, Schneider and Seeger, SIGMOD 1990)
// over (box, index) values, bgi::rstar<16>, bulk-loaded by the packing constructor (STR-like
// packing: Leutenegger, Lopez and Edgington, ICDE 1997). self_pairs(): one
// query(bgi::intersects(box i)) per box, keeping j > i; pairs_with(): one query per box of
// `others`. Boost compares the doubles exactly and its box/box intersects is closed (disjoint
// only if max < min on some axis), so the answer is the closed-box one with no filtering.
// update(): each box whose coordinates changed is removed with its old value and inserted
// again (Boost's R* insertion, forced reinsertion included); unchanged boxes are not touched.
// No settings: the node capacity is a template argument (one configuration, like the kNN
// peer boost_rtree). name() "boost_rtree_collide". memory_bytes(): every node the tree
// allocated (a counting allocator) and our copy of the boxes.
std::unique_ptr<collide_index> make_boost_rtree_collide_index();

// Every collision peer compiled into this build: each in its registry configuration and, when
// `sweep`, in every configuration of its tuning sweep (labelled with it). FCL's managers and
// Boost's rtree have no setting to sweep.
inline std::vector<std::unique_ptr<collide_index>> make_peer_collide_indices(bool sweep = false) {
    std::vector<std::unique_ptr<collide_index>> out;
    (void)sweep;
#if defined(SPATIAL_HAVE_CGAL) && SPATIAL_HAVE_CGAL
    add_peer_configurations(out, "cgal_box_intersection", make_cgal_box_intersection_collide_index, sweep);
#endif
#if defined(SPATIAL_HAVE_FCL) && SPATIAL_HAVE_FCL
    out.push_back(make_fcl_collide_index(fcl_manager_kind::dynamic_aabb_tree));
    out.push_back(make_fcl_collide_index(fcl_manager_kind::sap));
    out.push_back(make_fcl_collide_index(fcl_manager_kind::spatial_hashing));
#endif
#if defined(SPATIAL_HAVE_BOOST_GEOMETRY) && SPATIAL_HAVE_BOOST_GEOMETRY
    out.push_back(make_boost_rtree_collide_index());
#endif
#if defined(SPATIAL_HAVE_EMBREE) && SPATIAL_HAVE_EMBREE
    add_peer_configurations(out, "embree_collide", make_embree_collide_index, sweep);
#endif
    return out;
}

}  // namespace harness
