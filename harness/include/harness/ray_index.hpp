#pragma once
// harness::ray_index<T> — the runtime interface every benchmarked ray-casting structure
// (ours and the peers' Embree and CGAL AABB_tree) is put behind, so one timing loop and one
// validator serve all. 3D triangle meshes only.
//
// A structure receives the scene in both forms: the indexed mesh (double, as loaded or
// generated; what Embree and CGAL take) and the same triangles as objects in T (what our
// containers store). triangles[i] is mesh triangle i rounded to T. Hits are compared by
// their DISTANCE along the ray (the harness normalises directions), never by triangle id,
// because a ray through a shared edge may legitimately report either neighbour.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "datasets/triangle_mesh.hpp"
#include "harness/configured.hpp"
#include "spatial/core/point.hpp"
#include "spatial/objects/triangle.hpp"

namespace harness {

template <class T>
struct ray_hit {
    T t = std::numeric_limits<T>::infinity();  // ray parameter of the first hit
    std::uint32_t triangle = ~std::uint32_t{0};  // index of the hit triangle in the mesh
};

template <class T>
class ray_index : public configured {  // configuration(): harness/configured.hpp
public:
    using point_type = spatial::point<T, 3>;
    using triangle_type = spatial::objects::triangle<T, 3>;
    virtual ~ray_index() = default;

    // CSV `structure` column (embree, cgal_aabb_tree, brute_force, bvh, ...) and `bv` column.
    virtual std::string name() const = 0;
    virtual std::string bv() const { return {}; }

    // Replace the contents with the scene. The caller keeps `mesh` and `triangles` alive and
    // unchanged until the next build (peers may share the buffers instead of copying).
    virtual void build(const datasets::triangle_mesh& mesh, std::span<const triangle_type> triangles) = 0;
    virtual std::size_t size() const = 0;
    // Bytes held, INCLUDING shared buffers the structure references but does not own.
    virtual std::size_t memory_bytes() const = 0;

    // First hit with 0 <= t < t_max along origin + t * direction; false (hit untouched) if none.
    virtual bool intersect(const point_type& origin, const point_type& direction, T t_max, ray_hit<T>& hit) = 0;
    // Whether any hit with 0 <= t < t_max exists (shadow rays).
    virtual bool occluded(const point_type& origin, const point_type& direction, T t_max) = 0;

    // Nodes visited by the last intersect(), or -1 when the structure cannot report it.
    virtual long long last_nodes_visited() const { return -1; }
    // Properties of the built structure, (metric, value) pairs written as build rows
    // (bvh: node_area_ratio, its node tightness). Empty when it has none.
    virtual std::vector<std::pair<std::string, double>> build_metrics() const { return {}; }
};

}  // namespace harness
