#pragma once
// The `collide` suite: collision pairs on every structure and peer (CGAL box_intersection_d,
// FCL's broad-phase managers, Embree rtcCollide), static and moving, and the BVH of every
// bounding-volume type on triangles (candidate pairs against time). Every pair set is
// validated before its timing is recorded. Writes results/collide.csv (columns:
// results/README.md). Workloads and presets: harness/src/collide_suite.cpp.

#include <string>
#include <vector>

#include "harness/suite_options.hpp"

namespace harness {

void run_collide_suite(const suite_options& options);
// The ids of the cases a run with these options would run, in order (suite_cases.hpp).
std::vector<std::string> collide_case_ids(const suite_options& options);

}  // namespace harness
