// Embree user geometry over boxes and points (harness/object_ray_index.hpp): Embree's float
// BVH with our exact double tests in its callbacks must give brute force's hit times EXACTLY
// (the bounds' margin keeps the float traversal from culling any primitive the double test
// would hit), for thin rays on boxes, thick rays on points (a point is hit when the ray passes
// within the thickness), rays along axes with +-0 components and origins on box faces, and
// with a finite t_max. Also: an empty scene, and an origin too far for the float margin.

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>
#include <vector>

#include "harness/object_ray_index.hpp"
#include "spatial/brute/brute_force.hpp"
#include "spatial/objects/box.hpp"
#include "test_support.hpp"

#if defined(SPATIAL_HAVE_EMBREE) && SPATIAL_HAVE_EMBREE

namespace {

using P = spatial::point<double, 3>;
using box3 = spatial::objects::box<double, 3>;

template <class O>
std::size_t compare_with_brute_force(harness::object_ray_index<O>& index, const std::vector<O>& objects,
                                     double thickness, std::mt19937_64& rng, int rays) {
    index.build(objects, thickness);
    spatial::brute_force<O> oracle;
    oracle.insert(objects.begin(), objects.end());
    std::uniform_real_distribution<double> u(-0.2, 1.2);
    std::uniform_int_distribution<int> grid(0, 8), mode(0, 5);
    std::size_t hits = 0;
    for (int r = 0; r < rays; ++r) {
        P o, d;
        for (std::size_t k = 0; k < 3; ++k) {
            o[k] = r % 4 == 0 ? grid(rng) / 8.0 : u(rng);  // on the grid the boxes are aligned to
            d[k] = u(rng) - 0.5;
        }
        const int m = mode(rng);
        if (m < 3) d[static_cast<std::size_t>(m)] = r % 2 ? 0.0 : -0.0;  // along a face / axis
        if (d[0] == 0 && d[1] == 0 && d[2] == 0) d[2] = 1;
        const double t_max = r % 5 == 0 ? 0.6 : std::numeric_limits<double>::infinity();
        harness::ray_hit<double> hit;
        const bool h = index.intersect(o, d, t_max, hit);
        spatial::intersect_info<P> info;
        info.hit_time = t_max;
        const bool want = oracle.intersect(o, d, thickness, info);
        EXPECT_EQ(h, want) << "ray " << r;
        if (h && want) {
            EXPECT_EQ(hit.t, info.hit_time) << "ray " << r;
            // The reported object really is hit at that time.
            spatial::intersect_info<P> own;
            own.hit_time = t_max;
            EXPECT_TRUE(objects[hit.triangle].intersect(o, d, thickness, own)) << "ray " << r;
            EXPECT_EQ(own.hit_time, hit.t);
        }
        hits += want;
    }
    return hits;
}

TEST(embree_user_geometry, boxes_match_brute_force_exactly) {
    const std::uint64_t seed = spatial_test::test_seed(81);
    SCOPED_TRACE(spatial_test::replay_hint(seed));
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1), h(0.002, 0.05);
    std::uniform_int_distribution<int> grid(0, 7);
    std::vector<box3> boxes;
    for (int i = 0; i < 3000; ++i) {
        P lo, hi;
        for (std::size_t k = 0; k < 3; ++k) {
            if (i % 3 == 0) {  // grid-aligned boxes: faces shared with ray origins
                lo[k] = grid(rng) / 8.0;
                hi[k] = lo[k] + 0.125;
            } else {
                const double c = u(rng), r = h(rng);
                lo[k] = c - r;
                hi[k] = c + r;
            }
        }
        boxes.emplace_back(lo, hi);
    }
    auto index = harness::make_embree_box_ray_index();
    EXPECT_EQ(index->name(), "embree_user");
    EXPECT_GT(compare_with_brute_force(*index, boxes, 0.0, rng, 4000), 1000u);
    EXPECT_GT(compare_with_brute_force(*index, boxes, 0.01, rng, 1000), 300u);  // thick rays too
    EXPECT_GT(index->memory_bytes(), boxes.size() * sizeof(box3));
}

TEST(embree_user_geometry, points_with_thick_rays_match_brute_force_exactly) {
    const std::uint64_t seed = spatial_test::test_seed(82);
    SCOPED_TRACE(spatial_test::replay_hint(seed));
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<P> points;
    for (int i = 0; i < 5000; ++i) points.push_back(P{{u(rng), u(rng), u(rng)}});
    auto index = harness::make_embree_point_ray_index();
    EXPECT_GT(compare_with_brute_force(*index, points, 0.01, rng, 3000), 500u);
}

TEST(embree_user_geometry, empty_scene_and_far_origins) {
    auto index = harness::make_embree_box_ray_index();
    const std::vector<box3> none;
    index->build(none, 0.0);
    harness::ray_hit<double> hit;
    EXPECT_FALSE(index->intersect(P{{0, 0, 0}}, P{{1, 0, 0}}, 1e300, hit));
    const std::vector<box3> one{box3(P{{0, 0, 0}}, P{{1, 1, 1}})};
    index->build(one, 0.0);
    EXPECT_TRUE(index->intersect(P{{-5, 0.5, 0.5}}, P{{1, 0, 0}}, 1e300, hit));
    EXPECT_EQ(hit.t, 5.0);
    EXPECT_THROW(index->intersect(P{{-1e6, 0.5, 0.5}}, P{{1, 0, 0}}, 1e300, hit), std::invalid_argument);
}

}  // namespace

#else
TEST(embree_user_geometry, skipped_without_embree) { GTEST_SKIP() << "built without Embree"; }
#endif
