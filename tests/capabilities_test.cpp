// The capability concepts (core/capabilities.hpp) hold for exactly the structures their
// documentation lists as models (docs/contract.md, "Capabilities beyond the contract"), and
// the shared base gives every structure the same forwarding members and error names.

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "spatial/brute/brute_force.hpp"
#include "spatial/bvh/bvh.hpp"
#include "spatial/collide/collision_grid.hpp"
#include "spatial/collide/sweep_and_prune.hpp"
#include "spatial/core/capabilities.hpp"
#include "spatial/core/point.hpp"
#include "spatial/grid/hashed_grid.hpp"
#include "spatial/grid/uniform_grid.hpp"
#include "spatial/kdtree/kd_tree.hpp"
#include "spatial/objects/box.hpp"
#include "spatial/octree/octree.hpp"

using namespace spatial;
using B = objects::box<double, 3>;
using P = point<double, 3>;

// Motion.
static_assert(single_motion<bvh<B>> && single_motion<collision_grid<B>> && single_motion<sweep_and_prune<B>>);
static_assert(!single_motion<kd_tree<B>> && !single_motion<octree<B>> && !single_motion<uniform_grid<B>> &&
              !single_motion<hashed_grid<B>> && !single_motion<brute_force<B>>);
static_assert(batched_motion<bvh<B>> && batched_motion<collision_grid<B>>);
static_assert(!batched_motion<sweep_and_prune<B>> && !batched_motion<kd_tree<B>> && !batched_motion<brute_force<B>>);
static_assert(motion_with_strategy<bvh<B>> && !motion_with_strategy<collision_grid<B>>);
// Pairs.
static_assert(pair_search<brute_force<B>> && pair_search<kd_tree<B>> && pair_search<octree<B>> &&
              pair_search<uniform_grid<B>> && pair_search<hashed_grid<B>> && pair_search<bvh<B>> &&
              pair_search<collision_grid<B>> && pair_search<sweep_and_prune<B>>);
static_assert(streamed_self_pairs<collision_grid<B>> && !streamed_self_pairs<sweep_and_prune<B>> &&
              !streamed_self_pairs<bvh<B>>);
// Rays, kNN candidates, statistics, node areas.
static_assert(ray_preparation<bvh<B>> && !ray_preparation<kd_tree<B>> && !ray_preparation<octree<B>>);
static_assert(candidate_knn<kd_tree<P>> && !candidate_knn<bvh<P>> && !candidate_knn<brute_force<P>>);
static_assert(candidate_ball<kd_tree<P>> && !candidate_ball<bvh<P>> && !candidate_ball<brute_force<P>>);
static_assert(batched_knn<kd_tree<P>> && batched_knn<kd_tree<B>> && !batched_knn<bvh<P>> && !batched_knn<octree<P>> &&
              !batched_knn<brute_force<P>>);
using kd_with_stats = kd_tree<P, kd_tree_config<16, median_of_widest_spread, true>>;
static_assert(reports_query_stats<bvh<B>> && reports_query_stats<kd_with_stats>);
static_assert(!reports_query_stats<kd_tree<P>> && !reports_query_stats<octree<P>> && !reports_query_stats<brute_force<P>>);
static_assert(reports_node_areas<bvh<B>> && !reports_node_areas<kd_tree<B>>);

namespace {

// The last query's counts, reset by the next query, the same way in both models.
TEST(query_stats, kd_tree_and_bvh_report_the_last_query_only) {
    std::vector<P> pts;
    for (int i = 0; i < 500; ++i) pts.push_back(P{{i * 0.37 - 90.0 * (i % 3), (i * 7 % 101) * 0.5, (i % 13) * 1.5}});
    kd_with_stats kd(pts.begin(), pts.end());
    bvh<P> tree(pts.begin(), pts.end());
    const P far{{1e6, 1e6, 1e6}}, near{{10, 10, 10}};
    (void)kd.find_nearest(near, 50);
    const auto many = kd.last_query_stats();
    (void)kd.find_in_box(far, far);  // a box far from every point: a short descent
    const auto few = kd.last_query_stats();
    (void)kd.find_in_box(far, far);  // the same query again: the same counts, not a running sum
    EXPECT_GT(many.nodes_visited, few.nodes_visited);
    EXPECT_GT(many.objects_tested, 0u);
    EXPECT_EQ(kd.last_query_stats().nodes_visited, few.nodes_visited);
    EXPECT_EQ(kd.last_query_stats().objects_tested, few.objects_tested);
    (void)tree.find_nearest(near, 50);
    EXPECT_GT(tree.last_query_stats().objects_tested, 0u);
    (void)tree.find_in_box(far, far);
    EXPECT_EQ(tree.last_query_stats().objects_tested, 0u);
}

// Error messages name the structure (its one structure_name) and the operation.
template <class C>
std::string message_of_bad_query() {
    C c;
    c.insert(P{{0, 0, 0}});
    try {
        (void)c.find_nearest(P{{std::nan(""), 0, 0}}, 1);
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "no exception";
}
TEST(container_base, error_messages_name_structure_and_operation) {
    EXPECT_EQ(message_of_bad_query<kd_tree<P>>().rfind("kd_tree::find_nearest: query point", 0), 0u);
    EXPECT_EQ(message_of_bad_query<octree<P>>().rfind("octree::find_nearest: query point", 0), 0u);
    EXPECT_EQ(message_of_bad_query<uniform_grid<P>>().rfind("uniform_grid::find_nearest: query point", 0), 0u);
    EXPECT_EQ(message_of_bad_query<hashed_grid<P>>().rfind("hashed_grid::find_nearest: query point", 0), 0u);
    EXPECT_EQ(message_of_bad_query<bvh<P>>().rfind("bvh::find_nearest: query point", 0), 0u);
    EXPECT_EQ(message_of_bad_query<brute_force<P>>().rfind("brute_force::find_nearest: query point", 0), 0u);
}

// The base's thickness check names the structure too, and a rejected value changes nothing.
TEST(container_base, set_ray_thickness_rejects_negative_and_keeps_the_old_value) {
    octree<P> o;
    o.set_ray_thickness(0.5);
    try {
        o.set_ray_thickness(-1);
        FAIL() << "negative thickness accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_EQ(std::string(e.what()).rfind("octree::set_ray_thickness: thickness", 0), 0u) << e.what();
    }
    EXPECT_EQ(o.ray_thickness(), 0.5);
}

}  // namespace
