#pragma once
// The names the command-line fuzz target gives harness::command_line: the runnable suites of
// harness/src/suite_table.cpp (their names and descriptions, copied: linking the suite table
// links every suite and peer, minutes of sanitizer build for names only) and the scene
// structures of the help text. harness_test checks the copy against the suite table
// (command_line_vocabulary.the_fuzz_targets_copy_names_every_runnable_suite).

#include "harness/command_line.hpp"

namespace spatial_fuzz {

inline const harness::command_line_vocabulary& command_line_vocabulary() {
    static const harness::command_line_vocabulary v{
        {{"knn", "k-nearest, radius and approximate kNN queries on point sets, static and dynamic"},
         {"structures", "the knn suite's static queries on every structure of the library, with the peers"},
         {"bv", "bounding-volume fits and tests: fit time, tightness, test time, false positives"},
         {"raycast", "first-hit ray casting on triangle meshes, boxes and points"},
         {"collide", "all intersecting pairs: static and moving boxes, triangles per BVH volume type"}},
        "bvh kd_tree octree uniform_grid hashed_grid collision_grid sweep_and_prune morton_array brute_force"};
    return v;
}

}  // namespace spatial_fuzz
