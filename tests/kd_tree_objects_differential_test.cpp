// kd_tree over objects with extent against the brute_force oracle: long random sequences of
// every operation (tests/differential.hpp), every distribution, several object types, leaf
// capacities and scalars.

#include <gtest/gtest.h>

#include "differential.hpp"
#include "spatial/kdtree/kd_tree.hpp"
#include "spatial/objects/box.hpp"
#include "spatial/objects/sphere.hpp"
#include "spatial/objects/triangle.hpp"

using namespace spatial;

template <class C>
class kd_tree_objects_differential : public ::testing::Test {};
using differential_types =
    ::testing::Types<kd_tree<objects::box<double, 3>>, kd_tree<objects::triangle<double, 3>, kd_tree_config<4>>,
                     kd_tree<objects::sphere<double, 3>, kd_tree_config<5, midpoint_of_max_spread>>,
                     kd_tree<objects::triangle<float, 2>, kd_tree_config<2>>, kd_tree<spatial_test::tagged_box>>;
TYPED_TEST_SUITE(kd_tree_objects_differential, differential_types);

TYPED_TEST(kd_tree_objects_differential, agrees_with_brute_force_on_every_distribution) {
    spatial_test::run_all_distributions<TypeParam>(20261123, 3000);
}
