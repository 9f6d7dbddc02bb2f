#pragma once
// Seeded and procedural triangle meshes for the ray-casting workloads. Like the point
// workloads (generators.hpp) they lie in the unit cube and are bit-identical for the same
// arguments on every IEEE-754 machine: only +, -, *, /, sqrt and our deterministic sin/cos
// are used (no <cmath> transcendental whose last bit depends on the C library).
//
//   uv_sphere(stacks, slices)   latitude/longitude tessellation of the sphere of centre
//                               (0.5, 0.5, 0.5), radius 0.5: 2 * slices * (stacks - 1)
//                               triangles; fans at the poles, so slivers there, as in real
//                               UV-sphere assets. Closed and consistently oriented.
//   icosphere(subdivisions)     the icosahedron with each triangle split into 4, `subdivisions`
//                               times, new vertices pushed to the sphere: 20 * 4^s nearly
//                               equal triangles. Closed; every edge shared by exactly 2.
//   random_soup(n, seed)        n independent triangles: a centre uniform in [h, 1 - h]^3 and
//                               three vertices uniform in the cube of half-side h around it,
//                               with h = 1 / ceil(n^(1/3)), so a random line crosses about the
//                               same number of triangles at every n (depth complexity ~ const).
//   generate_mesh(name, n, seed) "sphere" (UV sphere with about n triangles) or "soup".

#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

#include "datasets/deterministic_math.hpp"
#include "datasets/random.hpp"
#include "datasets/triangle_mesh.hpp"

namespace datasets {

// Latitude/longitude sphere. stacks >= 2 bands from pole to pole, slices >= 3 around.
// O(stacks * slices).
inline triangle_mesh uv_sphere(std::size_t stacks, std::size_t slices) {
    if (stacks < 2 || slices < 3)
        throw std::invalid_argument("uv_sphere: needs stacks >= 2 and slices >= 3, got " + std::to_string(stacks) +
                                    " and " + std::to_string(slices));
    triangle_mesh m;
    m.vertices.push_back({{0.5, 0.5, 1.0}});  // north pole: vertex 0
    for (std::size_t i = 1; i < stacks; ++i) {
        // Polar angle i/stacks of a half turn: sin/cos of (i / (2 stacks)) turns.
        const auto polar = detail::deterministic_sin_cos_turns(static_cast<double>(i) / static_cast<double>(2 * stacks));
        for (std::size_t j = 0; j < slices; ++j) {
            const auto az = detail::deterministic_sin_cos_turns(static_cast<double>(j) / static_cast<double>(slices));
            m.vertices.push_back({{0.5 + 0.5 * polar.sin * az.cos, 0.5 + 0.5 * polar.sin * az.sin, 0.5 + 0.5 * polar.cos}});
        }
    }
    const auto south = static_cast<std::uint32_t>(m.vertices.size());
    m.vertices.push_back({{0.5, 0.5, 0.0}});
    auto ring = [&](std::size_t i, std::size_t j) { return static_cast<std::uint32_t>(1 + (i - 1) * slices + j % slices); };
    // Outward (counter-clockwise seen from outside) orientation.
    for (std::size_t j = 0; j < slices; ++j) m.triangles.push_back({0, ring(1, j), ring(1, j + 1)});
    for (std::size_t i = 1; i + 1 < stacks; ++i)
        for (std::size_t j = 0; j < slices; ++j) {
            m.triangles.push_back({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
            m.triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
        }
    for (std::size_t j = 0; j < slices; ++j) m.triangles.push_back({south, ring(stacks - 1, j + 1), ring(stacks - 1, j)});
    return m;
}

// A UV sphere with about n triangles (slices = 2 * stacks: 4 stacks (stacks - 1) triangles, the
// largest such count <= n; at least 8).
inline triangle_mesh uv_sphere_with_about(std::size_t n) {
    std::size_t stacks = 2;
    while (2 * (2 * (stacks + 1)) * stacks <= n) ++stacks;  // O(sqrt n)
    return uv_sphere(stacks, 2 * stacks);
}

// Icosphere (Loop-style 1:4 subdivision of the icosahedron, vertices projected to the sphere).
// O(20 * 4^subdivisions); subdivisions <= 10.
inline triangle_mesh icosphere(std::size_t subdivisions) {
    if (subdivisions > 10) throw std::invalid_argument("icosphere: subdivisions must be <= 10 (20 * 4^10 triangles)");
    triangle_mesh m;
    // Unit-sphere coordinates first, mapped to centre 0.5 / radius 0.5 at the end.
    const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
    const std::array<std::array<double, 3>, 12> ico{{{-1, phi, 0}, {1, phi, 0}, {-1, -phi, 0}, {1, -phi, 0},
                                                     {0, -1, phi}, {0, 1, phi}, {0, -1, -phi}, {0, 1, -phi},
                                                     {phi, 0, -1}, {phi, 0, 1}, {-phi, 0, -1}, {-phi, 0, 1}}};
    std::vector<std::array<double, 3>> unit;
    auto push_unit = [&](std::array<double, 3> p) {
        const double len = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        unit.push_back({p[0] / len, p[1] / len, p[2] / len});
        return static_cast<std::uint32_t>(unit.size() - 1);
    };
    for (const auto& p : ico) push_unit(p);
    std::vector<triangle_mesh::index_triple> faces{{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                                   {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                                   {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                                   {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    for (std::size_t s = 0; s < subdivisions; ++s) {
        // One midpoint per edge, shared by both faces of the edge: keeps the mesh closed.
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoint;
        auto mid = [&](std::uint32_t a, std::uint32_t b) {
            const auto key = std::minmax(a, b);
            const auto it = midpoint.find(key);
            if (it != midpoint.end()) return it->second;
            const auto& p = unit[a];
            const auto& q = unit[b];
            const std::uint32_t v = push_unit({p[0] + q[0], p[1] + q[1], p[2] + q[2]});
            midpoint.emplace(key, v);
            return v;
        };
        std::vector<triangle_mesh::index_triple> next;
        next.reserve(faces.size() * 4);
        for (const auto& f : faces) {
            const auto ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
            next.push_back({f[0], ab, ca});
            next.push_back({f[1], bc, ab});
            next.push_back({f[2], ca, bc});
            next.push_back({ab, bc, ca});
        }
        faces = std::move(next);
    }
    m.vertices.reserve(unit.size());
    for (const auto& p : unit) m.vertices.push_back({{0.5 + 0.5 * p[0], 0.5 + 0.5 * p[1], 0.5 + 0.5 * p[2]}});
    m.triangles = std::move(faces);
    return m;
}

// n random triangles in the unit cube (see the table above). O(n).
inline triangle_mesh random_soup(std::size_t n, std::uint64_t seed) {
    std::uint64_t side = 1;
    while (side * side * side < n) ++side;  // ceil(n^(1/3)) in integers, O(n^(1/3))
    const double h = 1.0 / static_cast<double>(side);
    random_stream rng(derive_seed(seed, 0x50u /* stream: triangle soup */));
    triangle_mesh m;
    m.vertices.reserve(3 * n);
    m.triangles.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        std::array<double, 3> c;
        for (auto& x : c) x = h + (1.0 - 2.0 * h) * rng.uniform01<double>();
        for (int k = 0; k < 3; ++k) {
            triangle_mesh::vertex_type v;
            for (std::size_t d = 0; d < 3; ++d) v[d] = c[d] + h * (2.0 * rng.uniform01<double>() - 1.0);
            m.vertices.push_back(v);
        }
        const auto base = static_cast<std::uint32_t>(3 * i);
        m.triangles.push_back({base, base + 1, base + 2});
    }
    return m;
}

inline constexpr std::array<std::string_view, 2> mesh_workload_names{"sphere", "soup"};

// The generated mesh workload `name` with about n triangles (exactly n for "soup").
// Throws std::invalid_argument for an unknown name, listing the valid ones.
inline triangle_mesh generate_mesh(std::string_view name, std::size_t n, std::uint64_t seed) {
    if (name == "sphere") return uv_sphere_with_about(n);
    if (name == "soup") return random_soup(n, seed);
    throw std::invalid_argument("unknown mesh workload \"" + std::string(name) + "\"; valid workloads: sphere, soup");
}

}  // namespace datasets
