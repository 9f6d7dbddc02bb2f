#pragma once
// The objects of a scene's sets: seeded generation (points, boxes, spheres, triangles),
// mesh sets turned into triangle objects, and the objects churn inserts and erases.
//
// A runner dispatches once on (scene.dimension, scene.scalar) and, per set, on its kind:
//
//     datasets::with_object_type<double, 3>(set.kind, [&](auto type) {
//         using object = typename decltype(type)::type;  // e.g. spatial::objects::box<double, 3>
//         std::vector<object> objects;
//         if constexpr (std::is_same_v<object, spatial::objects::triangle<double, 3>>)
//             if (set.mesh && set.mesh->from == datasets::mesh_source::origin::file)
//                 objects = datasets::mesh_objects<double>(load_mesh(set.mesh->file), *set.mesh);
//         if (objects.empty()) objects = datasets::generate_objects<object>(scene, set_index);
//         ...
//     });
//
// Generator sets: sizes are drawn first (box edge / sphere radius / triangle circumradius, see
// draw_sizes), then centres from the set's point workload (generators.hpp, in [0, 1]^D) mapped
// into the domain SHRUNK by each object's half-extent (box: size/2, sphere and triangle: size),
// so every object starts inside the domain when it fits (clusters may poke out by their 8.6
// sigma tails). Triangles: three vertices at uniformly random angles on the circumcircle, in a
// uniformly random plane (3D). All arithmetic is in double; coordinates are rounded to T once.
//
// Reproducibility: objects depend only on (scene seed, set index, the set's own keys); each
// purpose reads its own stream (scene_streams.hpp). Bit-identical across machines and
// standard libraries when compiled without FMA contraction (the project's -ffp-contract=off):
// unlike generators.hpp, not every product-then-add here is an explicit std::fma.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <unordered_set>
#include <vector>

#include "datasets/deterministic_math.hpp"
#include "datasets/generators.hpp"
#include "datasets/mesh_generators.hpp"
#include "datasets/random.hpp"
#include "datasets/scene.hpp"
#include "datasets/scene_streams.hpp"
#include "datasets/triangle_mesh.hpp"
#include "spatial/core/point.hpp"
#include "spatial/objects/box.hpp"
#include "spatial/objects/sphere.hpp"
#include "spatial/objects/triangle.hpp"

namespace datasets {

// ---- object types of a set -------------------------------------------------------------------

// The object_kind of an object type (point, box, sphere, triangle of any T, D).
template <class Object>
struct scene_object_traits;
template <class T, std::size_t D>
struct scene_object_traits<spatial::point<T, D>> {
    static constexpr object_kind kind = object_kind::point;
};
template <class T, std::size_t D>
struct scene_object_traits<spatial::objects::box<T, D>> {
    static constexpr object_kind kind = object_kind::box;
};
template <class T, std::size_t D>
struct scene_object_traits<spatial::objects::sphere<T, D>> {
    static constexpr object_kind kind = object_kind::sphere;
};
template <class T, std::size_t D>
struct scene_object_traits<spatial::objects::triangle<T, D>> {
    static constexpr object_kind kind = object_kind::triangle;
};

template <class Object>
concept scene_object = requires { scene_object_traits<Object>::kind; };

// Calls f(std::type_identity<Object>{}) with the object type of `kind` in scalar T and
// dimension D, and returns what it returns (every instantiation must return the same type).
template <class T, std::size_t D, class F>
decltype(auto) with_object_type(object_kind kind, F&& f) {
    switch (kind) {
        case object_kind::point: return f(std::type_identity<spatial::point<T, D>>{});
        case object_kind::box: return f(std::type_identity<spatial::objects::box<T, D>>{});
        case object_kind::sphere: return f(std::type_identity<spatial::objects::sphere<T, D>>{});
        case object_kind::triangle: break;
    }
    return f(std::type_identity<spatial::objects::triangle<T, D>>{});
}

// ---- mesh sets -------------------------------------------------------------------------------

// The mesh as a set places it: every vertex x -> offset + scale * n(x), where n maps the mesh's
// bounding box into the unit cube (largest extent 1, centred at 0.5 on every axis) when
// source.normalize is set, and is the identity otherwise. Vertices are transformed once, so
// triangles that share a vertex still share it bit for bit (watertight rays). O(V + F).
// Throws std::invalid_argument (naming source.reference) for an empty or invalid mesh.
inline triangle_mesh placed_mesh(triangle_mesh mesh, const mesh_source& source) {
    require_valid_mesh(mesh, source.reference);
    if (mesh.triangles.empty()) throw std::invalid_argument(source.reference + ": the mesh has no triangles");
    const mesh_bounds b = bounds_of(mesh);
    double extent = 0;
    for (std::size_t d = 0; d < 3; ++d) extent = std::max(extent, b.hi[d] - b.lo[d]);
    const bool normalize = source.normalize && extent > 0;  // a single point stays where it is
    const auto centre = b.center();
    for (auto& v : mesh.vertices)
        for (std::size_t d = 0; d < 3; ++d) {
            const double unit = normalize ? (v[d] - centre[d]) / extent + 0.5 : v[d];
            v[d] = std::fma(source.scale, unit, source.offset[d]);
        }
    return mesh;
}

// The triangle objects of a mesh set: triangle i is mesh triangle i, placed by placed_mesh.
// This is all a runner needs after loading a mesh file (mesh_source::file). O(V + F).
template <class T>
std::vector<spatial::objects::triangle<T, 3>> mesh_objects(const triangle_mesh& mesh, const mesh_source& source) {
    return to_triangles<T>(placed_mesh(mesh, source));
}

// The generated mesh of a "generated:..." mesh set (before placement). O(triangles).
inline triangle_mesh generated_scene_mesh(const scene_description& scene, std::size_t set_index) {
    const auto& set = scene.objects.at(set_index);
    if (!set.mesh || set.mesh->from != mesh_source::origin::generated)
        throw std::invalid_argument("generated_scene_mesh: set '" + set.name + "' is not a generated mesh");
    return generate_mesh(set.mesh->generator, set.mesh->triangles,
                         scene_stream_seed(scene.seed, set_index, scene_stream::mesh));
}

// ---- generator sets --------------------------------------------------------------------------

namespace detail {

// n sizes of a generator set. All three distributions have mean `size` (before the cap):
//   fixed         every object: size.
//   uniform       uniform in [size/2, 3 size/2).
//   heavy_tailed  Pareto with shape alpha = 2 and minimum x_m = size/2 (mean size, infinite
//                 variance: P(s > x) = (x_m / x)^2), clamped to size_max (default 10 size,
//                 reached by 0.25% of the objects; the clamp lowers the mean to 0.975 size).
//                 Drawn by inversion: x_m / sqrt(1 - u).
inline std::vector<double> draw_sizes(const generator_source& g, std::size_t n, random_stream& rng) {
    std::vector<double> sizes(n, g.size);
    switch (g.sizes) {
        case size_distribution::fixed: break;
        case size_distribution::uniform:
            for (auto& s : sizes) s = g.size * (0.5 + rng.uniform01<double>());
            break;
        case size_distribution::heavy_tailed:
            for (auto& s : sizes) s = std::min(0.5 * g.size / std::sqrt(1.0 - rng.uniform01<double>()), g.size_max);
            break;
    }
    return sizes;
}

// How far an object of this kind and size reaches from its centre (per axis, at most).
inline double reach(object_kind kind, double size) {
    switch (kind) {
        case object_kind::point: return 0;
        case object_kind::box: return size / 2;
        case object_kind::sphere:
        case object_kind::triangle: break;
    }
    return size;
}

using vec3 = std::array<double, 3>;

inline vec3 cross(const vec3& a, const vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline vec3 normalized(vec3 v) {
    const double length = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (auto& x : v) x /= length;
    return v;
}

// Two orthonormal vectors spanning a uniformly random plane through the origin (3D): the
// plane's normal is a normalised Gaussian vector (Muller 1959).
inline std::array<vec3, 2> random_plane(random_stream& rng) {
    vec3 n{};
    double length = 0;
    while (!(length > 0)) {
        for (auto& x : n) x = rng.gaussian();
        length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    }
    for (auto& x : n) x /= length;
    // Cross with the axis least aligned with n: never (nearly) parallel.
    std::size_t least = 0;
    for (std::size_t d = 1; d < 3; ++d)
        if (std::abs(n[d]) < std::abs(n[least])) least = d;
    vec3 axis{};
    axis[least] = 1;
    const vec3 e1 = normalized(cross(n, axis));
    return {e1, cross(n, e1)};
}

template <class T, std::size_t D>
spatial::point<T, D> rounded(const std::array<double, D>& x) {
    spatial::point<T, D> p;
    for (std::size_t d = 0; d < D; ++d) p[d] = static_cast<T>(x[d]);
    return p;
}

struct generator_seeds {
    std::uint64_t placement, sizes, shapes;
};

// `count` objects of a generator set, drawn from the given streams.
template <class Object>
std::vector<Object> draw_objects(const scene_description& scene, const object_set& set, std::size_t count,
                                 const generator_seeds& seeds) {
    using T = typename Object::scalar_type;
    constexpr std::size_t D = Object::dimension;
    const generator_source& g = *set.generator;

    random_stream size_rng(seeds.sizes);
    const std::vector<double> sizes = draw_sizes(g, count, size_rng);
    const auto unit = generate_points<double, D>(to_string(g.placement), count, seeds.placement);
    random_stream shape_rng(seeds.shapes);

    std::vector<Object> out;
    out.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
        const double size = sizes[i];
        const double margin = reach(set.kind, size);
        std::array<double, D> c{};
        for (std::size_t d = 0; d < D; ++d) {
            const double lo = scene.domain_lo[d] + margin;
            c[d] = std::fma(unit[i][d], (scene.domain_hi[d] - margin) - lo, lo);
        }
        if constexpr (scene_object_traits<Object>::kind == object_kind::point) {
            out.push_back(rounded<T, D>(c));
        } else if constexpr (scene_object_traits<Object>::kind == object_kind::box) {
            std::array<double, D> lo{}, hi{};
            for (std::size_t d = 0; d < D; ++d) {
                lo[d] = c[d] - size / 2;
                hi[d] = c[d] + size / 2;
            }
            out.emplace_back(rounded<T, D>(lo), rounded<T, D>(hi));
        } else if constexpr (scene_object_traits<Object>::kind == object_kind::sphere) {
            out.emplace_back(rounded<T, D>(c), static_cast<T>(size));
        } else {
            std::array<vec3, 2> plane{vec3{1, 0, 0}, vec3{0, 1, 0}};  // 2D: the plane itself
            if constexpr (D == 3) plane = random_plane(shape_rng);
            std::array<spatial::point<T, D>, 3> v;
            for (auto& vertex : v) {
                const sin_cos angle = deterministic_sin_cos_turns(shape_rng.uniform01<double>());
                std::array<double, D> x{};
                for (std::size_t d = 0; d < D; ++d)
                    x[d] = std::fma(size, std::fma(angle.cos, plane[0][d], angle.sin * plane[1][d]), c[d]);
                vertex = rounded<T, D>(x);
            }
            out.emplace_back(v[0], v[1], v[2]);
        }
    }
    return out;
}

template <class Object>
const object_set& checked_set(const scene_description& scene, std::size_t set_index, const char* caller) {
    static_assert(Object::dimension == 2 || Object::dimension == 3, "scene objects are 2D or 3D");
    const object_set& set = scene.objects.at(set_index);
    if (set.kind != scene_object_traits<Object>::kind)
        throw std::invalid_argument(std::string(caller) + ": set '" + set.name + "' holds " +
                                    std::string(to_string(set.kind)) + " objects, not " +
                                    std::string(to_string(scene_object_traits<Object>::kind)));
    if (Object::dimension != scene.dimension)
        throw std::invalid_argument(std::string(caller) + ": the scene is " + std::to_string(scene.dimension) +
                                    "D, the object type " + std::to_string(Object::dimension) + "D");
    return set;
}

}  // namespace detail

// The initial objects of set `set_index`: a generator set's `count` objects, or a generated
// mesh's triangles (placed). A mesh FILE set throws std::invalid_argument: the runner loads the
// file and calls mesh_objects. Also throws std::invalid_argument when Object does not match the
// set's kind or the scene's dimension. O(count) (lattice placement: O(s^D), see generators.hpp).
template <scene_object Object>
std::vector<Object> generate_objects(const scene_description& scene, std::size_t set_index) {
    const object_set& set = detail::checked_set<Object>(scene, set_index, "generate_objects");
    if (set.mesh) {
        if constexpr (scene_object_traits<Object>::kind == object_kind::triangle && Object::dimension == 3) {
            if (set.mesh->from == mesh_source::origin::file)
                throw std::invalid_argument("generate_objects: set '" + set.name + "' is the mesh file " +
                                            set.mesh->file.string() + ": load it and call mesh_objects");
            return mesh_objects<typename Object::scalar_type>(generated_scene_mesh(scene, set_index), *set.mesh);
        }
        throw std::invalid_argument("generate_objects: mesh sets hold 3D triangles");  // the parser ensures it
    }
    return detail::draw_objects<Object>(scene, set, set.generator->count,
                                        {scene_stream_seed(scene.seed, set_index, scene_stream::placement),
                                         scene_stream_seed(scene.seed, set_index, scene_stream::sizes),
                                         scene_stream_seed(scene.seed, set_index, scene_stream::shapes)});
}

// ---- churn -----------------------------------------------------------------------------------

// The scene.churn->inserts_per_step objects churn inserts into its target set at `step`
// (0-based): drawn exactly like the set's initial objects (same placement, size distribution,
// kind) but from the step's own streams, so step s inserts the same objects in every run.
// Lattice and duplicates placements draw a fresh small lattice / duplicate pool per step.
template <scene_object Object>
std::vector<Object> generate_churn_objects(const scene_description& scene, std::size_t step) {
    if (!scene.churn) throw std::invalid_argument("generate_churn_objects: the scene has no churn effect");
    const std::size_t target = scene.churn->target;
    const object_set& set = detail::checked_set<Object>(scene, target, "generate_churn_objects");
    const std::uint64_t base = scene_stream_seed(scene.seed, target, scene_stream::churn_inserts, step);
    return detail::draw_objects<Object>(scene, set, scene.churn->inserts_per_step,
                                        {derive_seed(base, 1), derive_seed(base, 2), derive_seed(base, 3)});
}

// Which objects churn erases at `step` from a set that holds `current_size` objects (in the
// runner's order): min(erases_per_step, current_size) distinct indices, uniformly random, in
// DECREASING order, so that erasing them one by one with swap-and-pop (move the last object
// into the hole, as scene_motion::erase does with its state) erases exactly these objects.
// O(erases) expected time and memory (Floyd's sampling, Bentley & Floyd 1987).
inline std::vector<std::size_t> churn_erase_indices(const scene_description& scene, std::size_t step,
                                                    std::size_t current_size) {
    if (!scene.churn) throw std::invalid_argument("churn_erase_indices: the scene has no churn effect");
    const std::size_t m = std::min(scene.churn->erases_per_step, current_size);
    random_stream rng(scene_stream_seed(scene.seed, scene.churn->target, scene_stream::churn_erases, step));
    // Floyd: for j = n - m .. n - 1, pick t in [0, j]; take t unless taken, else take j. The
    // hash set only answers membership, so the result does not depend on its iteration order.
    std::vector<std::size_t> chosen;
    chosen.reserve(m);
    std::unordered_set<std::size_t> taken;
    taken.reserve(m);
    for (std::size_t j = current_size - m; j < current_size; ++j) {
        const auto t = static_cast<std::size_t>(rng.uniform_index(j + 1));
        const std::size_t pick = taken.contains(t) ? j : t;
        taken.insert(pick);
        chosen.push_back(pick);
    }
    std::sort(chosen.begin(), chosen.end(), std::greater<>());
    return chosen;
}

}  // namespace datasets
