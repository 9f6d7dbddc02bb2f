// The shared container contract suite (container_contract.hpp) on a few bvh instantiations:
// points and objects, several volumes, both builders, float and 2D.

#include "container_contract.hpp"

#include "spatial/bvh/bvh.hpp"
#include "spatial/objects/box.hpp"
#include "spatial/objects/sphere.hpp"
#include "spatial/objects/triangle.hpp"

using namespace spatial;
using spatial_test::tagged_box;
using spatial_test::tagged_point;

// The sanitizer build runs a representative subset (CI time: SPATIAL_TEST_FULL_MATRIX=0): points
// and objects, both scalars and dimensions, a user type and a non-box volume still appear.
#if SPATIAL_TEST_FULL_MATRIX
using bvh_point_containers =
    ::testing::Types<bvh<point<double, 3>>, bvh<point<float, 2>, obb<float, 2>, bvh_median_config<2>>,
                     bvh<tagged_point, sphere<double, 3>>, bvh<point<double, 3>, kdop<double, 3, 26>, bvh_median_config<>>>;
#else
using bvh_point_containers = ::testing::Types<bvh<point<float, 2>, obb<float, 2>, bvh_median_config<2>>,
                                              bvh<tagged_point, sphere<double, 3>>>;
#endif
namespace spatial_contract {
INSTANTIATE_TYPED_TEST_SUITE_P(bvh_points, container_contract, bvh_point_containers);
}

#if SPATIAL_TEST_FULL_MATRIX
using bvh_object_containers =
    ::testing::Types<bvh<objects::box<double, 3>, ellipsoid<double, 3>>, bvh<tagged_box, aabb<double, 3>>,
                     bvh<objects::triangle<double, 3>, convex_hull<double, 3>, bvh_median_config<>>,
                     bvh<objects::sphere<float, 2>, kdop<float, 2, 8>>>;
#else
using bvh_object_containers = ::testing::Types<bvh<tagged_box, aabb<double, 3>>,
                                               bvh<objects::triangle<double, 3>, convex_hull<double, 3>, bvh_median_config<>>>;
#endif
namespace spatial_contract {
INSTANTIATE_TYPED_TEST_SUITE_P(bvh_objects, container_contract, bvh_object_containers);
}
