#pragma once
// spatial::bvh's settings and statistics: bvh_config (compile-time configuration with
// commented defaults, as madmann91/bvh's Config structs), the bvh_median_config and
// bvh_sah_config shorthands, and bvh_stats (what last_query_stats() reports). The build
// methods themselves (bvh_build_method) are described in bvh/builders.hpp, the wide ray
// layout in bvh/wide_ray_layout.hpp.

#include <cstddef>

#include "spatial/bvh/builders.hpp"
#include "spatial/bvh/wide_ray_layout.hpp"
#include "spatial/core/object_concepts.hpp"
#include "spatial/core/query_stats.hpp"

namespace spatial {

// Compile-time configuration with commented defaults.
template <std::size_t LeafSize = 4, bvh_build_method Builder = bvh_build_method::binned_sah,
          std::size_t SahBins = 16>
struct bvh_config {
    // Objects per leaf (at most). 4 is the usual SAH choice for ray tracing (Wald 2007);
    // larger leaves build faster and suit kNN over points.
    static constexpr std::size_t leaf_size = LeafSize;
    static constexpr bvh_build_method builder = Builder;
    // Bins per axis of the binned SAH (Wald 2007 found 16-32 as good as a full sweep).
    static constexpr std::size_t sah_bins = SahBins;
    // SAH constants C_trav and C_isect (only their ratio matters).
    static constexpr double traversal_cost = 1.0;
    static constexpr double intersection_cost = 1.0;
    // Full rebuild after rebuild_factor * max(size at last build, min_rebuild_updates)
    // inserts + erases.
    static constexpr double rebuild_factor = 1.0;
    static constexpr std::size_t min_rebuild_updates = 32;
    // Motion, automatic strategy (update(first, last)): reinsert the moved objects when at
    // most reinsert_fraction of the tree moved; otherwise refit, and rebuild once the refitted
    // tree's node-box area (relative to the root's) exceeds refit_quality_limit times its
    // value at the last build. Measured in results/collide.csv (refit_decay rows).
    static constexpr double reinsert_fraction = 1.0 / 32;
    static constexpr double refit_quality_limit = 1.3;
    // BV = aabb only: cast rays on a wide (8 or 4 lanes) copy of the tree with quantised
    // child boxes and the objects in leaf order (bvh/wide_ray_layout.hpp; triangles as SIMD
    // blocks of their vertices), built on the first ray cast after a change or by
    // prepare_rays(). Same answers; costs a copy of the objects (or of their vertices).
    static constexpr bool wide_ray_layout = true;
    // Lanes of a wide node: 8 with AVX (one 256-bit slab test per axis), else 4.
    static constexpr std::size_t wide_ray_width = bvh_detail::default_wide_ray_width;
    // Where the wide layout's leaves find their objects (wide_ray_layout.hpp): copies in the
    // layout (fastest), or the container's objects in place after a bulk build (the layout is
    // then only its nodes: memory against time in docs/structures/bvh.md).
    static constexpr bvh_ray_leaves ray_leaves = bvh_ray_leaves::copies;
    // A full build leaves an eighth of its node and leaf-block arrays spare, so the updates
    // that follow it do not copy them at once (core/capacity_headroom.hpp); false fits them
    // exactly: less memory for a tree built to be read, and the first insertion after the
    // build then copies both arrays.
    static constexpr bool build_headroom = true;
};

template <std::size_t LeafSize = 4>
using bvh_median_config = bvh_config<LeafSize, bvh_build_method::median_split>;
template <std::size_t LeafSize = 4, std::size_t Bins = 16>
using bvh_sah_config = bvh_config<LeafSize, bvh_build_method::binned_sah, Bins>;

// The default configuration of bvh<O>: leaves of 4 objects with extent (the SAH choice for
// rays, Wald 2007), and of 8 points. A bulk-built point tree fills its leaves half (see
// bvh::sah_block), so a leaf of 8 holds about 4 points after a build and takes 4 more
// insertions before it splits; leaves of 4 built full made every later insertion split a
// leaf and read its points (docs/experiments/bvh-rays.md, point leaves).
template <class O>
using bvh_default_config = bvh_config<point_object<O> ? 8 : 4>;

// nodes_visited: nodes whose volume was entered; objects_tested: exact object tests.
struct bvh_stats : query_stats {
    bool wide_ray_layout = false;    // last query was a ray cast on the wide layout (nodes
                                     // visited then counts wide nodes)
    bool wide_leaves_in_place = false;  // ... whose leaves tested the stored objects where the
                                        // container keeps them (wide_ray_layout.hpp)
};

}  // namespace spatial
