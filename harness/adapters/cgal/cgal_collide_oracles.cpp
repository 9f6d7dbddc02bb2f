// CGAL::do_intersect on closed triangles with Epick (exact predicates): the oracle of
// tests/exact_intersection_test.cpp. CGAL's Triangle_3/Triangle_2 tests accept degenerate
// triangles only in some configurations, so callers pass non-degenerate ones.

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/intersections.h>

#include "harness/collide_oracles.hpp"

namespace harness {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;

bool cgal_triangles_intersect(const std::array<double, 9>& a, const std::array<double, 9>& b) {
    const K::Triangle_3 ta(K::Point_3(a[0], a[1], a[2]), K::Point_3(a[3], a[4], a[5]), K::Point_3(a[6], a[7], a[8]));
    const K::Triangle_3 tb(K::Point_3(b[0], b[1], b[2]), K::Point_3(b[3], b[4], b[5]), K::Point_3(b[6], b[7], b[8]));
    return CGAL::do_intersect(ta, tb);
}

bool cgal_triangles_intersect(const std::array<double, 6>& a, const std::array<double, 6>& b) {
    const K::Triangle_2 ta(K::Point_2(a[0], a[1]), K::Point_2(a[2], a[3]), K::Point_2(a[4], a[5]));
    const K::Triangle_2 tb(K::Point_2(b[0], b[1]), K::Point_2(b[2], b[3]), K::Point_2(b[4], b[5]));
    return CGAL::do_intersect(ta, tb);
}

}  // namespace harness
