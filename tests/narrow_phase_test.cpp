// collide::objects_intersect for every object pair, mixed types included (closed sets:
// touching counts), hand-built cases on both sides of each boundary, argument order
// symmetric; the box-overlap fallback for a user type; and mixed-type bipartite pair
// queries (boxes in a bvh against spheres in brute_force and in a uniform grid) agreeing with
// brute force.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "spatial/brute/brute_force.hpp"
#include "spatial/bvh/bvh.hpp"
#include "spatial/collide/narrow_phase.hpp"
#include "spatial/collide/pairs.hpp"
#include "spatial/grid/uniform_grid.hpp"
#include "test_support.hpp"

using namespace spatial;
using P = point<double, 3>;
using box3 = objects::box<double, 3>;
using sphere3 = objects::sphere<double, 3>;
using tri3 = objects::triangle<double, 3>;

namespace {

template <class A, class B>
bool both_ways(const A& a, const B& b) {
    const bool x = collide::narrow_phase(a, b), y = collide::narrow_phase(b, a);
    EXPECT_EQ(x, y);
    return x;
}

const double above = std::nextafter(1.0, 2.0);

TEST(narrow_phase, boxes_points_and_triangles_are_exact) {
    const box3 unit(P{{0, 0, 0}}, P{{1, 1, 1}});
    EXPECT_TRUE(both_ways(unit, box3(P{{1, 0, 0}}, P{{2, 1, 1}})));       // touching face
    EXPECT_FALSE(both_ways(unit, box3(P{{above, 0, 0}}, P{{2, 1, 1}})));  // 1 ulp apart
    EXPECT_TRUE(both_ways(P{{1, 1, 1}}, unit));                            // corner
    EXPECT_FALSE(both_ways(P{{1, 1, above}}, unit));
    EXPECT_TRUE(both_ways(P{{1, 2, 3}}, P{{1, 2, 3}}));
    EXPECT_FALSE(both_ways(P{{1, 2, 3}}, P{{1, 2, std::nextafter(3.0, 4.0)}}));
    const tri3 t(P{{0, 0, 0}}, P{{2, 0, 0}}, P{{0, 2, 0}});
    EXPECT_TRUE(both_ways(P{{1, 1, 0}}, t));   // on the hypotenuse
    EXPECT_FALSE(both_ways(P{{1, std::nextafter(1.0, 2.0), 0}}, t));
    EXPECT_FALSE(both_ways(P{{0.5, 0.5, 1e-300}}, t));  // off the plane
    EXPECT_TRUE(both_ways(t, box3(P{{1, 1, -1}}, P{{3, 3, 0}})));  // box touches the hypotenuse from above-right
    EXPECT_FALSE(both_ways(t, box3(P{{1.1, 1.1, -1}}, P{{3, 3, 1}})));
}

TEST(narrow_phase, spheres_against_everything) {
    const sphere3 s(P{{0, 0, 0}}, 1);
    EXPECT_TRUE(both_ways(s, sphere3(P{{2, 0, 0}}, 1)));  // touching
    EXPECT_FALSE(both_ways(s, sphere3(P{{2.001, 0, 0}}, 1)));
    EXPECT_TRUE(both_ways(s, box3(P{{1, -1, -1}}, P{{2, 1, 1}})));  // box face tangent
    EXPECT_FALSE(both_ways(s, box3(P{{0.8, 0.8, 0.8}}, P{{2, 2, 2}})));  // corner outside the ball
    EXPECT_TRUE(both_ways(s, box3(P{{0.5, 0.5, 0.5}}, P{{2, 2, 2}})));
    EXPECT_TRUE(both_ways(s, tri3(P{{0.5, -5, 0}}, P{{0.5, 5, 0}}, P{{0.5, 0, 5}})));  // plane x = 0.5 cuts the ball
    EXPECT_FALSE(both_ways(s, tri3(P{{1.5, -5, 0}}, P{{1.5, 5, 0}}, P{{1.5, 0, 5}})));
    EXPECT_TRUE(both_ways(P{{0, 0, 1}}, s));
    EXPECT_FALSE(both_ways(P{{0, 0, 1.001}}, s));
}

// A user type with bounds only: the fallback is box overlap (conservative).
TEST(narrow_phase, user_types_fall_back_to_their_bounding_boxes) {
    using spatial_test::tagged_box;
    static_assert(stored_object<tagged_box>);
    tagged_box a, b;
    for (std::size_t i = 0; i < 3; ++i) a.lo[i] = 0, a.hi[i] = 1, b.lo[i] = 1, b.hi[i] = 2;
    EXPECT_TRUE(collide::narrow_phase(a, b));
    b.lo[0] = above;
    EXPECT_FALSE(collide::narrow_phase(a, b));
}

TEST(narrow_phase, mixed_type_bipartite_pairs_agree_with_brute_force) {
    const std::uint64_t seed = spatial_test::test_seed(111);
    SCOPED_TRACE(spatial_test::replay_hint(seed));
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1), h(0.005, 0.03);
    std::vector<box3> boxes;
    std::vector<sphere3> spheres;
    for (int i = 0; i < 800; ++i) {
        const P c{{u(rng), u(rng), u(rng)}};
        const double r = h(rng);
        boxes.emplace_back(P{{c[0] - r, c[1] - r, c[2] - r}}, P{{c[0] + r, c[1] + 2 * r, c[2] + r}});
        spheres.emplace_back(P{{u(rng), u(rng), u(rng)}}, h(rng));
    }
    brute_force<box3> box_oracle;
    box_oracle.insert(boxes.begin(), boxes.end());
    brute_force<sphere3> sphere_oracle;
    sphere_oracle.insert(spheres.begin(), spheres.end());
    const auto want = box_oracle.pairs_with(sphere_oracle);
    EXPECT_GT(want.size(), 20u);
    // The candidate set is bigger: some box/sphere pairs only have overlapping boxes.
    EXPECT_GT(box_oracle.pairs_with(sphere_oracle, pair_filter::candidates).size(), want.size());
    auto slots = [](const auto& pairs) {
        std::vector<std::pair<slot_index, slot_index>> s;
        for (const auto& [a, b] : pairs) s.emplace_back(a.slot(), b.slot());
        return s;
    };
    const bvh<box3> tree(boxes.begin(), boxes.end());  // bulk insert from empty: slots in input order
    EXPECT_EQ(slots(tree.pairs_with(sphere_oracle)), slots(want));
    uniform_grid<sphere3> grid;
    grid.insert(spheres.begin(), spheres.end());
    // The grid of spheres against the brute-force boxes, the other way round: the same pairs.
    // The grid may allocate slots in its own order, so spheres are named by their centre's x
    // (distinct random doubles) and boxes by their slot.
    std::vector<std::pair<slot_index, double>> got, expected;
    for (const auto& [s, b] : grid.pairs_with(box_oracle)) got.emplace_back(b.slot(), s->center()[0]);
    for (const auto& [b, s] : want) expected.emplace_back(b.slot(), s->center()[0]);
    std::sort(got.begin(), got.end());
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(got, expected);
}

}  // namespace
