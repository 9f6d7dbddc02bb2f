#pragma once
// datasets::triangle_mesh — an indexed triangle mesh (shared vertices + index triples), the
// form meshes are loaded and generated in, and its conversion to the library's triangle
// objects (spatial::objects::triangle<T, 3>) that our containers store.
//
// Indexed rather than a soup because peers (Embree) take vertex and index buffers directly,
// and a closed mesh keeps its shared edges bit-identical in every triangle that uses them,
// which the watertight ray test relies on (Woop, Benthin & Wald 2013).
// Loading files (OFF, PLY, OBJ, STL) goes through CGAL and lives in the harness's CGAL
// adapter (harness/mesh_loading.hpp); generators are in datasets/mesh_generators.hpp.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "spatial/core/point.hpp"
#include "spatial/objects/triangle.hpp"

namespace datasets {

struct triangle_mesh {
    using vertex_type = spatial::point<double, 3>;
    using index_triple = std::array<std::uint32_t, 3>;

    std::vector<vertex_type> vertices;
    std::vector<index_triple> triangles;  // counter-clockwise as stored in the source

    std::size_t size() const noexcept { return triangles.size(); }
};

// Throws std::invalid_argument naming `what` (a file name or generator) when an index is out
// of range or a vertex coordinate is not finite. O(V + F).
inline void require_valid_mesh(const triangle_mesh& mesh, const std::string& what) {
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
        for (std::size_t d = 0; d < 3; ++d)
            if (!std::isfinite(mesh.vertices[i][d]))
                throw std::invalid_argument(what + ": vertex " + std::to_string(i) + " has a non-finite coordinate");
    const auto count = mesh.vertices.size();
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f)
        for (std::uint32_t v : mesh.triangles[f])
            if (v >= count)
                throw std::invalid_argument(what + ": triangle " + std::to_string(f) + " uses vertex " +
                                            std::to_string(v) + " but the mesh has " + std::to_string(count) +
                                            " vertices");
}

// Axis-aligned bounds of the vertices used by triangles (lo > hi for an empty mesh).
struct mesh_bounds {
    std::array<double, 3> lo{}, hi{};
    std::array<double, 3> center() const { return {(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2}; }
    double diagonal() const {
        double s = 0;
        for (std::size_t d = 0; d < 3; ++d) s += (hi[d] - lo[d]) * (hi[d] - lo[d]);
        return std::sqrt(s);
    }
};

inline mesh_bounds bounds_of(const triangle_mesh& mesh) {
    mesh_bounds b;
    b.lo.fill(1e300);
    b.hi.fill(-1e300);
    for (const auto& tri : mesh.triangles)
        for (std::uint32_t v : tri)
            for (std::size_t d = 0; d < 3; ++d) {
                b.lo[d] = std::min(b.lo[d], mesh.vertices[v][d]);
                b.hi[d] = std::max(b.hi[d], mesh.vertices[v][d]);
            }
    return b;
}

// The mesh's triangles as objects in scalar T: element i is triangle i of the mesh (the
// harness relies on that order to compare hit triangles). Coordinates are rounded to T once
// per vertex, so triangles sharing a vertex still share it bit for bit. O(F).
template <class T>
std::vector<spatial::objects::triangle<T, 3>> to_triangles(const triangle_mesh& mesh) {
    std::vector<spatial::point<T, 3>> converted(mesh.vertices.size());
    for (std::size_t i = 0; i < converted.size(); ++i)
        for (std::size_t d = 0; d < 3; ++d) converted[i][d] = static_cast<T>(mesh.vertices[i][d]);
    std::vector<spatial::objects::triangle<T, 3>> out;
    out.reserve(mesh.triangles.size());
    for (const auto& tri : mesh.triangles) out.emplace_back(converted[tri[0]], converted[tri[1]], converted[tri[2]]);
    return out;
}

}  // namespace datasets
