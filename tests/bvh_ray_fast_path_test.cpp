// The aabb ray path of spatial::bvh (per-ray inverse direction and signs, both children tested
// from the parent, triangle::prepared_ray) against brute_force, which calls O::intersect
// directly: hit times must be bit-identical, for triangles in 3D (double and float) and 2D,
// thin and thick rays (with and without a finite
// hit_time limit), directions with +0 / -0 components, origins on node boundaries and
// inside the scene, and after dynamic inserts, erases and updates.

#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "spatial/brute/brute_force.hpp"
#include "spatial/bvh/bvh.hpp"
#include "spatial/objects/triangle.hpp"
#include "test_support.hpp"

using namespace spatial;

namespace {

template <class T, std::size_t D>
objects::triangle<T, D> random_triangle(std::mt19937_64& rng, bool on_grid) {
    using P = point<T, D>;
    std::uniform_real_distribution<T> u(T(0), T(1));
    std::uniform_int_distribution<int> g(0, 8);
    std::uniform_real_distribution<T> size(T(0.02), T(0.2));
    P c, v[3];
    for (std::size_t i = 0; i < D; ++i) c[i] = u(rng);
    const T h = size(rng);
    for (auto& p : v)
        for (std::size_t i = 0; i < D; ++i)
            p[i] = on_grid ? static_cast<T>(g(rng)) / 8 : c[i] + h * (2 * u(rng) - 1);
    return objects::triangle<T, D>(v[0], v[1], v[2]);
}

// Bit-identical hit times, except that +0 and -0 are one time: an origin on several objects
// hits them all at t = 0 with either sign, and which of these ties is reported depends on
// the visiting order (the contract compares hit times, not identities).
template <class T>
bool same_time(T a, T b) { return a == b ? (a == 0 || std::memcmp(&a, &b, sizeof(T)) == 0) : false; }

// Casts many rays at tree and oracle and requires identical answers; returns the hit count.
template <class Tree, class Oracle>
std::size_t compare_rays(const Tree& tree, const Oracle& oracle, std::mt19937_64& rng, int rays) {
    using P = typename Tree::point_type;
    using T = typename Tree::scalar_type;
    constexpr std::size_t D = Tree::dimension;
    std::uniform_real_distribution<T> u(T(-0.5), T(1.5));
    std::uniform_int_distribution<int> grid(0, 8), mode(0, 7);
    std::size_t hits = 0;
    for (int r = 0; r < rays; ++r) {
        P o, d;
        for (std::size_t i = 0; i < D; ++i) {
            // Origins on the vertex grid (node boundaries) a quarter of the time.
            o[i] = r % 4 == 0 ? static_cast<T>(grid(rng)) / 8 : u(rng);
            d[i] = u(rng) - T(0.5);
        }
        const int m = mode(rng);
        if (m < static_cast<int>(D)) d[static_cast<std::size_t>(m)] = r % 2 ? T(0) : -T(0);
        if (m == 6) for (std::size_t i = 1; i < D; ++i) d[i] = -T(0);  // axis-parallel, -0 elsewhere
        bool nonzero = false;
        for (std::size_t i = 0; i < D; ++i) nonzero = nonzero || d[i] != 0;
        if (!nonzero) d[0] = 1;
        const T thickness = r % 6 == 0 ? T(0.01) : T(0);
        intersect_info<P> a, b;
        if (r % 5 == 0) a.hit_time = b.hit_time = T(0.7);  // a finite limit
        const auto it = tree.intersect_object(o, d, thickness, a);
        const bool hb = oracle.intersect(o, d, thickness, b);
        EXPECT_EQ(it != tree.end(), hb) << "ray " << r;
        EXPECT_TRUE(same_time(a.hit_time, b.hit_time)) << "ray " << r << ": " << a.hit_time << " vs " << b.hit_time;
        if (it != tree.end()) {
            intersect_info<P> own;  // the reported object really is hit at that time
            if (r % 5 == 0) own.hit_time = T(0.7);
            EXPECT_TRUE(it->intersect(o, d, thickness, own));
            EXPECT_TRUE(same_time(own.hit_time, a.hit_time));
        }
        hits += hb;
    }
    return hits;
}

template <class T, std::size_t D>
void run_fast_path_case(std::uint64_t seed) {
    using tri = objects::triangle<T, D>;
    std::mt19937_64 rng(seed);
    std::vector<tri> tris;
    for (int k = 0; k < 1500; ++k) tris.push_back(random_triangle<T, D>(rng, k % 3 == 0));
    bvh<tri> tree(tris.begin(), tris.end());
    brute_force<tri> oracle;
    oracle.insert(tris.begin(), tris.end());
    ASSERT_EQ(tree.check_invariants(), "");
    EXPECT_GT(compare_rays(tree, oracle, rng, 3000), 300u);

    // Dynamic updates: inserts, erases, moves; the ray path must follow.
    std::vector<typename bvh<tri>::iterator> handles;
    for (int k = 0; k < 300; ++k) {
        const tri t = random_triangle<T, D>(rng, k % 2 == 0);
        handles.push_back(tree.insert(t));
        oracle.insert(t);
    }
    for (int k = 0; k < 100; ++k) {
        const tri gone = *handles[static_cast<std::size_t>(k)];
        tree.erase(handles[static_cast<std::size_t>(k)]);
        oracle.erase(gone);
    }
    for (std::size_t k = 100; k < 200; ++k) {
        const tri old = *handles[k], moved = random_triangle<T, D>(rng, false);
        tree.update(handles[k], moved);
        oracle.erase(old);
        oracle.insert(moved);
    }
    ASSERT_EQ(tree.check_invariants(), "");
    ASSERT_EQ(tree.size(), oracle.size());
    EXPECT_GT(compare_rays(tree, oracle, rng, 3000), 300u);
}

}  // namespace

TEST(bvh_ray_fast_path, triangles_3d_double_match_brute_force_bit_for_bit) {
    const std::uint64_t seed = spatial_test::test_seed(31);
    SCOPED_TRACE(spatial_test::replay_hint(seed));
    run_fast_path_case<double, 3>(seed);
}

TEST(bvh_ray_fast_path, triangles_3d_float_match_brute_force_bit_for_bit) {
    const std::uint64_t seed = spatial_test::test_seed(32);
    SCOPED_TRACE(spatial_test::replay_hint(seed));
    run_fast_path_case<float, 3>(seed);
}

TEST(bvh_ray_fast_path, triangles_2d_match_brute_force_bit_for_bit) {
    const std::uint64_t seed = spatial_test::test_seed(33);
    SCOPED_TRACE(spatial_test::replay_hint(seed));
    run_fast_path_case<double, 2>(seed);
}

// The statistics stay meaningful on the fast path: a ray that hits visits nodes and tests
// objects; a ray that misses the root box visits nothing.
TEST(bvh_ray_fast_path, statistics_count_nodes_and_objects) {
    std::mt19937_64 rng(5);
    std::vector<objects::triangle<double, 3>> tris;
    for (int k = 0; k < 200; ++k) tris.push_back(random_triangle<double, 3>(rng, false));
    bvh<objects::triangle<double, 3>> tree(tris.begin(), tris.end());
    intersect_info<point<double, 3>> info;
    const bool hit = tree.intersect(point<double, 3>{{0.5, 0.5, -1}}, point<double, 3>{{0, 0, 1}}, 0.0, info);
    EXPECT_GT(tree.last_query_stats().nodes_visited, 0u);  // the root box spans the ray's path
    if (hit) {
        EXPECT_GT(tree.last_query_stats().objects_tested, 0u);
    }
    intersect_info<point<double, 3>> miss;
    EXPECT_FALSE(tree.intersect(point<double, 3>{{5, 5, 5}}, point<double, 3>{{1, 0, 0}}, 0.0, miss));
    EXPECT_EQ(tree.last_query_stats().nodes_visited, 0u);
    EXPECT_EQ(tree.last_query_stats().objects_tested, 0u);
}

// A subnormal direction component (1/d overflows) takes the generic path: same answers.
TEST(bvh_ray_fast_path, subnormal_direction_components_match_brute_force) {
    std::mt19937_64 rng(9);
    std::vector<objects::triangle<double, 3>> tris;
    for (int k = 0; k < 300; ++k) tris.push_back(random_triangle<double, 3>(rng, k % 2 == 0));
    bvh<objects::triangle<double, 3>> tree(tris.begin(), tris.end());
    brute_force<objects::triangle<double, 3>> oracle;
    oracle.insert(tris.begin(), tris.end());
    const double tiny = std::numeric_limits<double>::denorm_min() * 8;
    std::size_t hits = 0;
    for (int a = 0; a <= 8; ++a)
        for (int b = 0; b <= 8; ++b) {
            const point<double, 3> o{{a / 8.0, b / 8.0, -1}}, d{{tiny, -tiny, 1}};
            intersect_info<point<double, 3>> x, y;
            const bool hx = tree.intersect(o, d, 0.0, x), hy = oracle.intersect(o, d, 0.0, y);
            EXPECT_EQ(hx, hy);
            EXPECT_EQ(x.hit_time, y.hit_time);
            hits += hx;
        }
    EXPECT_GT(hits, 0u);
}
