// Structures outside the library (examples/) run the same typed contract suite
// (container_contract.hpp) and differential tests against brute force (differential.hpp) as
// the library's own. A new structure is ONE line in each type list below
// (docs/adding-a-structure.md).

#include <gtest/gtest.h>

#include "container_contract.hpp"
#include "differential.hpp"
#include "examples/morton_array.hpp"
#include "spatial/objects/box.hpp"
#include "spatial/objects/sphere.hpp"
#include "spatial/objects/triangle.hpp"

using namespace spatial;
using spatial_test::tagged_box;
using spatial_test::tagged_point;

// Small blocks so that the tests cross block boundaries, re-sorts and holes often.
template <class O>
using morton_small = examples::morton_array<O, 4>;

// The sanitizer build runs a representative subset (CI time: SPATIAL_TEST_FULL_MATRIX=0); every
// object kind still appears.
#if SPATIAL_TEST_FULL_MATRIX
using example_point_containers =
    ::testing::Types<examples::morton_array<point<double, 3>>, morton_small<point<float, 2>>, morton_small<tagged_point>>;
using example_object_containers =
    ::testing::Types<examples::morton_array<objects::box<double, 3>>, morton_small<objects::triangle<float, 3>>,
                     morton_small<objects::sphere<double, 2>>, morton_small<tagged_box>>;
#else
using example_point_containers = ::testing::Types<morton_small<point<float, 2>>>;
using example_object_containers =
    ::testing::Types<morton_small<objects::triangle<float, 3>>, morton_small<objects::sphere<double, 2>>>;
#endif

namespace spatial_contract {
INSTANTIATE_TYPED_TEST_SUITE_P(example_points, container_contract, example_point_containers);
INSTANTIATE_TYPED_TEST_SUITE_P(example_objects, container_contract, example_object_containers);
}  // namespace spatial_contract

namespace {

template <class C>
class example_differential : public ::testing::Test {};
#if SPATIAL_TEST_FULL_MATRIX
using example_differential_types =
    ::testing::Types<examples::morton_array<point<double, 3>>, morton_small<point<float, 2>>,
                     morton_small<objects::box<double, 3>>, morton_small<objects::triangle<double, 3>>>;
#else
using example_differential_types = ::testing::Types<morton_small<point<float, 2>>, morton_small<objects::box<double, 3>>>;
#endif
TYPED_TEST_SUITE(example_differential, example_differential_types);

TYPED_TEST(example_differential, random_operation_sequences_agree_with_brute_force) {
    spatial_test::run_all_distributions<TypeParam>(20261125, 3000);
}

}  // namespace
