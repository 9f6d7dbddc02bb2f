// The ready-made objects (box, sphere, triangle): ray tests including the watertightness of
// closed meshes, exact distances, triangle/box overlap against an independent clipping
// oracle, and split() against sampling.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <source_location>
#include <vector>

#include "spatial/brute/brute_force.hpp"
#include "spatial/core/object_concepts.hpp"
#include "spatial/core/object_geometry.hpp"
#include "spatial/objects/box.hpp"
#include "spatial/objects/sphere.hpp"
#include "spatial/objects/triangle.hpp"
#include "test_support.hpp"

using namespace spatial;
using objects::box;
using objects::sphere;
using objects::triangle;
using P3 = point<double, 3>;
using P2 = point<double, 2>;
using info3 = intersect_info<P3>;

static_assert(bounded_object<box<double, 3>> && bounded_object<box<float, 2>>);
static_assert(bounded_object<sphere<double, 3>> && bounded_object<sphere<float, 2>>);
static_assert(bounded_object<triangle<double, 3>> && bounded_object<triangle<float, 3>>);
static_assert(bounded_object<triangle<double, 2>> && bounded_object<triangle<float, 2>>);
static_assert(spatial_container<brute_force<triangle<double, 3>>>);

namespace {

P3 p3(double x, double y, double z) { return P3{{x, y, z}}; }
P2 p2(double x, double y) { return P2{{x, y}}; }

// The random geometry of the triangle and split tests: uniform draws in [-1, 1) from a
// seeded_rng (its seed logged as for the test's own line), points of three draws and triangles
// of three such points.
class uniform_draws {
public:
    explicit uniform_draws(std::uint64_t seed, std::source_location where = std::source_location::current())
        : rng_(seed, where) {}
    double operator()() { return u_(rng_); }
    P3 point() { return p3(u_(rng_), u_(rng_), u_(rng_)); }
    triangle<double, 3> triangle3() { return triangle<double, 3>(point(), point(), point()); }

private:
    spatial_test::seeded_rng rng_;
    std::uniform_real_distribution<double> u_{-1, 1};
};

template <class T>
bool any_hit(const std::vector<triangle<T, 3>>& mesh, const point<T, 3>& o, const point<T, 3>& d) {
    for (const auto& tri : mesh) {
        intersect_info<point<T, 3>> info;
        if (tri.intersect(o, d, T(0), info)) return true;
    }
    return false;
}

}  // namespace

// ---- triangle: watertightness ------------------------------------------------------------

template <class T> using watertight = spatial_test::plain_typed_suite<T>;
TYPED_TEST_SUITE(watertight, spatial_test::scalar_types);

TYPED_TEST(watertight, rays_from_inside_through_every_vertex_and_along_every_edge_hit_the_closed_mesh) {
    using T = TypeParam;
    using V = point<T, 3>;
    const auto mesh = spatial_test::icosphere<T>(2);
    spatial_test::seeded_rng rng(41);
    std::uniform_real_distribution<double> unit(0, 1);
    // Origins: the centre (rays exactly through vertices and edge points) and random inner points.
    std::vector<V> origins = {V{{0, 0, 0}}};
    for (int i = 0; i < 5; ++i) origins.push_back(V{{T(unit(rng) * 0.6 - 0.3), T(unit(rng) * 0.6 - 0.3), T(unit(rng) * 0.6 - 0.3)}});
    int rays = 0;
    for (const auto& o : origins)
        for (const auto& tri : mesh)
            for (int k = 0; k < 3; ++k) {
                const V& a = tri.vertex(k);
                const V& b = tri.vertex((k + 1) % 3);
                const T s = T(unit(rng));
                for (const V& target : {a, V{{a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]), a[2] + s * (b[2] - a[2])}}}) {
                    const V d{{target[0] - o[0], target[1] - o[1], target[2] - o[2]}};
                    ASSERT_TRUE(any_hit(mesh, o, d)) << "ray from " << o << " toward " << target << " slipped through";
                    ++rays;
                }
            }
    EXPECT_GT(rays, 5000);
}

TYPED_TEST(watertight, axis_rays_with_zero_and_negative_zero_components_hit_the_octahedron) {
    using T = TypeParam;
    using V = point<T, 3>;
    // The octahedron's vertices lie on the axes: every axis ray passes exactly through a vertex
    // shared by four triangles, and diagonal rays through shared edges.
    const V px{{1, 0, 0}}, nx{{-1, 0, 0}}, py{{0, 1, 0}}, ny{{0, -1, 0}}, pz{{0, 0, 1}}, nz{{0, 0, -1}};
    const std::vector<triangle<T, 3>> mesh = {{px, py, pz}, {py, nx, pz}, {nx, ny, pz}, {ny, px, pz},
                                              {py, px, nz}, {nx, py, nz}, {ny, nx, nz}, {px, ny, nz}};
    const T z = T(0), nzero = -T(0);
    for (T sgn : {T(1), T(-1)})
        for (int axis = 0; axis < 3; ++axis)
            for (T other : {z, nzero}) {
                V d{{other, other, other}};
                d[axis] = sgn;
                EXPECT_TRUE(any_hit(mesh, V{{0, 0, 0}}, d)) << "direction " << d;
                // From outside, aimed at the vertex on the far side.
                V o{{0, 0, 0}};
                o[axis] = -sgn * 5;
                EXPECT_TRUE(any_hit(mesh, o, d)) << "from " << o << " direction " << d;
                // Through the middle of an edge: direction (1,1,0)-like with a signed zero.
                V e{{other, other, other}};
                e[axis] = sgn;
                e[(axis + 1) % 3] = sgn;
                EXPECT_TRUE(any_hit(mesh, V{{0, 0, 0}}, e)) << "edge direction " << e;
            }
}

// ---- triangle: ray against an independent plane computation ------------------------------

TEST(triangle_ray, hit_time_matches_the_plane_and_barycentric_test_on_random_rays) {
    uniform_draws u(7);
    int hits = 0, misses = 0;
    for (int i = 0; i < 20000; ++i) {
        const triangle<double, 3> tri = u.triangle3();
        const P3 o = p3(3 * u(), 3 * u(), 3 * u());
        // Half the rays aim at a point near the triangle (barycentrics in [-0.2, 1.2]).
        P3 d = u.point();
        if (i % 2 == 0) {
            const double a = 0.7 * u() + 0.5, b = 0.7 * u() + 0.5;
            for (int k = 0; k < 3; ++k)
                d[k] = tri.vertex(0)[k] + a * (tri.vertex(1)[k] - tri.vertex(0)[k]) +
                       b * (tri.vertex(2)[k] - tri.vertex(0)[k]) - o[k];
        }
        // Oracle: Möller-Trumbore-style barycentrics by Cramer's rule in long double.
        using L = long double;
        const L e1[3] = {L(tri.vertex(1)[0]) - tri.vertex(0)[0], L(tri.vertex(1)[1]) - tri.vertex(0)[1], L(tri.vertex(1)[2]) - tri.vertex(0)[2]};
        const L e2[3] = {L(tri.vertex(2)[0]) - tri.vertex(0)[0], L(tri.vertex(2)[1]) - tri.vertex(0)[1], L(tri.vertex(2)[2]) - tri.vertex(0)[2]};
        const L s[3] = {L(o[0]) - tri.vertex(0)[0], L(o[1]) - tri.vertex(0)[1], L(o[2]) - tri.vertex(0)[2]};
        const L dd[3] = {d[0], d[1], d[2]};
        auto det3 = [](const L* a, const L* b, const L* c) {
            return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
        };
        const L nd[3] = {-dd[0], -dd[1], -dd[2]};
        const L det = det3(nd, e1, e2);
        if (std::abs(det) < 1e-6) continue;
        const L t = det3(s, e1, e2) / det, b1 = det3(nd, s, e2) / det, b2 = det3(nd, e1, s) / det;
        const L margin = 1e-9;
        const bool inside = b1 > margin && b2 > margin && b1 + b2 < 1 - margin && t > margin;
        const bool outside = b1 < -margin || b2 < -margin || b1 + b2 > 1 + margin || t < -margin;
        info3 info;
        const bool hit = tri.intersect(o, d, 0.0, info);
        if (inside) {
            ASSERT_TRUE(hit) << "i=" << i;
            EXPECT_NEAR(info.hit_time, static_cast<double>(t), 1e-9 * (1 + std::abs(static_cast<double>(t))));
            ++hits;
        } else if (outside) {
            ASSERT_FALSE(hit) << "i=" << i;
            ++misses;
        }
    }
    EXPECT_GT(hits, 1000);
    EXPECT_GT(misses, 1000);
}

TEST(triangle_ray, respects_hit_time_limit_and_origin_on_the_triangle_hits_at_zero) {
    const triangle<double, 3> tri(p3(0, 0, 0), p3(1, 0, 0), p3(0, 1, 0));
    info3 info;
    ASSERT_TRUE(tri.intersect(p3(0.2, 0.2, 1), p3(0, 0, -1), 0.0, info));
    EXPECT_EQ(info.hit_time, 1.0);
    EXPECT_EQ(info.hit_location, p3(0.2, 0.2, 0));
    info3 limited;
    limited.hit_time = 1.0;  // strictly before the limit only
    EXPECT_FALSE(tri.intersect(p3(0.2, 0.2, 1), p3(0, 0, -1), 0.0, limited));
    info3 on;
    ASSERT_TRUE(tri.intersect(p3(0.2, 0.2, 0), p3(0, 0, 1), 0.0, on));
    EXPECT_EQ(on.hit_time, 0.0);
    info3 behind;
    EXPECT_FALSE(tri.intersect(p3(0.2, 0.2, 1), p3(0, 0, 1), 0.0, behind));
}

TEST(triangle_ray, thick_ray_first_contact_is_at_distance_thickness) {
    const triangle<double, 3> tri(p3(0, 0, 0), p3(1, 0, 0), p3(0, 1, 0));
    // A ray parallel to the triangle's plane at height 0.5 passing over it: misses thin,
    // touches with thickness >= 0.5.
    info3 thin;
    EXPECT_FALSE(tri.intersect(p3(-2, 0.25, 0.5), p3(1, 0, 0), 0.0, thin));
    info3 thick;
    ASSERT_TRUE(tri.intersect(p3(-2, 0.25, 0.5), p3(1, 0, 0), 0.6, thick));
    // First contact: distance to the edge x = 0 region equals 0.6: (x^2 + 0.5^2) = 0.36 with x < 0.
    const double expected = 2 - std::sqrt(0.36 - 0.25);
    EXPECT_NEAR(thick.hit_time, expected, 1e-9);
    EXPECT_NEAR(std::sqrt(tri.squared_distance(thick.hit_location)), 0.6, 1e-9);
    info3 too_thin;
    EXPECT_FALSE(tri.intersect(p3(-2, 0.25, 0.5), p3(1, 0, 0), 0.49, too_thin));
}

// ---- triangle: distance, overlap, split ----------------------------------------------------

TEST(triangle_geometry, squared_distance_is_the_minimum_over_a_dense_sample_and_a_lower_bound_of_it) {
    uniform_draws u(11);
    for (int i = 0; i < 300; ++i) {
        const triangle<double, 3> tri = u.triangle3();
        const P3 q = p3(2 * u(), 2 * u(), 2 * u());
        double best = std::numeric_limits<double>::infinity();
        const int n = 120;
        for (int a = 0; a <= n; ++a)
            for (int b = 0; a + b <= n; ++b) {
                const double s = double(a) / n, t = double(b) / n;
                double d2 = 0;
                for (int k = 0; k < 3; ++k) {
                    const double x = tri.vertex(0)[k] + s * (tri.vertex(1)[k] - tri.vertex(0)[k]) +
                                     t * (tri.vertex(2)[k] - tri.vertex(0)[k]);
                    d2 += (x - q[k]) * (x - q[k]);
                }
                best = std::min(best, d2);
            }
        const double d = std::sqrt(tri.squared_distance(q));
        EXPECT_LE(d, std::sqrt(best) + 1e-12);
        EXPECT_GE(d, std::sqrt(best) - 0.05);  // grid spacing bound for triangles of size <= 2*sqrt(3)
    }
    // Degenerate triangle: the distance to its segment.
    const triangle<double, 3> seg(p3(0, 0, 0), p3(1, 0, 0), p3(2, 0, 0));
    EXPECT_TRUE(seg.is_degenerate());
    EXPECT_DOUBLE_EQ(seg.squared_distance(p3(1.5, 2, 0)), 4.0);
    EXPECT_DOUBLE_EQ(seg.squared_distance(p3(3, 0, 0)), 1.0);
}

namespace {
// Independent overlap oracle: clip the triangle polygon by the box's 2D planes
// (Sutherland-Hodgman); non-empty result <=> overlap.
template <std::size_t D>
bool clip_overlaps(const triangle<double, D>& tri, const point<double, D>& lo, const point<double, D>& hi) {
    std::vector<std::array<double, D>> poly;
    for (int k = 0; k < 3; ++k) {
        std::array<double, D> v;
        for (std::size_t i = 0; i < D; ++i) v[i] = tri.vertex(k)[i];
        poly.push_back(v);
    }
    for (std::size_t axis = 0; axis < D; ++axis)
        for (int side = 0; side < 2; ++side) {
            auto inside = [&](const std::array<double, D>& v) { return side == 0 ? v[axis] >= lo[axis] : v[axis] <= hi[axis]; };
            const double bound = side == 0 ? lo[axis] : hi[axis];
            std::vector<std::array<double, D>> out;
            for (std::size_t k = 0; k < poly.size(); ++k) {
                const auto& a = poly[k];
                const auto& b = poly[(k + 1) % poly.size()];
                if (inside(a)) out.push_back(a);
                if (inside(a) != inside(b)) {
                    const double s = (bound - a[axis]) / (b[axis] - a[axis]);
                    std::array<double, D> c;
                    for (std::size_t i = 0; i < D; ++i) c[i] = a[i] + s * (b[i] - a[i]);
                    c[axis] = bound;
                    out.push_back(c);
                }
            }
            poly = out;
            if (poly.empty()) return false;
        }
    return true;
}
}  // namespace

TEST(triangle_geometry, box_overlap_agrees_with_polygon_clipping_in_2d_and_3d) {
    uniform_draws u(13);
    int yes = 0, no = 0;
    for (int i = 0; i < 20000; ++i) {
        const triangle<double, 3> t3 = u.triangle3();
        const P3 c = u.point();
        const double h = 0.05 + 0.3 * (u() + 1);
        const P3 lo = p3(c[0] - h, c[1] - h * 0.7, c[2] - h * 0.4), hi = p3(c[0] + h, c[1] + h * 0.7, c[2] + h * 0.4);
        const bool expect3 = clip_overlaps(t3, lo, hi);
        ASSERT_EQ(t3.overlaps_box(lo, hi), expect3) << "3D case " << i;
        (expect3 ? yes : no)++;
        const triangle<double, 2> t2(p2(u(), u()), p2(u(), u()), p2(u(), u()));
        const P2 lo2 = p2(lo[0], lo[1]), hi2 = p2(hi[0], hi[1]);
        ASSERT_EQ(t2.overlaps_box(lo2, hi2), clip_overlaps(t2, lo2, hi2)) << "2D case " << i;
    }
    EXPECT_GT(yes, 2000);
    EXPECT_GT(no, 2000);
}

TEST(triangle_geometry, split_boxes_contain_every_sampled_point_of_their_side) {
    uniform_draws u(17);
    for (int i = 0; i < 500; ++i) {
        const triangle<double, 3> tri = u.triangle3();
        double normal[3] = {u(), u(), u()};
        if (i % 3 == 0) normal[0] = normal[1] = 0, normal[2] = i % 2 ? 1 : -1;  // axis-aligned planes too
        const double offset = 0.5 * u();
        box<double, 3> left, right;
        tri.split(normal, offset, left, right);
        const int n = 40;
        for (int a = 0; a <= n; ++a)
            for (int b = 0; a + b <= n; ++b) {
                P3 x;
                for (int k = 0; k < 3; ++k)
                    x[k] = tri.vertex(0)[k] + double(a) / n * (tri.vertex(1)[k] - tri.vertex(0)[k]) +
                           double(b) / n * (tri.vertex(2)[k] - tri.vertex(0)[k]);
                const double s = normal[0] * x[0] + normal[1] * x[1] + normal[2] * x[2] - offset;
                if (s <= 0) {
                    ASSERT_LE(left.squared_distance(x), 1e-28) << "case " << i;
                }
                if (s >= 0) {
                    ASSERT_LE(right.squared_distance(x), 1e-28) << "case " << i;
                }
            }
    }
    // Entirely on one side: the other part is empty.
    const triangle<double, 3> tri(p3(0, 0, 0), p3(1, 0, 0), p3(0, 1, 0));
    const double nx[3] = {1, 0, 0};
    box<double, 3> l, r;
    tri.split(nx, 5.0, l, r);
    EXPECT_FALSE(l.is_empty());
    EXPECT_TRUE(r.is_empty());
}

TEST(triangle_2d, rays_enter_the_filled_triangle_and_origins_inside_hit_at_zero) {
    const triangle<double, 2> tri(p2(0, 0), p2(2, 0), p2(0, 2));
    intersect_info<P2> info;
    ASSERT_TRUE(tri.intersect(p2(-1, 0.5), p2(1, 0), 0.0, info));
    EXPECT_EQ(info.hit_time, 1.0);
    intersect_info<P2> inside;
    ASSERT_TRUE(tri.intersect(p2(0.5, 0.5), p2(1, -0.0), 0.0, inside));
    EXPECT_EQ(inside.hit_time, 0.0);
    intersect_info<P2> miss;
    EXPECT_FALSE(tri.intersect(p2(-1, 3), p2(1, 0), 0.0, miss));
    // Clockwise winding gives the same answers.
    const triangle<double, 2> cw(p2(0, 0), p2(0, 2), p2(2, 0));
    intersect_info<P2> info_cw;
    ASSERT_TRUE(cw.intersect(p2(-1, 0.5), p2(1, 0), 0.0, info_cw));
    EXPECT_EQ(info_cw.hit_time, 1.0);
    // Degenerate (a segment): hit where the ray crosses it.
    const triangle<double, 2> seg(p2(0, 0), p2(1, 1), p2(2, 2));
    intersect_info<P2> info_seg;
    ASSERT_TRUE(seg.intersect(p2(1, -1), p2(0, 1), 0.0, info_seg));
    EXPECT_EQ(info_seg.hit_time, 2.0);
    EXPECT_EQ(seg.squared_distance(p2(2, 0)), 2.0);
}

// ---- sphere ----------------------------------------------------------------------------------

TEST(sphere_object, ray_hits_match_the_quadratic_and_inside_origins_hit_at_zero) {
    const sphere<double, 3> s(p3(1, 2, 3), 0.5);
    info3 info;
    ASSERT_TRUE(s.intersect(p3(1, 2, -1), p3(0, 0, 1), 0.0, info));
    EXPECT_DOUBLE_EQ(info.hit_time, 3.5);
    info3 inside;
    ASSERT_TRUE(s.intersect(p3(1, 2, 3.2), p3(0, -0.0, 1), 0.0, inside));
    EXPECT_EQ(inside.hit_time, 0.0);
    info3 behind;
    EXPECT_FALSE(s.intersect(p3(1, 2, 4), p3(0, 0, 1), 0.0, behind));
    info3 miss, thick;
    EXPECT_FALSE(s.intersect(p3(1.7, 2, -1), p3(0, 0, 1), 0.0, miss));
    ASSERT_TRUE(s.intersect(p3(1.7, 2, -1), p3(0, 0, 1), 0.25, thick));  // radius 0.75 now
    EXPECT_NEAR(thick.hit_time, 4 - std::sqrt(0.75 * 0.75 - 0.7 * 0.7), 1e-12);
    EXPECT_THROW((sphere<double, 3>(p3(0, 0, 0), -1)), std::invalid_argument);
}

TEST(sphere_object, a_tiny_sphere_far_from_the_origin_is_still_hit_stable_form) {
    // b^2 - ac would cancel completely here; the closest-approach form does not.
    const sphere<float, 3> s(point<float, 3>{{1e4f, 1e4f, 1e4f}}, 1e-2f);
    intersect_info<point<float, 3>> info;
    ASSERT_TRUE(s.intersect(point<float, 3>{{0, 0, 0}}, point<float, 3>{{1, 1, 1}}, 0.0f, info));
    EXPECT_NEAR(info.hit_time, 1e4f, 1e-1f);
}

TEST(sphere_object, bounds_contain_the_ball_and_split_caps_contain_sampled_points) {
    uniform_draws u(19);
    for (int i = 0; i < 300; ++i) {
        const sphere<double, 3> s(p3(u() * 1e3, u(), u()), 0.1 + (u() + 1) / 2);
        const int axis = i % 3;
        double normal[3] = {0, 0, 0};
        normal[axis] = i % 2 ? 2.0 : -0.5;
        const double offset = normal[axis] * (s.center()[axis] + 0.8 * s.radius() * u());
        box<double, 3> left, right;
        s.split(normal, offset, left, right);
        for (int k = 0; k < 2000; ++k) {
            P3 dir = u.point();
            const double n = std::sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
            const double r = s.radius() * std::cbrt((u() + 1) / 2);
            P3 x;
            for (int j = 0; j < 3; ++j) x[j] = s.center()[j] + dir[j] / n * r;
            if (k % 10 == 0) x = [&] { P3 y = x; for (int j = 0; j < 3; ++j) y[j] = s.center()[j] + dir[j] / n * s.radius(); return y; }();
            ASSERT_EQ(object_box_squared_distance(s, x), 0.0);
            const double side = normal[0] * x[0] + normal[1] * x[1] + normal[2] * x[2] - offset;
            if (side <= 0) {
                ASSERT_EQ(left.squared_distance(x), 0.0) << "case " << i;
            }
            if (side >= 0) {
                ASSERT_EQ(right.squared_distance(x), 0.0) << "case " << i;
            }
        }
    }
}

// ---- box ---------------------------------------------------------------------------------------

TEST(box_object, slab_test_handles_zero_and_negative_zero_directions_and_faces) {
    const box<double, 3> b(p3(0, 0, 0), p3(1, 1, 1));
    for (double z : {0.0, -0.0}) {
        info3 on_face;  // grazing the face y = 1 along x
        ASSERT_TRUE(b.intersect(p3(-1, 1, 0.5), p3(1, z, z), 0.0, on_face));
        EXPECT_EQ(on_face.hit_time, 1.0);
        info3 outside;
        EXPECT_FALSE(b.intersect(p3(-1, 1.0000001, 0.5), p3(1, z, z), 0.0, outside));
        info3 neg;
        ASSERT_TRUE(b.intersect(p3(0.5, 0.5, 3), p3(z, z, -1), 0.0, neg));
        EXPECT_EQ(neg.hit_time, 2.0);
    }
    info3 inside;
    ASSERT_TRUE(b.intersect(p3(0.5, 0.5, 0.5), p3(1, 1, 1), 0.0, inside));
    EXPECT_EQ(inside.hit_time, 0.0);
    info3 thick;
    ASSERT_TRUE(b.intersect(p3(-1, 1.2, 0.5), p3(1, 0, 0), 0.3, thick));
    EXPECT_NEAR(thick.hit_time, 1 - std::sqrt(0.09 - 0.04), 1e-9);
}

TEST(box_object, split_is_exact_for_axis_planes_and_marks_empty_parts) {
    const box<double, 3> b(p3(0, 0, 0), p3(2, 2, 2));
    const double n[3] = {0, -1, 0};
    box<double, 3> l, r;
    b.split(n, -0.5, l, r);  // -y <= -0.5  <=>  y >= 0.5 goes left
    EXPECT_EQ(l.lo[1], 0.5);
    EXPECT_EQ(l.hi[1], 2.0);
    EXPECT_EQ(r.lo[1], 0.0);
    EXPECT_EQ(r.hi[1], 0.5);
    b.split(n, 1.0, l, r);  // y >= -1: everything left
    EXPECT_EQ(l, b);
    EXPECT_TRUE(r.is_empty());
}

// ---- the oracle stores objects --------------------------------------------------------------

TEST(brute_force_objects, rejects_non_finite_objects_and_keeps_its_contents) {
    brute_force<sphere<double, 3>> c;
    c.insert(sphere<double, 3>(p3(0, 0, 0), 1));
    std::vector<sphere<double, 3>> batch = {sphere<double, 3>(p3(5, 0, 0), 1),
                                            sphere<double, 3>(p3(std::nan(""), 0, 0), 1)};
    EXPECT_THROW(c.insert(batch.begin(), batch.end()), std::invalid_argument);
    EXPECT_EQ(c.size(), 1u);
    // Ranges see the whole object: the ball of radius 1 at the origin reaches x = 0.9.
    EXPECT_EQ(c.find_in_box(p3(0.9, -0.1, -0.1), p3(3, 0.1, 0.1)).size(), 1u);
    EXPECT_EQ(c.find_in_ball(p3(1.5, 0, 0), 0.5).size(), 1u);
    EXPECT_EQ(c.find_in_ball(p3(1.5, 0, 0), 0.49).size(), 0u);
}

// A NaN in any vertex of a triangle, or in either corner of a box, makes the bounds on that
// axis NaN, so containers (which check an object's bounds) reject it. std::min and std::max
// skip a NaN that is not their first argument: a NaN in a triangle's second or third vertex,
// or in a box's second corner, used to leave finite bounds, and containers stored a triangle
// whose distances and ray tests were NaN.
TEST(object_bounds, a_nan_in_any_vertex_or_corner_makes_the_bounds_nan_and_containers_reject_it) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (std::size_t k = 0; k < 3; ++k)
        for (std::size_t axis = 0; axis < 3; ++axis) {
            std::array<P3, 3> v{p3(0, 0, 0), p3(1, 0, 0), p3(0, 1, 0)};
            v[k][axis] = nan;
            const triangle<double, 3> t(v[0], v[1], v[2]);
            EXPECT_TRUE(std::isnan(t.get_min_bound()[axis]) && std::isnan(t.get_max_bound()[axis]))
                << "vertex " << k << ", axis " << axis;
            EXPECT_FALSE(detail::is_finite_object(t)) << "vertex " << k << ", axis " << axis;
            brute_force<triangle<double, 3>> c;
            c.insert(triangle<double, 3>(p3(0, 0, 0), p3(1, 0, 0), p3(0, 1, 0)));
            EXPECT_THROW(c.insert(t), std::invalid_argument) << "vertex " << k << ", axis " << axis;
            EXPECT_EQ(c.size(), 1u);
        }
    for (std::size_t corner = 0; corner < 2; ++corner)
        for (std::size_t axis = 0; axis < 3; ++axis) {
            std::array<P3, 2> c{p3(0, 0, 0), p3(1, 1, 1)};
            c[corner][axis] = nan;
            const box<double, 3> b(c[0], c[1]);
            EXPECT_TRUE(std::isnan(b.lo[axis]) && std::isnan(b.hi[axis])) << "corner " << corner << ", axis " << axis;
            EXPECT_FALSE(detail::is_finite_object(b)) << "corner " << corner << ", axis " << axis;
        }
}

#include <cstring>  // std::memcmp: bit-level comparison of hit times

// triangle::prepared_ray (the per-ray part of the watertight test, computed once for many
// triangles, as spatial::bvh does) must give bit-identical answers to the plain call: the
// same hit/miss, hit_time and hit_location, for thin and thick rays, with directions that
// have +0 / -0 components (axis-parallel rays, rays in a coordinate plane), rays through
// shared vertices and edges, and one prepared ray reused across many triangles.
template <class T>
static void check_prepared_ray_matches_plain(std::uint64_t seed) {
    using P = point<T, 3>;
    using tri = triangle<T, 3>;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<T> u(T(-1), T(1));
    std::uniform_int_distribution<int> pick(0, 5);
    // A small grid of vertices (integers/4) so that many rays pass exactly through
    // vertices and edges, plus random ones.
    auto grid_point = [&] {
        P p;
        for (std::size_t i = 0; i < 3; ++i) p[i] = static_cast<T>(std::uniform_int_distribution<int>(-4, 4)(rng)) / 4;
        return p;
    };
    auto random_point = [&] { return P{{u(rng), u(rng), u(rng)}}; };
    std::vector<tri> tris;
    for (int k = 0; k < 60; ++k)
        tris.emplace_back(k % 2 ? grid_point() : random_point(), grid_point(), k % 3 ? random_point() : grid_point());
    std::size_t hits = 0, zero_components = 0;
    for (int r = 0; r < 1500; ++r) {
        P o = r % 4 == 0 ? grid_point() : random_point();
        for (std::size_t i = 0; i < 3; ++i) o[i] *= 3;
        P d = random_point();
        const int mode = pick(rng);  // zero out components, with either sign
        if (mode >= 1) {
            const std::size_t i = static_cast<std::size_t>(mode - 1) % 3;
            d[i] = mode % 2 ? T(0) : -T(0);
            if (mode >= 4) d[(i + 1) % 3] = mode % 2 ? -T(0) : T(0);
        }
        if (d[0] == 0 && d[1] == 0 && d[2] == 0) d[2] = 1;
        if (r % 7 == 0) {  // aim at a vertex or an edge midpoint of some triangle
            const tri& t = tris[static_cast<std::size_t>(r) % tris.size()];
            for (std::size_t i = 0; i < 3; ++i) d[i] = (t.vertex(0)[i] + t.vertex(r % 2 ? 0 : 1)[i]) / 2 - o[i];
            if (d[0] == 0 && d[1] == 0 && d[2] == 0) d[0] = 1;
        }
        for (std::size_t i = 0; i < 3; ++i) zero_components += d[i] == 0;
        const T thickness = r % 5 == 0 ? T(0.05) : T(0);
        const typename tri::prepared_ray prepared(o, d);
        ASSERT_EQ(prepared.origin(), o);
        ASSERT_EQ(prepared.direction(), d);
        intersect_info<P> plain_best, prepared_best;
        for (const tri& t : tris) {
            intersect_info<P> a, b;
            const bool ha = t.intersect(o, d, thickness, a);
            const bool hb = t.intersect(prepared, thickness, b);
            ASSERT_EQ(ha, hb) << "ray " << r;
            // Bit-identical (== would accept -0 for +0): compare the representations.
            ASSERT_EQ(std::memcmp(&a.hit_time, &b.hit_time, sizeof(T)), 0) << "ray " << r;
            for (std::size_t i = 0; i < 3; ++i)
                ASSERT_EQ(std::memcmp(&a.hit_location[i], &b.hit_location[i], sizeof(T)), 0) << "ray " << r;
            hits += ha;
            // Running "first hit" accumulation, as a container does.
            t.intersect(o, d, thickness, plain_best);
            t.intersect(prepared, thickness, prepared_best);
            ASSERT_EQ(std::memcmp(&plain_best.hit_time, &prepared_best.hit_time, sizeof(T)), 0) << "ray " << r;
        }
    }
    EXPECT_GT(hits, 1000u);            // the test exercises hits, not only misses
    EXPECT_GT(zero_components, 500u);  // and directions with zero components
}

TEST(TrianglePreparedRay, BitIdenticalToPlainIntersectDouble) {
    const spatial_test::logged_seed seed(2013);
    check_prepared_ray_matches_plain<double>(seed);
}

TEST(TrianglePreparedRay, BitIdenticalToPlainIntersectFloat) {
    const spatial_test::logged_seed seed(2014);
    check_prepared_ray_matches_plain<float>(seed);
}
