#pragma once
// The random streams of a scene: every draw a scene makes (object centres, sizes, triangle
// shapes, velocities, churn, rays, query points) reads its own splitmix64-derived stream of the
// scene's seed, keyed by (object set, purpose, step). So adding a set, an effect or a step never
// changes what the others draw, and set i's objects do not depend on set j's count.
//
// The purposes are part of every derived seed: never renumber them (that would change every
// scene's objects and queries).

#include <cstddef>
#include <cstdint>

#include "datasets/random.hpp"

namespace datasets {

enum class scene_stream : std::uint64_t {
    placement = 1,      // centres (through generate_points)
    sizes = 2,          // box edges, sphere radii, triangle circumradii
    shapes = 3,         // triangle orientations and vertex angles
    motion = 4,         // initial velocities (linear), displacements (random_walk)
    churn_inserts = 5,  // per step: the objects inserted by churn
    churn_erases = 6,   // per step: which objects churn erases
    mesh = 7,           // generated meshes ("generated:soup")
    rays = 8,           // per step, scene-wide
    nearest = 9,        // per step, scene-wide
    range = 10,         // per step, scene-wide
};

// Scene-wide streams (rays, query points) are not tied to a set.
inline constexpr std::size_t scene_wide = static_cast<std::size_t>(-1);

// The seed of stream `purpose` of set `set_index` (or scene_wide) at `step`. O(1).
inline std::uint64_t scene_stream_seed(std::uint64_t scene_seed, std::size_t set_index, scene_stream purpose,
                                       std::uint64_t step = 0) {
    const std::uint64_t set_tag = set_index == scene_wide ? 0 : static_cast<std::uint64_t>(set_index) + 1;
    return derive_seed(derive_seed(scene_seed, (set_tag << 8) | static_cast<std::uint64_t>(purpose)), step);
}

}  // namespace datasets
