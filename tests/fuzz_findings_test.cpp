// Regression tests for what the operations fuzzer found in the structures (fuzz/operations,
// docs/fuzzing.md). Each test is one finding, minimised by libFuzzer and written out from the
// fuzzer's trace (SPATIAL_FUZZ_TRACE=1), run on every structure over points and over boxes
// (a point stands for the box of zero size at it) and compared with brute_force.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "spatial/brute/brute_force.hpp"
#include "spatial/bv/convex_hull.hpp"
#include "spatial/bv/ellipsoid.hpp"
#include "spatial/bv/kdop.hpp"
#include "spatial/bv/obb.hpp"
#include "spatial/bv/sphere.hpp"
#include "spatial/bvh/bvh.hpp"
#include "spatial/collide/collision_grid.hpp"
#include "spatial/grid/hashed_grid.hpp"
#include "spatial/grid/uniform_grid.hpp"
#include "spatial/kdtree/kd_tree.hpp"
#include "spatial/octree/octree.hpp"
#include "test_support.hpp"

namespace {

using namespace spatial;
using spatial_test::B3;
using spatial_test::P3;

constexpr double denormal = std::numeric_limits<double>::denorm_min();

// Every structure, over points and over boxes; all volume types of the bvh.
template <class O>
using structures_of = ::testing::Types<kd_tree<O>, octree<O>, uniform_grid<O>, hashed_grid<O>, bvh<O>,
                                       bvh<O, sphere<double, 3>>, bvh<O, obb<double, 3>>, bvh<O, kdop<double, 3, 26>>,
                                       bvh<O, ellipsoid<double, 3>>, bvh<O, convex_hull<double, 3>>>;

template <class C>
class fuzz_findings : public ::testing::Test {
protected:
    using O = typename C::value_type;
    // The object standing at p: p itself, or the box of zero size at p.
    static O at(const P3& p) {
        if constexpr (point_object<O>) return p;
        else return O(p, p);
    }
    // A structure and the oracle holding the objects at `points` (inserted one by one, or as
    // one batch).
    void store(const std::vector<P3>& points, bool bulk = false) {
        std::vector<O> objects;
        for (const P3& p : points) objects.push_back(at(p));
        if (bulk) c.insert(objects.begin(), objects.end());
        else for (const O& v : objects) c.insert(v);
        oracle.insert(objects.begin(), objects.end());
    }
    // The structure's own invariant check, where it has one.
    void expect_sound() const {
        if constexpr (requires { c.check_invariants(); }) {
            EXPECT_EQ(c.check_invariants(), "");
        }
    }
    void expect_same_nearest(const P3& q) const {
        EXPECT_EQ(spatial_test::distances_from(q, c.find_nearest(q, 3)), spatial_test::distances_from(q, oracle.find_nearest(q, 3)));
    }
    // `limit`: the hit_time the cast starts with (the farthest hit accepted).
    void expect_same_ray(const P3& origin, const P3& direction, double thickness,
                         double limit = std::numeric_limits<double>::infinity()) const {
        intersect_info<P3> a, b;
        a.hit_time = b.hit_time = limit;
        const bool hit = c.intersect(origin, direction, thickness, a);
        EXPECT_EQ(hit, oracle.intersect(origin, direction, thickness, b));
        EXPECT_EQ(a.hit_time, b.hit_time);
    }
    void expect_same_ball(const P3& center, double radius) const {
        EXPECT_EQ(spatial_test::distances_from(center, c.find_in_ball(center, radius)),
                  spatial_test::distances_from(center, oracle.find_in_ball(center, radius)));
    }
    C c;
    brute_force<O> oracle;
};

template <class A, class B>
struct concatenated;
template <class... A, class... B>
struct concatenated<::testing::Types<A...>, ::testing::Types<B...>> {
    using type = ::testing::Types<A..., B...>;
};
// The sanitizer build runs a representative subset (CI time: SPATIAL_TEST_FULL_MATRIX=0): the
// structures the findings were made on, and each family over the other object type.
#if SPATIAL_TEST_FULL_MATRIX
using point_and_box_structures = concatenated<structures_of<P3>, structures_of<B3>>::type;
#else
using point_and_box_structures = ::testing::Types<kd_tree<P3>, hashed_grid<P3>, bvh<P3, ellipsoid<double, 3>>,
                                                  octree<B3>, uniform_grid<B3>, bvh<B3>>;
#endif
TYPED_TEST_SUITE(fuzz_findings, point_and_box_structures);

// A squared distance underflows to 0 when each coordinate difference is below about 1e-162, so
// the object's own test accepts an object a denormal away from a thin ray (thickness 0). The
// structures clipped the ray against their cells with pads relative to the magnitudes only
// (a pad of 0 at 0) and pruned it: kd_tree, hashed_grid and bvh<ellipsoid> missed the hit.
TYPED_TEST(fuzz_findings, thin_ray_hits_an_object_a_denormal_off_its_line) {
    const P3 along_minus_x{{-1.0, -0.0, -0.0}};
    this->store({P3{{0x0.012688b70e62bp-1022, 0, 0}}});  // behind the origin by a denormal: hit at t = 0
    this->expect_same_ray(P3{{0, 0, 0}}, along_minus_x, 0);
    this->c.clear(), this->oracle.clear();
    this->store({P3{{0, 0, -denormal}}});
    this->expect_same_ray(P3{{0, 0, 0}}, along_minus_x, 0);
    this->c.clear(), this->oracle.clear();
    this->store({P3{{0, -0.0, denormal}}});
    this->expect_same_ray(P3{{1, 0, 0}}, along_minus_x, 0);
}

// Found by the soak (issue 19 part 5) in hashed_grid<point>: a ray cast that did not return.
// Two points a denormal apart size a grid's cells at 2^-1012; emptied, it keeps that size, and
// points near 1e30 then stored land in cells clamped to +-2^50. A ray from near 1e30 pads its
// segment by the rounding of those coordinates (about 1e16), a box of 2^51 cells, which the walk
// (grid_core.hpp) enumerated before comparing the count with its budget. Hangs before the fix.
TYPED_TEST(fuzz_findings, a_ray_walk_never_enumerates_more_cells_than_its_budget) {
    this->store({P3{{0, 0, 0}}, P3{{denormal, 0, 0}}}, true);
    this->c.erase(this->c.begin(), this->c.end());
    this->oracle.clear();
    this->store({P3{{3, -denormal, 0x1.93e5939a08ceap+99}}, P3{{-0.5, 0x1.93e5939a08ceap+99, 0x1.c6bf526340004p+49}}});
    const P3 origin{{3, -denormal, 0x1.93e5939a08ceap+99}}, direction{{-1, 1, -1}};
    this->expect_same_ray(origin, direction, 0, 0);
    this->expect_same_ray(origin, direction, 0);
    this->expect_same_ray(origin, direction, 0.5);
}

// Found by the soak (issue 19 part 5) in hashed_grid<point>, then minimised by a random search
// for a ray cast that does not return: a grid's ray walk (grid_core.hpp) near 1e30, where the
// planes of consecutive cells round to the same value, stopped advancing in t and stepped
// through empty cells forever (the budget counted only occupied ones). Hangs before the fix.
TYPED_TEST(fuzz_findings, a_ray_walk_through_cells_near_1e30_ends) {
    this->store({P3{{1, 0, 1}}, P3{{0x1.93e5939a08ceap+99, 0x1.431e0fae6d721p+96, 1}}});
    this->expect_same_ray(P3{{0x1.93e5939a08ceap+99, -1, -1}},
                          P3{{0x1.9a8p+9, 0x1.93e5939a08ceap+100, 0x1.431e0fae6d721p+96}}, 0);
    this->expect_same_ray(P3{{0x1.93e5939a08ceap+99, -1, -1}},
                          P3{{0x1.9a8p+9, 0x1.93e5939a08ceap+100, 0x1.431e0fae6d721p+96}}, 0.5);
}

// The same underflow in a ball of radius 0: an object at (denormal, -denormal, 0) is at squared
// distance 0 from the origin. hashed_grid looked only at the cells of [c - pad, c + pad] with a
// pad of 0, and missed the object in the neighbouring cell.
TYPED_TEST(fuzz_findings, ball_of_radius_zero_holds_an_object_a_denormal_away) {
    this->store({P3{{denormal, -denormal, 0}}});
    const P3 origin{{0, 0, 0}};
    EXPECT_EQ(spatial_test::signatures_of(this->c.find_in_ball(origin, 0)),
              spatial_test::signatures_of(this->oracle.find_in_ball(origin, 0)));
    EXPECT_EQ(this->oracle.find_in_ball(origin, 0).size(), 1u);
}

// A bvh node volume fitted to objects whose coordinates mix denormals, 1e-30 and 1e30, or span a
// denormal width, did not contain them: the ellipsoid's merge returned the empty ellipsoid (two
// points a denormal apart, then a third), the convex hull's fit a hull half outside a box of
// denormal width or crashed (its exact predicates underflow). check_invariants() caught it; a
// query pruned by such a node would miss objects.
TYPED_TEST(fuzz_findings, node_volumes_contain_objects_whose_coordinates_span_denormals_to_1e30) {
    this->store({P3{{1, 1, 2}}, P3{{-0.0, 0, denormal}}}, true);
    this->store({P3{{0, 0, 0}}});
    this->expect_sound();
    this->expect_same_nearest(P3{{1, 1, 2}});
    this->c.clear(), this->oracle.clear();
    std::vector<P3> corners;  // a box of denormal width
    for (int m = 0; m < 8; ++m) corners.push_back(P3{{m & 1 ? denormal : 0.0, m & 2 ? 2.0 : 0.0, m & 4 ? 0.5 : 0.0}});
    this->store(corners, true);
    this->expect_sound();
    this->c.clear(), this->oracle.clear();
    this->store({P3{{0x0.012688b70e62bp-1022, -123456.789, 1e-30}}, P3{{-denormal, 1e30, 0}}, P3{{0, 0, 0}},
                 P3{{0, 0, 0}}, P3{{0, 0, 0}}},
                true);
    this->expect_sound();
    this->expect_same_nearest(P3{{0, 1e30, 0}});
    this->c.clear(), this->oracle.clear();
    // One by one (the bvh refits and merges node volumes): the ellipsoid merge lost both far
    // points (a NaN scale taken for 0).
    this->store({P3{{2, 1, 3}}, P3{{0, 0, -1e30}}, P3{{denormal, 0, 0}}, P3{{0, 0, 0}}, P3{{0, 0, 0}}, P3{{0, 0, 1e30}}});
    this->expect_sound();
    this->expect_same_nearest(P3{{0, 0, 1e30}});
}

// Soak finding (docs/fuzzing.md, "Soak"; minimised from the failing sequence by removing points
// while the answer stayed wrong): kd_tree's kNN updated the squared distance to a far cell as
// rd - old^2 + diff^2 (Arya & Mount). With coordinates near 1e30 next to small ones the
// subtraction cancels and rounds ABOVE the squared distance of a point in that cell, and the
// cell was pruned: the 25 nearest of these 35 points were not the oracle's.
TYPED_TEST(fuzz_findings, knn_does_not_prune_a_cell_whose_distance_rounds_up_near_1e30) {
    this->store({P3{{0x1.c6bf52633fffcp+51, 0x1.93e5939a08ceap+99, -6}}, P3{{2, 3, 1}}, P3{{1, 2, 0x1.5b33333333333p+4}},
                 P3{{3, 1, 3}}, P3{{-0x1.3333333333334p-1, 0x1.0000000000001p+0, 0x1.8666666666667p+2}},
                 P3{{0x0.01c8871bbcb29p-1022, -0x1.4484bfeebc2ap-101, 0x1.39051f30fa069p+100}},
                 P3{{0x1.e4ad1785a42b2p+98, 0x1.8cccccccccccdp+1, 0x1.0000000000001p+0}}, P3{{3, 2, 3}},
                 P3{{0x1.999999999999ap-4, 0x1.6b33333333333p+5, 0}}, P3{{0, 2, 0x1p-1022}},
                 P3{{0x1.0cccccccccccdp+2, 0x1.0cccccccccccdp+2, -0x1.e240c9fbe76c9p+16}}, P3{{4, -6, -1}},
                 P3{{0, 7, -0x1.e240c9fbe76c9p+16}}, P3{{-0x1.4484bfeebc2ap-100, 0x1.856c1984e1ccp-101, -0x1.4484bfeebc2ap-100}},
                 P3{{0x1.299999999999ap+3, -0x1.215a12ca57a78p+16, -0x1.8cccccccccccdp+1}}, P3{{1, 0, 0}},
                 P3{{0x1.6666666666666p-1022, 0x1.3333333333333p+1, -1}}, P3{{0x1.0cccccccccccdp+2, 0x1.9999999999999p-3, -0.5}},
                 P3{{0x1.2f2a36ecd5542p+49, 0x1.82095d520e78fp+14, -0x1.9999999999999p-3}},
                 P3{{0x1.10d9316ec0002p+49, 0x0.012688b70e62bp-1022, -0.5}}, P3{{0x1.c6bf526340004p+49, 0x1.8cccccccccccdp-1, -0.0}},
                 P3{{0, 0, 0}}, P3{{denormal, 0x1.4484bfeebc2ap-100, -0.0}}, P3{{2, 0, 0}}, P3{{-0x1.3333333333333p-2, 0, 0}},
                 P3{{0x1.10d9316ec0002p+49, 0x0.012688b70e62bp-1022, -0.5}},
                 P3{{0x1.c6bf526340004p+49, -0x1.4484bfeebc2ap-100, -0x1.e240c9fbe76c9p+16}}, P3{{0x1.c6bf526340004p+49, -1, -1}},
                 P3{{0x1.c6bf526340004p+49, -0x1.4484bfeebc2ap-100, -0x1.e240c9fbe76c9p+16}},
                 P3{{0x1.c6bf526340004p+49, -0x1.e240c9fbe76c9p+16, -0.0}}, P3{{3, 0, -0x1.3333333333333p-1}},
                 P3{{-0x1.cccccccccccccp+1, -0.25, -0x1.8cccccccccccdp+0}}, P3{{0, 0x1p-1022, -0x1.f700f64ba3a78p-99}},
                 P3{{1, 0, 0}}, P3{{0, 0, 0}}});
    const P3 q{{-0x1.e4ad1785a42b2p+98, 0x1.93e5939a08ceap+100, 0x1.39051f30fa069p+101}};
    for (std::size_t k = 1; k <= this->oracle.size(); ++k)
        EXPECT_EQ(spatial_test::distances_from(q, this->c.find_nearest(q, k)),
                  spatial_test::distances_from(q, this->oracle.find_nearest(q, k)))
            << "k = " << k;
}

// Found by the operations fuzzer in hashed_grid<box> (CI of 96fc62c, 2026-12-02): the first
// object, near -123456, sizes the cells at about 7716, so objects near 1e30 land in cells
// clamped to 2^50 on x, which hold everything beyond the clamp too. The kNN search by blocks
// (grid_core.hpp) bounded such a cell by its nominal faces, about 1e30 short of its objects:
// both cells of the clamp column got the same bound, and whichever was visited first ended
// the search, with the farther object when it came first (two of these four orders, before
// the fix).
TYPED_TEST(fuzz_findings, knn_reaches_every_cell_at_the_clamp_of_the_cell_coordinates) {
    const double far = 0x1.93e5939a08ceap+99, first = -0x1.e240c9fbe76c9p+16;
    const P3 q{{far, -1, 0}};
    for (const double side : {1.0, -1.0})
        for (const bool nearer_first : {true, false}) {
            SCOPED_TRACE(testing::Message() << "side " << side << ", nearer stored first " << nearer_first);
            this->c.clear(), this->oracle.clear();
            const P3 nearer{{far, 0.25, 0.1 * side}}, farther{{far, 0.5, -0.5 * side}};
            this->store(nearer_first ? std::vector<P3>{P3{{first, 0, 0}}, nearer, farther}
                                     : std::vector<P3>{P3{{first, 0, 0}}, farther, nearer});
            for (std::size_t k = 1; k <= 3; ++k)
                EXPECT_EQ(spatial_test::distances_from(q, this->c.find_nearest(q, k)),
                          spatial_test::distances_from(q, this->oracle.find_nearest(q, k)))
                    << "k = " << k;
            this->expect_sound();
        }
}

// Found by the operations fuzzer (CI, 2026-11-28): the bvh places a small batch (below a quarter
// of its size) in the Morton order of the objects' centres (bvh_motion.hpp). A batch a denormal
// wide made the encoder's scale +inf, and the centre at the low end was encoded as 0 * inf = NaN,
// converted to an integer: undefined behaviour (-fsanitize=float-cast-overflow).
TYPED_TEST(fuzz_findings, a_small_batch_a_denormal_wide_is_inserted_whole) {
    this->store({P3{{1, 2, 3}}, P3{{-1, 0, 2}}, P3{{0.5, 7, -1}}, P3{{2, 2, 2}}, P3{{3, -1, 0}}, P3{{0, 0, 1}},
                 P3{{1e30, 0, 0}}, P3{{-1e30, 1, 1}}, P3{{0.25, 0.25, 0.25}}});
    this->store({P3{{0, 0, 0}}, P3{{denormal, 0, 0}}}, true);
    this->expect_sound();
    EXPECT_EQ(this->c.size(), this->oracle.size());
    this->expect_same_nearest(P3{{0, 0, 0}});
    this->expect_same_nearest(P3{{denormal, 0, 0}});
}

// Found by the soak (bvh<point, convex_hull>, docs/fuzzing.md run 14): three points equal in
// x, a few denormals apart in y and about 1e-30 apart in z, and a ball of radius R about
// 2^99.6 centred R away along y. Their squared distances round to exactly R^2, so the ball
// holds them; the bvh's hull of the three had "unit" normals longer than 1 (their squares
// underflowed) and pruned the ball.
TYPED_TEST(fuzz_findings, a_ball_reaching_a_sliver_a_few_denormals_thick_finds_it) {
    const std::vector<P3> sliver{P3{{0x1p+1, 0x1p-1022, 0x1.4484bfeebc2ap-100}},
                                 P3{{0x1p+1, 0x0.0000000000001p-1022, -0x1.4484bfeebc2ap-100}},
                                 P3{{0x1p+1, -0x0.0000000000001p-1022, -0x0.0000000000001p-1022}}};
    const P3 center{{0x1p+1, 0x1.93e5939a08ceap+99, 0x1p+0}};
    const double radius = 0x1.93e5939a08ceap+99;
    this->store(sliver);
    this->expect_same_ball(center, radius);
    this->c.clear(), this->oracle.clear();
    this->store(sliver, true);
    this->expect_same_ball(center, radius);
}

// collision_grid lays its cells out over the objects' bounds; for two points a denormal apart the
// cell size (the span over a cube root of the cell budget) underflowed to 0, then became NaN, and
// the layout loop never ended (a hang in self_pairs and pairs_with).
TEST(fuzz_findings_collision_grid, points_a_denormal_apart_get_cells_and_their_pairs) {
    const std::vector<P3> points{P3{{0, 0, 1}}, P3{{denormal, 0, 1}}, P3{{denormal, 0, 1}}};
    const collision_grid<P3> grid(points.begin(), points.end());
    const brute_force<P3> oracle(points.begin(), points.end());
    EXPECT_EQ(spatial_test::slots_of(grid.self_pairs(pair_filter::candidates)),
              spatial_test::slots_of(oracle.self_pairs(pair_filter::candidates)));
    EXPECT_EQ(spatial_test::slots_of(grid.self_pairs()), spatial_test::slots_of(oracle.self_pairs()));
    const collision_grid<P3> empty;
    EXPECT_TRUE(empty.pairs_with(grid, pair_filter::candidates).empty());
}

// Pairs between a collision_grid and an EMPTY one: the joint grid over both sets took the first
// set alone for a self-pair query and reported its pairs with indices into the empty second set
// (a read far out of bounds: a crash).
TEST(fuzz_findings_collision_grid, pairs_with_an_empty_grid_are_none) {
    using B = spatial_test::B3;
    const std::vector<B> boxes{B(P3{{0, 1, 3}}, P3{{0, 1, 3}}), B(P3{{0, 0, 3}}, P3{{denormal, 1, 3}})};
    const collision_grid<B> grid(boxes.begin(), boxes.end()), empty;
    for (const auto filter : {pair_filter::candidates, pair_filter::exact}) {
        EXPECT_TRUE(grid.pairs_with(empty, filter).empty());
        EXPECT_TRUE(empty.pairs_with(grid, filter).empty());
    }
}

// A box of denormal height next to a point-sized box: the joint grid's cell size was the denormal
// height itself, whose reciprocal overflows to infinity, so a coordinate on the grid's origin
// mapped to 0 * inf = NaN and then to a cell index by an undefined conversion.
TEST(fuzz_findings_collision_grid, a_box_of_denormal_height_gets_finite_cells) {
    using B = spatial_test::B3;
    const std::vector<B> a{B(P3{{0, 0, 0}}, P3{{0, 0, 0}})}, b{B(P3{{0, 0, 0}}, P3{{0, 0, denormal}})};
    const collision_grid<B> ga(a.begin(), a.end()), gb(b.begin(), b.end());
    const brute_force<B> oa(a.begin(), a.end()), ob(b.begin(), b.end());
    for (const auto filter : {pair_filter::candidates, pair_filter::exact}) {
        EXPECT_EQ(spatial_test::slots_of(ga.pairs_with(gb, filter)), spatial_test::slots_of(oa.pairs_with(ob, filter)));
        // The cause, visible without a sanitizer (a NaN cell index happens to give the right
        // pairs here): the cell size must have a finite reciprocal.
        EXPECT_TRUE(std::isfinite(1 / ga.grid_stats().cell_size)) << ga.grid_stats().cell_size;
    }
}

}  // namespace
