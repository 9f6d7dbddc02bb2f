#pragma once
// The `raycast` suite: ray casting against triangle meshes — ours (any spatial_container of
// spatial::objects::triangle<double, 3>, see our_ray_indexes.hpp) and the peers (Embree,
// CGAL AABB_tree; harness/ray_adapters.hpp) on generated meshes (UV sphere, random triangle
// soup) at several sizes and on the real meshes of scripts/fetch_meshes.sh, with incoherent
// rays (random origins on a bounding sphere towards random points in the box) and coherent
// rays (a pinhole camera). Per structure, workload and ray kind it records build time, time
// per ray (median of repetitions), nodes visited per ray (where reported), memory, hits, and
// the number of rays excused as ambiguous (near an edge, see ray_validation.hpp).
//
// Validation before any timing is kept: every structure's answers are checked against
// brute_force on a sample of rays of each kind and against the validated reference
// structure (exact-predicate CGAL, or ours) on EVERY ray; every timed repetition must
// reproduce the validated answers' checksum. A wrong answer throws validation_error and
// nothing is written.

#include <string>
#include <vector>

#include "harness/suite_options.hpp"

namespace harness {

void run_raycast_suite(const suite_options& options);
// The ids of the cases a run with these options would run, in order (suite_cases.hpp).
std::vector<std::string> raycast_case_ids(const suite_options& options);

}  // namespace harness
