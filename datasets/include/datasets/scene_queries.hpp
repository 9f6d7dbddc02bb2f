#pragma once
// The queries a scene's effects make at each step: rays (raycast), query points (nearest) and
// query boxes (range). Each step reads its own stream (scene_streams.hpp), so step s asks the
// same questions in every run, whatever the structure under test.
//
//   rays, kind = "random"  origin uniform in the domain, direction uniform on the unit sphere
//                          (circle in 2D): incoherent rays.
//   rays, kind = "camera"  a pinhole camera at `eye` looking at `look_at`, up = +z (+x when
//                          looking along z): 3D, an image of w = ceil(sqrt(n)) columns and
//                          ceil(n / w) rows of square pixels, field_of_view across the width,
//                          one ray per pixel in row-major order through a random point of the
//                          pixel (jittered per step); 2D, a fan of n rays across field_of_view
//                          from left to right as seen from the eye, one per equal angular slot,
//                          jittered inside it. Coherent rays.
//   nearest queries        uniform in the domain.
//   range queries          boxes centre -/+ half_extent, centres uniform in the domain.
//
// Rays have unit-length directions and carry the effect's thickness.

#include <array>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <vector>

#include "datasets/deterministic_math.hpp"
#include "datasets/random.hpp"
#include "datasets/scene.hpp"
#include "datasets/scene_streams.hpp"
#include "spatial/core/point.hpp"
#include "spatial/core/ray.hpp"
#include "spatial/objects/box.hpp"

namespace datasets {

namespace detail {

template <std::size_t D>
std::array<double, D> uniform_in_domain(const scene_description& scene, random_stream& rng) {
    std::array<double, D> x{};
    for (std::size_t d = 0; d < D; ++d)
        x[d] = std::fma(rng.uniform01<double>(), scene.domain_hi[d] - scene.domain_lo[d], scene.domain_lo[d]);
    return x;
}

template <std::size_t D>
std::array<double, D> unit_vector(std::array<double, D> v) {
    double sum = 0;
    for (double x : v) sum = std::fma(x, x, sum);
    const double length = std::sqrt(sum);
    for (auto& x : v) x /= length;
    return v;
}

template <std::size_t D>
std::array<double, D> random_direction(random_stream& rng) {
    std::array<double, D> v{};
    double sum = 0;
    while (!(sum > 0)) {  // all-zero Gaussians: redraw
        sum = 0;
        for (auto& x : v) {
            x = rng.gaussian();
            sum = std::fma(x, x, sum);
        }
    }
    return unit_vector(v);
}

// sin and cos of `radians` (any sign) through the deterministic turns version.
inline sin_cos sin_cos_radians(double radians) {
    constexpr double two_pi = 6.283185307179586476925286766559;
    double turns = radians / two_pi;
    turns -= std::floor(turns);
    if (turns >= 1) turns = 0;
    return deterministic_sin_cos_turns(turns);
}

template <class T, std::size_t D>
spatial::ray<spatial::point<T, D>> make_ray(const std::array<double, D>& origin, const std::array<double, D>& direction,
                                            double thickness) {
    spatial::ray<spatial::point<T, D>> r;
    for (std::size_t d = 0; d < D; ++d) {
        r.origin[d] = static_cast<T>(origin[d]);
        r.direction[d] = static_cast<T>(direction[d]);
    }
    r.thickness = static_cast<T>(thickness);
    return r;
}

}  // namespace detail

// The rays of scene.raycast at `step` (rays_per_step of them). Throws std::invalid_argument
// when the scene has no raycast effect or D is not its dimension. O(rays_per_step).
template <class T, std::size_t D>
std::vector<spatial::ray<spatial::point<T, D>>> generate_rays(const scene_description& scene, std::size_t step) {
    static_assert(D == 2 || D == 3, "scenes are 2D or 3D");
    if (!scene.raycast) throw std::invalid_argument("generate_rays: the scene has no raycast effect");
    if (scene.dimension != D) throw std::invalid_argument("generate_rays: D is not the scene's dimension");
    const raycast_effect& effect = *scene.raycast;
    random_stream rng(scene_stream_seed(scene.seed, scene_wide, scene_stream::rays, step));
    const std::size_t n = effect.rays_per_step;
    std::vector<spatial::ray<spatial::point<T, D>>> rays;
    rays.reserve(n);

    if (effect.kind == ray_kind::random) {
        for (std::size_t i = 0; i < n; ++i) {
            const auto origin = detail::uniform_in_domain<D>(scene, rng);
            rays.push_back(detail::make_ray<T, D>(origin, detail::random_direction<D>(rng), effect.thickness));
        }
        return rays;
    }

    std::array<double, D> eye{}, forward{};
    for (std::size_t d = 0; d < D; ++d) {
        eye[d] = effect.eye[d];
        forward[d] = effect.look_at[d] - effect.eye[d];
    }
    forward = detail::unit_vector(forward);
    const double half_angle = effect.field_of_view * (3.141592653589793238462643383279 / 360.0);
    if constexpr (D == 2) {
        for (std::size_t i = 0; i < n; ++i) {
            const double slot = (static_cast<double>(i) + rng.uniform01<double>()) / static_cast<double>(n);
            const detail::sin_cos sc = detail::sin_cos_radians((1 - 2 * slot) * half_angle);  // left to right
            const std::array<double, 2> direction{forward[0] * sc.cos - forward[1] * sc.sin,
                                                  forward[0] * sc.sin + forward[1] * sc.cos};
            rays.push_back(detail::make_ray<T, 2>(eye, direction, effect.thickness));
        }
    } else {
        const std::array<double, 3> world_up =
            std::abs(forward[2]) > 0.999 ? std::array<double, 3>{1, 0, 0} : std::array<double, 3>{0, 0, 1};
        const auto cross = [](const std::array<double, 3>& a, const std::array<double, 3>& b) {
            return std::array<double, 3>{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                                         a[0] * b[1] - a[1] * b[0]};
        };
        const auto right = detail::unit_vector(cross(forward, world_up));
        const auto up = cross(right, forward);
        const detail::sin_cos half = detail::sin_cos_radians(half_angle);
        const double tan_half = half.sin / half.cos;
        std::size_t width = 1;
        while (width * width < n) ++width;  // ceil(sqrt(n)) in integers
        const std::size_t height = (n + width - 1) / width;
        const double pixel = 2 * tan_half / static_cast<double>(width);  // square pixels
        for (std::size_t i = 0; i < n; ++i) {
            const double col = static_cast<double>(i % width) + rng.uniform01<double>();
            const double row = static_cast<double>(i / width) + rng.uniform01<double>();
            const double sx = (col - static_cast<double>(width) / 2) * pixel;
            const double sy = (static_cast<double>(height) / 2 - row) * pixel;
            std::array<double, 3> direction{};
            for (std::size_t d = 0; d < 3; ++d) direction[d] = forward[d] + sx * right[d] + sy * up[d];
            rays.push_back(detail::make_ray<T, 3>(eye, detail::unit_vector(direction), effect.thickness));
        }
    }
    return rays;
}

// The query points of scene.nearest at `step`. O(queries_per_step).
template <class T, std::size_t D>
std::vector<spatial::point<T, D>> generate_nearest_queries(const scene_description& scene, std::size_t step) {
    if (!scene.nearest) throw std::invalid_argument("generate_nearest_queries: the scene has no nearest effect");
    if (scene.dimension != D) throw std::invalid_argument("generate_nearest_queries: D is not the scene's dimension");
    random_stream rng(scene_stream_seed(scene.seed, scene_wide, scene_stream::nearest, step));
    std::vector<spatial::point<T, D>> out(scene.nearest->queries_per_step);
    for (auto& q : out) {
        const auto x = detail::uniform_in_domain<D>(scene, rng);
        for (std::size_t d = 0; d < D; ++d) q[d] = static_cast<T>(x[d]);
    }
    return out;
}

// The query boxes of scene.range at `step`. O(queries_per_step).
template <class T, std::size_t D>
std::vector<spatial::objects::box<T, D>> generate_range_queries(const scene_description& scene, std::size_t step) {
    if (!scene.range) throw std::invalid_argument("generate_range_queries: the scene has no range effect");
    if (scene.dimension != D) throw std::invalid_argument("generate_range_queries: D is not the scene's dimension");
    random_stream rng(scene_stream_seed(scene.seed, scene_wide, scene_stream::range, step));
    const double h = scene.range->half_extent;
    std::vector<spatial::objects::box<T, D>> out;
    out.reserve(scene.range->queries_per_step);
    for (std::size_t i = 0; i < scene.range->queries_per_step; ++i) {
        const auto c = detail::uniform_in_domain<D>(scene, rng);
        spatial::point<T, D> lo, hi;
        for (std::size_t d = 0; d < D; ++d) {
            lo[d] = static_cast<T>(c[d] - h);
            hi[d] = static_cast<T>(c[d] + h);
        }
        out.emplace_back(lo, hi);
    }
    return out;
}

}  // namespace datasets
