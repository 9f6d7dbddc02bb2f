#pragma once
// The `bv` suite: the bounding volumes' accuracy-versus-time study (issue 3). For every
// volume type x fitting method x shape (generated shapes from datasets/shapes.hpp and the
// vertices of real meshes) it records
//   fit      fit time, volume, tightness (volume over the convex hull's volume), on n points;
//   overlap  time per overlap test, and its false-positive rates against the exact
//            intersection of the two volumes and against the exact intersection of the two
//            enclosed point sets' hulls, over all pairs of randomly placed instances;
//   ray      time per ray-interval test, and how often a line that hits the volume misses
//            the enclosed set's hull.
// CGAL's fits (Min_sphere_of_spheres_d, convex_hull_3, oriented_bounding_box,
// Approximate_min_ellipsoid_d) run on the same points in the same run, for the ratios.
//
// Validation before any figure is kept: every fit contains every input point; the exact
// fits agree with CGAL's (ball radius, hull volume and vertex count); no overlap test
// misses an intersection that the exact reference (CGAL's exact LP for polytopes, long
// double closed forms for balls and ellipsoids) finds; ray intervals are consistent with
// contains(). A failure throws validation_error and nothing is written.

#include <string>
#include <vector>

#include "harness/suite_options.hpp"

namespace harness {

void run_bv_suite(const suite_options& options);
// The ids of the cases a run with these options would run, in order (suite_cases.hpp).
std::vector<std::string> bv_case_ids(const suite_options& options);

}  // namespace harness
