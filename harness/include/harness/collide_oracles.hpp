#pragma once
// CGAL as the oracle for the exact narrow-phase tests of the collision issue: CGAL's
// do_intersect on Epick triangles (exact predicates), implemented in
// harness/adapters/cgal/cgal_collide_oracles.cpp so that tests link the answers without
// compiling CGAL. Available when SPATIAL_HAVE_CGAL=1 (callers skip otherwise).
// Triangles are nine (3D) or six (2D) doubles: x0 y0 [z0] x1 y1 [z1] x2 y2 [z2].

#include <array>

namespace harness {

bool cgal_triangles_intersect(const std::array<double, 9>& a, const std::array<double, 9>& b);
bool cgal_triangles_intersect(const std::array<double, 6>& a, const std::array<double, 6>& b);

}  // namespace harness
