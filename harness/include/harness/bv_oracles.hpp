#pragma once
// CGAL as the oracle for the bounding-volume fits and overlap tests (issue 3). Everything
// here is implemented in harness/adapters/cgal/cgal_bv_oracles.cpp, the only translation
// unit that includes CGAL's geometry headers for this purpose, so tests and the `bv` suite
// link the answers without paying CGAL's compile time. The functions exist only when the
// project is configured with CGAL (SPATIAL_HAVE_CGAL=1, set by spatial_adapter_cgal);
// callers check cgal_bv_oracles_available() inside `#if SPATIAL_HAVE_CGAL` or skip.
//
// Points are plain double arrays: the oracles are independent of the library's types.
// `seconds` is the wall time of the CGAL call alone (input conversion excluded), for the
// same-run speed ratios in results/bv.csv.

#include <array>
#include <cstddef>
#include <span>
#include <vector>

namespace harness {

constexpr bool cgal_bv_oracles_available() {
#if defined(SPATIAL_HAVE_CGAL) && SPATIAL_HAVE_CGAL
    return true;
#else
    return false;
#endif
}

struct oracle_ball {
    std::vector<double> center;
    double radius = 0;
    double seconds = 0;
};
// Exact minimum enclosing ball: CGAL::Min_sphere_of_spheres_d (zero-radius spheres).
oracle_ball cgal_min_sphere(std::span<const std::array<double, 2>> pts);
oracle_ball cgal_min_sphere(std::span<const std::array<double, 3>> pts);

template <std::size_t D>
struct oracle_hull {
    std::vector<std::array<double, D>> vertices;  // the hull's vertices (any order)
    double volume = 0;                             // area in 2D
    std::size_t facets = 0;                        // edges in 2D, triangles in 3D
    double seconds = 0;
};
// Convex hull: CGAL::convex_hull_2 / convex_hull_3 (exact predicates, inexact constructions).
// Volume in 3D is computed exactly from the triangulated surface (or 0 for a degenerate hull).
oracle_hull<2> cgal_convex_hull(std::span<const std::array<double, 2>> pts);
oracle_hull<3> cgal_convex_hull(std::span<const std::array<double, 3>> pts);

struct oracle_obb {
    std::array<std::array<double, 3>, 8> corners{};
    double volume = 0;
    double seconds = 0;
};
// CGAL::oriented_bounding_box (Chang, Gorissen & Melchior 2011 optimiser), 3D only.
oracle_obb cgal_oriented_bounding_box(std::span<const std::array<double, 3>> pts);

struct oracle_ellipsoid {
    double volume = 0;  // area in 2D
    double seconds = 0;
    bool full_dimensional = true;  // CGAL reports false for a degenerate (flat) set
};
// CGAL::Approximate_min_ellipsoid_d with the given epsilon: its volume is at most
// (1 + eps) times the minimum-volume enclosing ellipsoid's.
oracle_ellipsoid cgal_min_ellipsoid(std::span<const std::array<double, 2>> pts, double eps);
oracle_ellipsoid cgal_min_ellipsoid(std::span<const std::array<double, 3>> pts, double eps);

// Exact test: do the convex hulls of the two vertex sets intersect (touching counts)?
// Exact predicates and constructions (CGAL::Epeck), so it is the reference for the
// false-positive rates of conservative polytope overlap tests.
bool cgal_convex_hulls_intersect(std::span<const std::array<double, 2>> a, std::span<const std::array<double, 2>> b);
bool cgal_convex_hulls_intersect(std::span<const std::array<double, 3>> a, std::span<const std::array<double, 3>> b);

}  // namespace harness
