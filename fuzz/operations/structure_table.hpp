#pragma once
// The structures the operations fuzzer tests: every in-house structure over 3D double points
// and 3D double boxes (the object types of the benchmarks' main cases; a point and an object
// with extent take different paths in every structure). The first input byte picks one.
// Compile time decides the default set: one instantiation costs about 12 s under the fuzz
// preset's -O1 (line tables) and sanitizers, so the default (the core matrix, 9 structures) has each
// structure once, the kd-tree, and the bvh with aabb (its wide ray layout), over both object
// types; SPATIAL_FUZZ_FULL_MATRIX=ON adds the other 15 (each structure over both types, every
// bvh volume type) for long runs. Each family is instantiated in its own translation unit
// (run_*.cpp), so the units stay small and can compile in parallel. The soak tool (fuzz/soak/)
// runs the same table, always the full matrix.

#include <cstddef>
#include <span>
#include <string_view>
#include <vector>

#include "fuzz_input.hpp"
#include "sequence_limits.hpp"
#include "spatial/core/point.hpp"
#include "spatial/objects/box.hpp"

namespace spatial_fuzz {

using point3 = spatial::point<double, 3>;
using box3 = spatial::objects::box<double, 3>;

struct named_structure {
    std::string_view name;
    // run_operations<C>: the input as operations on a C.
    sequence_summary (*run)(fuzz_input&, std::string_view, const sequence_limits&);
};

std::span<const named_structure> kd_tree_structures();   // run_kd_tree.cpp
std::span<const named_structure> octree_structures();    // run_octree.cpp
std::span<const named_structure> grid_structures();      // run_grids.cpp: uniform_grid, hashed_grid
std::span<const named_structure> bvh_point_structures(); // run_bvh_points.cpp: every volume type
std::span<const named_structure> bvh_box_structures();   // run_bvh_boxes.cpp: every volume type
std::span<const named_structure> collide_structures();   // run_collide.cpp: collision_grid, sweep_and_prune

// Every structure of this build, the families in the order above.
inline const std::vector<named_structure>& all_structures() {
    static const std::vector<named_structure> all = [] {
        std::vector<named_structure> v;
        for (auto family : {kd_tree_structures, octree_structures, grid_structures, bvh_point_structures,
                            bvh_box_structures, collide_structures})
            for (const auto& s : family()) v.push_back(s);
        return v;
    }();
    return all;
}

}  // namespace spatial_fuzz
