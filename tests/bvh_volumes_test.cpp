// spatial::bvh, part 2: differential tests against brute force for the remaining volumes
// (obb, ellipsoid, convex_hull) in 3D double and the other object types (spheres, triangles).
// Part 1 is bvh_test.cpp, 2D and float are in bvh_2d_float_test.cpp, the contract suite in
// bvh_contract_test.cpp.

#include <gtest/gtest.h>

#include "bvh_test_support.hpp"

using namespace spatial;
using bvh_test::differential;

namespace {

template <class Tree>
class bvh_volumes : public ::testing::Test {};

using P3 = point<double, 3>;
using B3 = objects::box<double, 3>;
using part2_trees = ::testing::Types<
    // 3D double: obb, ellipsoid, convex hull over points and boxes, both builders
    bvh<P3, obb<double, 3>, bvh_sah_config<>>, bvh<B3, obb<double, 3>, bvh_median_config<>>,
    bvh<P3, ellipsoid<double, 3>, bvh_median_config<>>, bvh<B3, ellipsoid<double, 3>, bvh_sah_config<>>,
    bvh<P3, convex_hull<double, 3>, bvh_sah_config<8>>, bvh<B3, convex_hull<double, 3>, bvh_median_config<4>>,
    // other objects
    bvh<objects::sphere<double, 3>, ellipsoid<double, 3>>, bvh<objects::triangle<double, 3>, obb<double, 3>>,
    bvh<objects::triangle<double, 3>, kdop<double, 3, 14>, bvh_median_config<>>>;
TYPED_TEST_SUITE(bvh_volumes, part2_trees);

TYPED_TEST(bvh_volumes, matches_brute_force_under_interleaved_updates_and_motion) {
    for (std::uint64_t seed : {21u, 22u}) differential<TypeParam>(spatial_test::test_seed(seed * 104729), 250, 5);
}
TYPED_TEST(bvh_volumes, matches_brute_force_at_offset_and_small_scales) {
    differential<TypeParam>(spatial_test::test_seed(31), 150, 2, 1e6, 10);
    differential<TypeParam>(spatial_test::test_seed(32), 150, 2, 0, 1e-12);
}
TYPED_TEST(bvh_volumes, small_trees) {
    for (std::size_t n : {0u, 1u, 3u}) differential<TypeParam>(spatial_test::test_seed(200 + n), n, 3);
}

}  // namespace
