// Differential property tests of the kd-tree against the brute-force oracle
// (differential.hpp): random operation sequences on points and objects. Seeds are logged;
// SPATIAL_TEST_SEED replays one.

#include <gtest/gtest.h>

#include "differential.hpp"
#include "spatial/kdtree/kd_tree.hpp"

using namespace spatial;

namespace {

template <class C>
class differential : public ::testing::Test {};

using kd_tiny = kd_tree_config<2, median_of_widest_spread>;
using kd_small = kd_tree_config<4, median_of_widest_spread>;
using kd_mid = kd_tree_config<5, midpoint_of_max_spread>;
using structure_types =
    ::testing::Types<kd_tree<point<double, 3>>, kd_tree<point<float, 3>>, kd_tree<point<double, 2>>,
                     kd_tree<point<float, 2>>, kd_tree<point<double, 3>, kd_tiny>, kd_tree<point<float, 2>, kd_small>,
                     kd_tree<point<double, 3>, kd_mid>, kd_tree<spatial_test::tagged_point, kd_small>>;
TYPED_TEST_SUITE(differential, structure_types);

TYPED_TEST(differential, random_operation_sequences_agree_with_brute_force) {
    spatial_test::run_all_distributions<TypeParam>(20261122, 4000);
}

}  // namespace
