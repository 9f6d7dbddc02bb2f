#pragma once
// Factories for the peer ray casters put behind harness::ray_index<T>. Declarations only:
// each is defined and instantiated for T in {float, double} in its adapter's .cpp, so
// Embree's and CGAL's headers stay inside their adapter libraries. A factory exists when its
// library was built (SPATIAL_HAVE_EMBREE / SPATIAL_HAVE_CGAL); make_peer_ray_indices() lists
// whichever exist, each in its registry configuration and, on request, in every configuration
// of its tuning sweep (harness/tuning_sweep.hpp).

#include <memory>
#include <vector>

#include "harness/ray_index.hpp"
#include "harness/tuning_sweep.hpp"

namespace harness {

// Embree 3 (libembree-dev 3.13): one RTC_GEOMETRY_TYPE_TRIANGLE geometry over SHARED vertex
// and index buffers (no copy of the indices), single-ray rtcIntersect1 / rtcOccluded1.
// Settings (the registry line's, or a tuning sweep's): build_quality low | medium | high
// (RTC_BUILD_QUALITY_*; medium is Embree's default, high adds spatial splits), and flags:
// absent, name() "embree", or robust, RTC_SCENE_FLAG_ROBUST and name() "embree_robust". A
// value it cannot run is std::invalid_argument naming the setting.
// Embree's triangle test is not watertight: rays aimed exactly at a shared vertex or edge of
// a closed mesh can slip through (tests/adapters_raycast_test.cpp counts them); ours and
// CGAL's (exact predicates) do not.
// Embree computes in float only: vertices, origins and directions are rounded to float, and
// hit distances come back as float (widened to T). For T = double this moves vertices by up
// to half a float ulp, so hits agree with double structures to a relative ~1e-6, not exactly.
// memory_bytes(): the bytes Embree allocated (counted by a device memory monitor) plus the
// shared float vertex buffer (the index buffer is the caller's mesh and is counted too).
template <class T>
std::unique_ptr<ray_index<T>> make_embree_ray_index(const key_values& settings);

// CGAL 5.5 AABB_tree over AABB_triangle_primitive with Epick (exact predicates, inexact
// constructions: with Simple_cartesian<double> rays aimed at shared vertices of a closed mesh
// leak through, with Epick they do not); intersect() is tree.first_intersection(ray) (the hit point converted back to a
// ray parameter), occluded() is do_intersect with the ray (or the segment [o, o + t_max d]). Triangles are taken from
// the T objects (converted to double), so they match our containers'. build() calls tree.build() so construction is
// timed, not left to the first query. name() "cgal_aabb_tree"; no settings (the tree has no tuning parameter).
// memory_bytes(): the triangle copies, primitives and nodes (2 children pointers + a Bbox_3 per node, n - 1 nodes):
// what the tree holds.
template <class T>
std::unique_ptr<ray_index<T>> make_cgal_aabb_tree_ray_index();

// Every peer ray caster compiled into this build: each in its registry configuration and,
// when `sweep`, in every configuration of its tuning sweep (labelled with it).
template <class T>
std::vector<std::unique_ptr<ray_index<T>>> make_peer_ray_indices(bool sweep = false) {
    std::vector<std::unique_ptr<ray_index<T>>> out;
    (void)sweep;
#if defined(SPATIAL_HAVE_EMBREE) && SPATIAL_HAVE_EMBREE
    add_peer_configurations(out, "embree", make_embree_ray_index<T>, sweep);
    add_peer_configurations(out, "embree_robust", make_embree_ray_index<T>, sweep);
#endif
#if defined(SPATIAL_HAVE_CGAL) && SPATIAL_HAVE_CGAL
    out.push_back(make_cgal_aabb_tree_ray_index<T>());
#endif
    return out;
}

}  // namespace harness
