// spatial::bvh, part 2: differential tests against brute force for the remaining volumes
// (obb, ellipsoid, convex_hull) in 3D double and the other object types (spheres, triangles).
// Part 1 is bvh_test.cpp, 2D and float are in bvh_2d_float_test.cpp, the contract suite in
// bvh_contract_test.cpp.

#include <gtest/gtest.h>

#include "bvh_test_support.hpp"

using namespace spatial;

namespace {

template <class Tree>
class bvh_volumes : public ::testing::Test {};

using spatial_test::B3, spatial_test::P3;
// The sanitizer build runs a representative subset (CI time: SPATIAL_TEST_FULL_MATRIX=0): each
// volume type, each object kind and both builders still appear; the release build runs all.
#if SPATIAL_TEST_FULL_MATRIX
using part2_trees = ::testing::Types<
    // 3D double: obb, ellipsoid, convex hull over points and boxes, both builders
    bvh<P3, obb<double, 3>, bvh_sah_config<>>, bvh<B3, obb<double, 3>, bvh_median_config<>>,
    bvh<P3, ellipsoid<double, 3>, bvh_median_config<>>, bvh<B3, ellipsoid<double, 3>, bvh_sah_config<>>,
    bvh<P3, convex_hull<double, 3>, bvh_sah_config<8>>, bvh<B3, convex_hull<double, 3>, bvh_median_config<4>>,
    // other objects
    bvh<objects::sphere<double, 3>, ellipsoid<double, 3>>, bvh<objects::triangle<double, 3>, obb<double, 3>>,
    bvh<objects::triangle<double, 3>, kdop<double, 3, 14>, bvh_median_config<>>>;
#else
using part2_trees = ::testing::Types<bvh<P3, obb<double, 3>, bvh_sah_config<>>, bvh<B3, ellipsoid<double, 3>, bvh_sah_config<>>,
                                     bvh<B3, convex_hull<double, 3>, bvh_median_config<4>>,
                                     bvh<objects::triangle<double, 3>, kdop<double, 3, 14>, bvh_median_config<>>>;
#endif
TYPED_TEST_SUITE(bvh_volumes, part2_trees);

TYPED_TEST(bvh_volumes, matches_brute_force_under_interleaved_updates_and_motion) {
    bvh_test::interleaved_updates_and_motion<TypeParam>();
}
TYPED_TEST(bvh_volumes, matches_brute_force_at_offset_and_small_scales) {
    bvh_test::offset_and_small_scales<TypeParam>();
}
TYPED_TEST(bvh_volumes, small_trees) {
    bvh_test::small_trees<TypeParam>();
}

}  // namespace

namespace {
// n small random triangles (edges up to 0.1) in the unit cube.
std::vector<objects::triangle<double, 3>> small_triangle_soup(std::uint64_t seed, int n) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1), s(0.01, 0.05);
    std::vector<objects::triangle<double, 3>> tris;
    for (int i = 0; i < n; ++i) {
        const point<double, 3> c{{u(rng), u(rng), u(rng)}};
        point<double, 3> v[3];
        for (auto& p : v)
            for (std::size_t k = 0; k < 3; ++k) p[k] = c[k] + s(rng) * (2 * u(rng) - 1);
        tris.emplace_back(v[0], v[1], v[2]);
    }
    return tris;
}
}  // namespace

// node_surface_areas(): the aabb tree's two sums coincide; volumes nested in the node's box
// (k-DOPs include the box's six directions, hulls are the tightest convex sets) never exceed
// its area (area is monotone under inclusion of convex sets), so their ratio is at most 1.
TEST(bvh_tightness, node_surface_areas_are_equal_for_boxes_and_at_most_the_boxes_for_nested_volumes) {
    const auto tris = small_triangle_soup(21, 2000);
    const auto [a_vol, a_box] = bvh<objects::triangle<double, 3>>(tris.begin(), tris.end()).node_surface_areas();
    EXPECT_GT(a_box, 0);
    EXPECT_EQ(a_vol, a_box);
    const auto [k_vol, k_box] =
        bvh<objects::triangle<double, 3>, kdop<double, 3, 14>>(tris.begin(), tris.end()).node_surface_areas();
    EXPECT_LT(k_vol, k_box * (1 + 1e-9));
    EXPECT_GT(k_vol, 0.5 * k_box);  // not degenerate
    const auto [h_vol, h_box] =
        bvh<objects::triangle<double, 3>, convex_hull<double, 3>>(tris.begin(), tris.end()).node_surface_areas();
    EXPECT_LT(h_vol, h_box * (1 + 1e-9));
    EXPECT_EQ(h_box, k_box);                // the builders see boxes only: the same tree
    EXPECT_LE(h_vol, k_vol * (1 + 1e-9));  // and the hull is nested in the 14-DOP
}

// quality() is the boxes' sum over the root box whatever the volume type: the same number as
// node_surface_areas().second over the root box (the same box for every tree over these
// objects), and the same for a 26-DOP and a hull tree (the builders see boxes only, so it is
// one tree). It used to compute the volumes' areas too and drop them, which made a k-DOP
// tree's every build pay for vertex enumeration.
TEST(bvh_tightness, quality_is_the_node_boxes_area_for_every_volume_type) {
    const auto tris = small_triangle_soup(22, 1500);
    const bvh<objects::triangle<double, 3>> boxes(tris.begin(), tris.end());
    const bvh<objects::triangle<double, 3>, kdop<double, 3, 26>> dops(tris.begin(), tris.end());
    const bvh<objects::triangle<double, 3>, convex_hull<double, 3>> hulls(tris.begin(), tris.end());
    // For the aabb tree the root volume is the root box.
    const double root_area = static_cast<double>(boxes.root_volume().surface_area());
    EXPECT_GT(boxes.quality(), 1.0);
    EXPECT_DOUBLE_EQ(boxes.quality(), boxes.node_surface_areas().second / root_area);
    EXPECT_DOUBLE_EQ(dops.quality(), dops.node_surface_areas().second / root_area);
    EXPECT_DOUBLE_EQ(hulls.quality(), hulls.node_surface_areas().second / root_area);
    EXPECT_EQ(hulls.quality(), dops.quality());  // the same tree, other volumes
    EXPECT_EQ(dops.quality_at_build(), dops.quality());
}
