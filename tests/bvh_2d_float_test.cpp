// spatial::bvh, part 3: differential tests against brute force in 2D (every volume type that
// supports 2D) and in float. Parts 1-2: bvh_test.cpp, bvh_volumes_test.cpp.

#include <gtest/gtest.h>

#include "bvh_test_support.hpp"

using namespace spatial;

namespace {

template <class Tree>
class bvh_2d_float : public ::testing::Test {};

// The sanitizer build runs a representative subset (CI time: SPATIAL_TEST_FULL_MATRIX=0): 2D and
// 3D float, points, boxes and triangles, both builders; the release build runs all.
#if SPATIAL_TEST_FULL_MATRIX
using part3_trees = ::testing::Types<
    // 2D
    bvh<point<double, 2>, kdop<double, 2, 8>>, bvh<objects::box<float, 2>, kdop<float, 2, 16>, bvh_median_config<>>,
    bvh<point<float, 2>, obb<float, 2>>, bvh<objects::box<double, 2>, convex_hull<double, 2>>,
    bvh<point<float, 2>, ellipsoid<float, 2>, bvh_median_config<>>, bvh<objects::triangle<double, 2>, sphere<double, 2>>,
    // 3D float
    bvh<objects::box<float, 3>, aabb<float, 3>>, bvh<point<float, 3>, sphere<float, 3>, bvh_median_config<>>,
    bvh<objects::box<float, 3>, obb<float, 3>>>;
#else
using part3_trees = ::testing::Types<bvh<objects::box<float, 2>, kdop<float, 2, 16>, bvh_median_config<>>,
                                     bvh<point<float, 2>, ellipsoid<float, 2>, bvh_median_config<>>,
                                     bvh<objects::triangle<double, 2>, sphere<double, 2>>, bvh<objects::box<float, 3>, obb<float, 3>>>;
#endif
TYPED_TEST_SUITE(bvh_2d_float, part3_trees);

TYPED_TEST(bvh_2d_float, matches_brute_force_under_interleaved_updates_and_motion) {
    bvh_test::interleaved_updates_and_motion<TypeParam>();
}
TYPED_TEST(bvh_2d_float, matches_brute_force_at_offset_and_small_scales) {
    bvh_test::offset_and_small_scales<TypeParam>();
}
TYPED_TEST(bvh_2d_float, small_trees) {
    bvh_test::small_trees<TypeParam>();
}

}  // namespace
