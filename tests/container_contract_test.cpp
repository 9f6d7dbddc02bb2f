// The contract suite (container_contract.hpp) on the brute-force oracle and the kd-tree, for
// points and for objects with extent (the oracle; other structures instantiate it in their
// own test files).

#include "container_contract.hpp"

#include "spatial/brute/brute_force.hpp"
#include "spatial/kdtree/kd_tree.hpp"

using namespace spatial;
using spatial_test::tagged_box;
using spatial_test::tagged_point;

using kd_small_leaves = kd_tree_config<4, median_of_widest_spread>;
using kd_midpoint = kd_tree_config<4, midpoint_of_max_spread>;

// The sanitizer build runs a representative subset (CI time: SPATIAL_TEST_FULL_MATRIX=0): every
// structure, scalar, dimension and object kind still appears; the release build runs them all.
#if SPATIAL_TEST_FULL_MATRIX
using point_containers =
    ::testing::Types<brute_force<point<double, 3>>, brute_force<point<float, 2>>, kd_tree<point<double, 3>>,
                     kd_tree<point<float, 2>>, kd_tree<point<double, 2>, kd_small_leaves>,
                     kd_tree<point<float, 3>, kd_midpoint>, kd_tree<tagged_point, kd_small_leaves>,
                     brute_force<tagged_point>>;
#else
using point_containers = ::testing::Types<brute_force<point<float, 2>>, kd_tree<point<double, 3>>,
                                          kd_tree<point<float, 3>, kd_midpoint>, kd_tree<tagged_point, kd_small_leaves>>;
#endif
namespace spatial_contract {
INSTANTIATE_TYPED_TEST_SUITE_P(points, container_contract, point_containers);
}

#if SPATIAL_TEST_FULL_MATRIX
using object_containers =
    ::testing::Types<brute_force<objects::box<double, 3>>, brute_force<objects::box<float, 2>>,
                     brute_force<objects::sphere<double, 3>>, brute_force<objects::sphere<float, 2>>,
                     brute_force<objects::triangle<double, 3>>, brute_force<objects::triangle<float, 3>>,
                     brute_force<objects::triangle<double, 2>>, brute_force<tagged_box>>;
#else
using object_containers =
    ::testing::Types<brute_force<objects::box<float, 2>>, brute_force<objects::sphere<double, 3>>,
                     brute_force<objects::triangle<float, 3>>, brute_force<objects::triangle<double, 2>>,
                     brute_force<tagged_box>>;
#endif
namespace spatial_contract {
INSTANTIATE_TYPED_TEST_SUITE_P(objects, container_contract, object_containers);
}

static_assert(point_object<tagged_point>);
static_assert(bounded_object<tagged_box>);
