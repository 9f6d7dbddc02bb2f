// spatial::octree (loose and classic): the shared contract suite, differential tests against
// brute force under interleaved updates, the numerically hard cases (octree_grid_checks.hpp),
// and octree-specific properties: growth by re-rooting, loose vs classic placement of
// straddlers, depth bounds for coincident objects, merging after erasure.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "container_contract.hpp"
#include "octree_grid_checks.hpp"
#include "spatial/brute/brute_force.hpp"
#include "spatial/objects/box.hpp"
#include "spatial/objects/sphere.hpp"
#include "spatial/objects/triangle.hpp"
#include "spatial/octree/octree.hpp"
#include "test_support.hpp"

using namespace spatial;
using spatial_test::tagged_point;
using P3 = point<double, 3>;
using B3 = objects::box<double, 3>;
using tiny_octree = octree_config<2, 6, std::ratio<2>>;  // capacity 2, depth 6: stresses overflow leaves

// The sanitizer build runs a representative subset (CI time: SPATIAL_TEST_FULL_MATRIX=0): every
// structure, scalar, dimension and object kind still appears; the release build runs them all.
#if SPATIAL_TEST_FULL_MATRIX
using octree_point_types = ::testing::Types<octree<P3>, octree<point<float, 2>>, octree<tagged_point>,
                                            octree<P3, classic_octree_config>, octree<P3, tiny_octree>>;
using octree_object_types =
    ::testing::Types<octree<B3>, octree<objects::box<float, 2>>, octree<B3, classic_octree_config>,
                     octree<objects::box<float, 2>, tiny_octree>, octree<objects::sphere<double, 3>>,
                     octree<objects::triangle<float, 3>>, octree<spatial_test::tagged_box>>;
// Hard cases: points and boxes (sphere/triangle factories reject NaN centres themselves).
using octree_hard_types =
    ::testing::Types<octree<P3>, octree<point<float, 2>>, octree<tagged_point>, octree<P3, tiny_octree>, octree<B3>,
                     octree<objects::box<float, 2>>, octree<B3, classic_octree_config>>;
#else
using octree_point_types = ::testing::Types<octree<point<float, 2>>, octree<tagged_point>, octree<P3, tiny_octree>>;
using octree_object_types =
    ::testing::Types<octree<B3, classic_octree_config>, octree<objects::box<float, 2>, tiny_octree>,
                     octree<objects::sphere<double, 3>>, octree<objects::triangle<float, 3>>, octree<spatial_test::tagged_box>>;
using octree_hard_types = ::testing::Types<octree<P3>, octree<objects::box<float, 2>>, octree<B3, classic_octree_config>>;
#endif

namespace spatial_contract {
INSTANTIATE_TYPED_TEST_SUITE_P(octree_points, container_contract, octree_point_types);
INSTANTIATE_TYPED_TEST_SUITE_P(octree_objects, container_contract, octree_object_types);
}  // namespace spatial_contract
namespace og_test {
INSTANTIATE_TYPED_TEST_SUITE_P(octree, octree_grid_hard_cases, octree_hard_types);
}

namespace {

template <class C>
class octree_differential_objects : public ::testing::Test {};
using octree_round_objects = ::testing::Types<octree<objects::sphere<double, 3>>, octree<objects::triangle<float, 3>>>;
TYPED_TEST_SUITE(octree_differential_objects, octree_round_objects);
TYPED_TEST(octree_differential_objects, spheres_and_triangles_match_brute_force) {
    spatial_test::run_all_distributions<TypeParam>(99, 300);
}

TEST(octree, grows_outward_by_re_rooting_and_keeps_everything) {
    octree<P3> t;
    std::vector<P3> pts;
    for (int i = 0; i < 100; ++i) pts.push_back(P3{{i * 0.01, 0.5, 0.5}});
    t.insert(pts.begin(), pts.end());
    const double before = t.root_size();
    ASSERT_GT(before, 0.0);
    t.insert(P3{{5.0, 0.5, 0.5}});  // a few levels: re-rooting keeps the old subtree
    EXPECT_GE(t.root_size(), 3.5 * before);  // re-rooted (5 is inside the loose cell of a 4x root)
    t.insert(P3{{-1e9, 3, 3}});  // too many levels: rebuilt around everything
    EXPECT_GE(t.root_size(), 1e9);
    EXPECT_EQ(t.size(), 102u);
    EXPECT_EQ(t.check_invariants(), "");
    EXPECT_EQ(t.count(P3{{5.0, 0.5, 0.5}}), 1u);
    const auto nn = t.find_nearest(P3{{-1e9, 0, 0}}, 1);
    ASSERT_EQ(nn.size(), 1u);
    EXPECT_EQ((*nn[0])[0], -1e9);
}

TEST(octree, loose_cells_sink_straddlers_that_the_classic_octree_keeps_in_inner_nodes) {
    const std::uint64_t seed = spatial_test::test_seed(3);
    SCOPED_TRACE(spatial_test::replay_hint(seed));
    spatial_test::point_source<P3> src(spatial_test::distribution::uniform, seed);
    std::vector<B3> boxes;
    for (int i = 0; i < 4000; ++i) {
        const P3 c = src.next();
        const double h = 0.002 + 0.004 * src.unit();
        boxes.push_back(B3(P3{{c[0] - h, c[1] - h, c[2] - h}}, P3{{c[0] + h, c[1] + h, c[2] + h}}));
    }
    octree<B3> loose(boxes.begin(), boxes.end());
    octree<B3, classic_octree_config> classic(boxes.begin(), boxes.end());
    EXPECT_EQ(loose.check_invariants(), "");
    EXPECT_EQ(classic.check_invariants(), "");
    // Classic: every box crossing an ancestor's split plane stays up; loose: only boxes larger
    // than their centre-cell (none at these sizes once the cells are >= 0.012) stay up.
    EXPECT_GT(classic.objects_in_inner_nodes(), 100u);
    EXPECT_LT(loose.objects_in_inner_nodes() * 4, classic.objects_in_inner_nodes());
}

TEST(octree, many_coincident_points_with_a_few_distinct_stay_shallow_under_max_depth) {
    octree<P3, tiny_octree> t;
    for (int i = 0; i < 2000; ++i) t.insert(P3{{0.5, 0.5, 0.5}});
    for (int i = 0; i < 20; ++i) t.insert(P3{{0.5 + i * 1e-12, 0.5, 0.5}});
    EXPECT_LE(t.height(), tiny_octree::max_depth + 1);
    EXPECT_EQ(t.check_invariants(), "");
    EXPECT_EQ(t.count(P3{{0.5, 0.5, 0.5}}), 2001u);
}

TEST(octree, erasing_merges_children_back) {
    octree<P3> t;
    spatial_test::point_source<P3> src(spatial_test::distribution::uniform, 5);
    std::vector<octree<P3>::iterator> its;
    for (int i = 0; i < 5000; ++i) its.push_back(t.insert(src.next()));
    const std::size_t full_nodes = t.node_count();
    for (std::size_t i = 0; i + 3 < its.size(); ++i) t.erase(its[i]);
    EXPECT_EQ(t.size(), 3u);
    EXPECT_EQ(t.check_invariants(), "");
    EXPECT_LT(t.node_count() * 50, full_nodes) << "empty subtrees must be merged away";
    EXPECT_LE(t.node_count(), 1u + 8u);
}

TEST(octree, hinted_insertion_of_a_coherent_stream_lands_in_the_right_leaves) {
    octree<P3> t;
    spatial_test::point_source<P3> src(spatial_test::distribution::uniform, 8);
    std::vector<P3> base;
    for (int i = 0; i < 20000; ++i) base.push_back(src.next());
    t.insert(base.begin(), base.end());
    P3 walk{{0.5, 0.5, 0.5}};
    auto hint = t.insert(walk);
    for (int i = 0; i < 5000; ++i) {
        for (int d = 0; d < 3; ++d) walk[d] = std::clamp(walk[d] + (src.unit() - 0.5) * 0.01, -0.5, 1.5);
        hint = t.insert(hint, walk);
        ASSERT_TRUE(*hint == walk);
    }
    EXPECT_EQ(t.check_invariants(), "");
    EXPECT_EQ(t.size(), 25001u);
}

}  // namespace
