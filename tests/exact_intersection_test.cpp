// spatial::collide exact intersection tests (collide/exact_intersection.hpp): closed
// segments and triangles, 2D and 3D, decided by exact orientation signs.
//  * hand-built hard cases: touching at a vertex, along an edge, a vertex on a face, coplanar
//    overlap / touch / containment / disjoint, a 1-ulp gap, degenerate (zero-area) triangles;
//  * symmetry (argument order, vertex order) on every case;
//  * differential against CGAL's do_intersect with Epick (exact predicates) on random
//    triangles with coordinates on a small integer grid (coplanar, touching and degenerate
//    configurations are then common) and on random doubles — with logged seeds.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <random>

#include "spatial/collide/exact_intersection.hpp"
#include "test_support.hpp"

#if defined(SPATIAL_HAVE_CGAL) && SPATIAL_HAVE_CGAL
#include "harness/collide_oracles.hpp"
#endif

using spatial::collide::triangles_intersect;
using spatial::collide::vec2;
using spatial::collide::vec3;

namespace {

struct tri3 {
    vec3 p, q, r;
};

// Every argument order and vertex rotation / reflection gives the same answer.
bool intersect_all_orders(const tri3& a, const tri3& b) {
    const bool base = triangles_intersect(a.p, a.q, a.r, b.p, b.q, b.r);
    const std::array<tri3, 3> as{a, tri3{a.q, a.r, a.p}, tri3{a.r, a.q, a.p}};
    const std::array<tri3, 3> bs{b, tri3{b.r, b.p, b.q}, tri3{b.q, b.p, b.r}};
    for (const auto& x : as)
        for (const auto& y : bs) {
            EXPECT_EQ(triangles_intersect(x.p, x.q, x.r, y.p, y.q, y.r), base);
            EXPECT_EQ(triangles_intersect(y.p, y.q, y.r, x.p, x.q, x.r), base);
        }
    return base;
}

const tri3 unit{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};

TEST(exact_intersection, touching_and_piercing_triangles_in_3d) {
    // Piercing: a vertical triangle through the unit triangle's interior.
    EXPECT_TRUE(intersect_all_orders(unit, {{0.2, 0.2, -1}, {0.3, 0.2, 1}, {0.2, 0.3, 1}}));
    // A vertex exactly on the face, the rest above.
    EXPECT_TRUE(intersect_all_orders(unit, {{0.25, 0.25, 0}, {1, 1, 1}, {0, 1, 1}}));
    // Lifted by one ulp: disjoint.
    const double up = std::nextafter(0.0, 1.0);
    EXPECT_FALSE(intersect_all_orders(unit, {{0.25, 0.25, up}, {1, 1, 1}, {0, 1, 1}}));
    // Edge on edge, the triangles in different planes (a hinge).
    EXPECT_TRUE(intersect_all_orders(unit, {{0, 0, 0}, {1, 0, 0}, {0.5, 0, 1}}));
    // Sharing only a vertex.
    EXPECT_TRUE(intersect_all_orders(unit, {{1, 0, 0}, {2, 0, 1}, {2, 1, 0}}));
    // A vertex on the hypotenuse x + y = 1 from above, and one ulp outside it.
    EXPECT_TRUE(intersect_all_orders(unit, {{0.5, 0.5, 0}, {0.5, 0.5, 1}, {1, 1, 1}}));
    EXPECT_FALSE(intersect_all_orders(unit, {{0.5, std::nextafter(0.5, 1.0), 0}, {0.5, 0.5, 1}, {1, 1, 1}}));
    // Crossing edges (an X seen from above) in different planes through the edge lines.
    EXPECT_TRUE(intersect_all_orders(unit, {{0.5, -1, 0}, {0.5, 1, 0}, {0.5, 0, 3}}));
    // Parallel planes: disjoint.
    EXPECT_FALSE(intersect_all_orders(unit, {{0, 0, 1}, {1, 0, 1}, {0, 1, 1}}));
}

TEST(exact_intersection, coplanar_triangles_in_3d) {
    // Overlapping, in a tilted plane z = x + 2y (exact on these coordinates).
    auto lift = [](double x, double y) { return vec3{x, y, x + 2 * y}; };
    const tri3 a{lift(0, 0), lift(4, 0), lift(0, 4)};
    EXPECT_TRUE(intersect_all_orders(a, {lift(1, 1), lift(5, 1), lift(1, 5)}));    // overlap
    EXPECT_TRUE(intersect_all_orders(a, {lift(1, 1), lift(2, 1), lift(1, 2)}));    // inside
    EXPECT_TRUE(intersect_all_orders(a, {lift(4, 0), lift(6, 0), lift(5, 2)}));    // touch at a vertex
    EXPECT_TRUE(intersect_all_orders(a, {lift(2, 2), lift(4, 4), lift(5, 1)}));    // vertex on the hypotenuse
    EXPECT_FALSE(intersect_all_orders(a, {lift(3, 3), lift(6, 3), lift(3, 6)}));   // beyond the hypotenuse
    EXPECT_TRUE(intersect_all_orders(a, {lift(0, 0), lift(4, 0), lift(2, -2)}));   // shared edge, other side
    // In a vertical plane (x = 1): the plane's projection along x is degenerate, the others not.
    const tri3 v{{1, 0, 0}, {1, 2, 0}, {1, 0, 2}};
    EXPECT_TRUE(intersect_all_orders(v, {{1, 1, 1}, {1, 3, 1}, {1, 1, 3}}));
    EXPECT_FALSE(intersect_all_orders(v, {{1, 1.5, 1.5}, {1, 3, 1}, {1, 1, 3}}));
}

TEST(exact_intersection, degenerate_triangles_are_their_segments_or_points) {
    const tri3 segment{{0.2, 0.2, -1}, {0.2, 0.2, 1}, {0.2, 0.2, 0.5}};  // collinear: a vertical segment
    EXPECT_TRUE(intersect_all_orders(unit, segment));
    const tri3 above{{0.2, 0.2, 0.1}, {0.2, 0.2, 1}, {0.2, 0.2, 0.5}};
    EXPECT_FALSE(intersect_all_orders(unit, above));
    const tri3 point_on_edge{{0.5, 0, 0}, {0.5, 0, 0}, {0.5, 0, 0}};
    EXPECT_TRUE(intersect_all_orders(unit, point_on_edge));
    const tri3 point_off{{0.5, -1e-300, 0}, {0.5, -1e-300, 0}, {0.5, -1e-300, 0}};
    EXPECT_FALSE(intersect_all_orders(unit, point_off));
    // Two degenerate triangles: crossing segments in a plane, skew segments.
    const tri3 s1{{0, 0, 0}, {2, 2, 2}, {1, 1, 1}}, s2{{0, 2, 0}, {2, 0, 2}, {1, 1, 1}}, s3{{0, 2, 0.5}, {2, 0, 0.5}, {1, 1, 0.5}};
    EXPECT_TRUE(intersect_all_orders(s1, s2));
    EXPECT_FALSE(intersect_all_orders(s1, s3));
    // Collinear overlapping and disjoint segments along an axis.
    const tri3 x1{{0, 0, 0}, {2, 0, 0}, {1, 0, 0}}, x2{{1.5, 0, 0}, {3, 0, 0}, {2, 0, 0}}, x3{{2.5, 0, 0}, {3, 0, 0}, {2.75, 0, 0}};
    EXPECT_TRUE(intersect_all_orders(x1, x2));
    EXPECT_FALSE(intersect_all_orders(x1, x3));
}

TEST(exact_intersection, triangles_in_2d) {
    const vec2 a{0, 0}, b{4, 0}, c{0, 4};
    EXPECT_TRUE(triangles_intersect(a, b, c, vec2{1, 1}, vec2{2, 1}, vec2{1, 2}));    // contained
    EXPECT_TRUE(triangles_intersect(vec2{1, 1}, vec2{2, 1}, vec2{1, 2}, a, b, c));    // container second
    EXPECT_TRUE(triangles_intersect(a, b, c, vec2{2, 2}, vec2{4, 4}, vec2{5, 1}));    // vertex on an edge
    EXPECT_FALSE(triangles_intersect(a, b, c, vec2{2, std::nextafter(2.0, 3.0)}, vec2{4, 4}, vec2{5, 1}));
    EXPECT_TRUE(triangles_intersect(a, b, c, vec2{-1, 2}, vec2{5, 2}, vec2{2, 5}));   // crossing edges
    EXPECT_FALSE(triangles_intersect(a, b, c, vec2{5, 5}, vec2{6, 5}, vec2{5, 6}));
    // Degenerate: a segment crossing, a point inside.
    EXPECT_TRUE(triangles_intersect(a, b, c, vec2{-1, 1}, vec2{5, 1}, vec2{2, 1}));
    EXPECT_TRUE(triangles_intersect(a, b, c, vec2{1, 1}, vec2{1, 1}, vec2{1, 1}));
    EXPECT_FALSE(triangles_intersect(a, b, c, vec2{3, 3}, vec2{3, 3}, vec2{3, 3}));
}

#if defined(SPATIAL_HAVE_CGAL) && SPATIAL_HAVE_CGAL

bool degenerate(const tri3& t) {
    return spatial::predicates::collinear_3d(t.p.data(), t.q.data(), t.r.data());
}

// Random triangles against CGAL (exact predicates). Grid coordinates in [0, 4] make
// coplanar, touching and edge-on-edge configurations common.
TEST(exact_intersection, random_triangles_agree_with_cgal) {
    const std::uint64_t seed = spatial_test::test_seed(91);
    SCOPED_TRACE(spatial_test::replay_hint(seed));
    std::mt19937_64 rng(seed);
    std::uniform_int_distribution<int> grid(0, 4);
    std::uniform_real_distribution<double> u(0, 1);
    std::size_t hits = 0, coplanar = 0, checked = 0;
    for (int k = 0; k < 20000; ++k) {
        const bool on_grid = k % 2 == 0;
        auto coord = [&] { return on_grid ? static_cast<double>(grid(rng)) : u(rng); };
        auto point = [&] { return vec3{coord(), coord(), k % 8 == 0 ? 0.0 : coord()}; };  // some all in z = 0
        tri3 a{point(), point(), point()}, b{point(), point(), point()};
        if (degenerate(a) || degenerate(b)) continue;
        const bool ours = triangles_intersect(a.p, a.q, a.r, b.p, b.q, b.r);
        const std::array<double, 9> ca{a.p[0], a.p[1], a.p[2], a.q[0], a.q[1], a.q[2], a.r[0], a.r[1], a.r[2]};
        const std::array<double, 9> cb{b.p[0], b.p[1], b.p[2], b.q[0], b.q[1], b.q[2], b.r[0], b.r[1], b.r[2]};
        const bool cgal = harness::cgal_triangles_intersect(ca, cb);
        ASSERT_EQ(ours, cgal) << "case " << k;
        hits += ours;
        coplanar += k % 8 == 0;
        ++checked;
    }
    EXPECT_GT(checked, 15000u);
    EXPECT_GT(hits, 2000u);
    EXPECT_GT(coplanar, 1500u);
}

TEST(exact_intersection, random_2d_triangles_agree_with_cgal) {
    const std::uint64_t seed = spatial_test::test_seed(92);
    SCOPED_TRACE(spatial_test::replay_hint(seed));
    std::mt19937_64 rng(seed);
    std::uniform_int_distribution<int> grid(0, 5);
    std::size_t hits = 0;
    for (int k = 0; k < 20000; ++k) {
        auto p = [&] { return vec2{static_cast<double>(grid(rng)), static_cast<double>(grid(rng))}; };
        const vec2 a0 = p(), a1 = p(), a2 = p(), b0 = p(), b1 = p(), b2 = p();
        if (spatial::predicates::orient_2d(a0.data(), a1.data(), a2.data()) == 0 ||
            spatial::predicates::orient_2d(b0.data(), b1.data(), b2.data()) == 0)
            continue;
        const bool ours = triangles_intersect(a0, a1, a2, b0, b1, b2);
        const bool cgal = harness::cgal_triangles_intersect(std::array<double, 6>{a0[0], a0[1], a1[0], a1[1], a2[0], a2[1]},
                                                            std::array<double, 6>{b0[0], b0[1], b1[0], b1[1], b2[0], b2[1]});
        ASSERT_EQ(ours, cgal) << "case " << k;
        hits += ours;
    }
    EXPECT_GT(hits, 3000u);
}

#endif

}  // namespace
