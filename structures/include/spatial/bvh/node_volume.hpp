#pragma once
// How a BVH fits, grows and tests ONE node volume of bounding-volume type BV (bv/*.hpp).
// Everything the bvh needs from a volume beyond the bounding_volume concept lives here, one
// overload per type, so bvh.hpp is written once for all of them.
//
//   fit_node_volume<BV>(pts)   the default FAST fit of each type (a BVH fits O(n log n) points
//                              in total): aabb::fit, sphere::fit_ritter (Ritter 1990),
//                              obb::fit_pca (Gottschalk, Lin & Manocha 1996), kdop::fit,
//                              ellipsoid::fit_pca, convex_hull::fit (Quickhull).
//   grown_ray_interval(bv, box, o, d, r, t0, t1)
//                              a CONSERVATIVE line interval of the volume grown by r (its
//                              Minkowski sum with a ball of radius r is inside the tested set):
//                              false only if the line passes farther than r from every point
//                              of bv. The bvh calls it with r = ray thickness + a rounding
//                              slack, so neither a thick ray nor a ray grazing a node (an
//                              origin on a node boundary, a ray along a face) is ever pruned
//                              wrongly. Per type: aabb/obb widen the half-extents by r, sphere
//                              the radius, kdop each slab by r |n_j|_1 (>= r |n_j|_2), the
//                              hull each facet plane by r (unit normals); an ellipsoid is
//                              scaled by 1 + r / a_min (E + B_r is inside that scaled copy:
//                              |x|_E' <= |y|_E / (1 + r/a_min) + (r/a_min) / (1 + r/a_min)),
//                              and when that would be loose (a_min < r, a flat ellipsoid) the
//                              node's aabb grown by r is used instead.
//   volume_heap_bytes(bv)      heap memory the volume owns (convex_hull only), for memory_bytes.
//   volume_name<BV>()          a short name for statistics and benchmark tables.
// All O(1) per call except convex_hull (O(facets)) and the fits (O(points)).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <string>

#include "spatial/bv/aabb.hpp"
#include "spatial/bv/convex_hull.hpp"
#include "spatial/bv/ellipsoid.hpp"
#include "spatial/bv/kdop.hpp"
#include "spatial/bv/obb.hpp"
#include "spatial/bv/sphere.hpp"

namespace spatial::bvh_detail {

// ---------------------------------------------------------------- fits
template <class T, std::size_t D>
aabb<T, D> fit_node_volume(std::span<const point<T, D>> pts, const aabb<T, D>*) { return aabb<T, D>::fit(pts); }
template <class T, std::size_t D>
sphere<T, D> fit_node_volume(std::span<const point<T, D>> pts, const sphere<T, D>*) {
    return sphere<T, D>::fit_ritter(pts);
}
template <class T, std::size_t D>
obb<T, D> fit_node_volume(std::span<const point<T, D>> pts, const obb<T, D>*) { return obb<T, D>::fit_pca(pts); }
template <class T, std::size_t D, std::size_t K>
kdop<T, D, K> fit_node_volume(std::span<const point<T, D>> pts, const kdop<T, D, K>*) {
    return kdop<T, D, K>::fit(pts);
}
template <class T, std::size_t D>
ellipsoid<T, D> fit_node_volume(std::span<const point<T, D>> pts, const ellipsoid<T, D>*) {
    return ellipsoid<T, D>::fit_pca(pts);
}
template <class T, std::size_t D>
convex_hull<T, D> fit_node_volume(std::span<const point<T, D>> pts, const convex_hull<T, D>*) {
    return convex_hull<T, D>::fit(pts);
}
template <class BV>
BV fit_volume(std::span<const typename BV::point_type> pts) {
    return fit_node_volume(pts, static_cast<const BV*>(nullptr));
}

// ---------------------------------------------------------------- grown ray intervals
template <class T, std::size_t D>
bool grown_ray_interval(const aabb<T, D>& b, const aabb<T, D>&, const point<T, D>& o, const point<T, D>& d, T r,
                        T& t0, T& t1) {
    aabb<T, D> g = b;
    for (std::size_t i = 0; i < D; ++i) g.lo[i] -= r, g.hi[i] += r;
    return g.ray_interval(o, d, t0, t1);
}
template <class T, std::size_t D>
bool grown_ray_interval(const sphere<T, D>& s, const aabb<T, D>&, const point<T, D>& o, const point<T, D>& d, T r,
                        T& t0, T& t1) {
    if (s.is_empty()) return false;
    sphere<T, D> g = s;
    g.radius += r;
    return g.ray_interval(o, d, t0, t1);
}
template <class T, std::size_t D>
bool grown_ray_interval(const obb<T, D>& b, const aabb<T, D>&, const point<T, D>& o, const point<T, D>& d, T r,
                        T& t0, T& t1) {
    if (b.is_empty()) return false;
    obb<T, D> g = b;
    for (std::size_t k = 0; k < D; ++k) g.half_extents[k] += r;
    return g.ray_interval(o, d, t0, t1);
}
template <class T, std::size_t D, std::size_t K>
bool grown_ray_interval(const kdop<T, D, K>& b, const aabb<T, D>&, const point<T, D>& o, const point<T, D>& d, T r,
                        T& t0, T& t1) {
    if (b.is_empty()) return false;
    kdop<T, D, K> g = b;
    for (std::size_t j = 0; j < K / 2; ++j) {
        T l1 = 0;
        for (std::size_t i = 0; i < D; ++i) l1 += static_cast<T>(std::abs(kdop<T, D, K>::directions[j][i]));
        g.lo[j] -= r * l1;
        g.hi[j] += r * l1;
    }
    return g.ray_interval(o, d, t0, t1);
}
template <class T, std::size_t D>
bool grown_ray_interval(const ellipsoid<T, D>& e, const aabb<T, D>& box, const point<T, D>& o,
                        const point<T, D>& d, T r, T& t0, T& t1) {
    if (e.is_empty()) return false;
    T amin = std::numeric_limits<T>::infinity();
    for (std::size_t k = 0; k < D; ++k) amin = std::min(amin, e.semi_axes[k]);
    if (!(amin >= r) || !(amin > 0)) return grown_ray_interval(box, box, o, d, r, t0, t1);
    ellipsoid<T, D> g = e;
    // 1 + r / amin, rounded up by a few ulps so the scaled copy still contains E + B_r.
    const T f = (1 + r / amin) * (1 + 4 * std::numeric_limits<T>::epsilon());
    for (std::size_t k = 0; k < D; ++k) g.semi_axes[k] *= f;
    return g.ray_interval(o, d, t0, t1);
}
// Cyrus & Beck (1978) clipping against the hull's facet planes, each pushed out by r (unit
// normals; the factor covers their rounding) on top of the hull's own tolerance().
template <class T, std::size_t D>
bool grown_ray_interval(const convex_hull<T, D>& h, const aabb<T, D>&, const point<T, D>& o, const point<T, D>& d,
                        T r, T& t0, T& t1) {
    return h.ray_interval(o, d, t0, t1, r * (1 + T(4 * D) * std::numeric_limits<T>::epsilon()));
}

// ---------------------------------------------------------------- memory, names
template <class BV>
std::size_t volume_heap_bytes(const BV& bv) {
    if constexpr (requires { bv.vertices(); bv.planes(); bv.triangles(); })
        return bv.vertices().size() * sizeof(typename BV::point_type) +
               bv.planes().size() * sizeof(typename decltype(bv.planes())::value_type) +
               bv.triangles().size() * sizeof(typename decltype(bv.triangles())::value_type);
    else return 0;
}

template <class T, std::size_t D>
std::string volume_name(const aabb<T, D>*) { return "aabb"; }
template <class T, std::size_t D>
std::string volume_name(const sphere<T, D>*) { return "sphere"; }
template <class T, std::size_t D>
std::string volume_name(const obb<T, D>*) { return "obb"; }
template <class T, std::size_t D, std::size_t K>
std::string volume_name(const kdop<T, D, K>*) { return "kdop" + std::to_string(K); }
template <class T, std::size_t D>
std::string volume_name(const ellipsoid<T, D>*) { return "ellipsoid"; }
template <class T, std::size_t D>
std::string volume_name(const convex_hull<T, D>*) { return "convex_hull"; }

}  // namespace spatial::bvh_detail
