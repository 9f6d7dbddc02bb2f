// The aabb ray paths of spatial::bvh against brute_force, which calls O::intersect directly:
//  * the wide layout (bvh/wide_ray_layout.hpp: 4- or 8-wide float nodes, objects in leaf
//    order), the default, and
//  * the binary path (per-ray inverse direction and signs, both children tested from the
//    parent, triangle::prepared_ray), Config::wide_ray_layout = false.
// Hit times must be bit-identical, for triangles in 3D (double and float) and 2D, thin and
// thick rays (with and without a finite hit_time limit), directions with +0 / -0
// components, origins on node boundaries and inside the scene, and after dynamic inserts,
// erases and updates, with the layout's leaves as copies (the default) and in place (after
// a bulk build, bvh_ray_leaves::in_place). Plus: the layout's life cycle (built lazily,
// dropped on change, shared by copies), concurrent first queries, and scenes beyond float's
// range.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <random>
#include <thread>
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

struct binary_rays : bvh_config<> {
    static constexpr bool wide_ray_layout = false;
};
struct four_wide_rays : bvh_config<> {
    static constexpr std::size_t wide_ray_width = 4;
};
struct leaves_in_place : bvh_config<> {
    static constexpr bvh_ray_leaves ray_leaves = bvh_ray_leaves::in_place;
};
struct four_wide_leaves_in_place : leaves_in_place {
    static constexpr std::size_t wide_ray_width = 4;
};
// The registry's bvh_in_place: leaves of up to 8 in place, the build's arrays fitted exactly.
struct eight_leaves_in_place_fitted : bvh_config<8> {
    static constexpr bvh_ray_leaves ray_leaves = bvh_ray_leaves::in_place;
    static constexpr bool build_headroom = false;
};
struct eight_wide_rays : bvh_config<> {
    static constexpr std::size_t wide_ray_width = 8;
};

// Whether a thin ray across the unit box was answered on the wide layout with its leaves in
// place (the container's objects tested where they are stored).
template <class Tree>
bool ray_leaves_in_place(const Tree& tree) {
    using P = typename Tree::point_type;
    using T = typename Tree::scalar_type;
    P o, d;
    for (std::size_t i = 0; i < Tree::dimension; ++i) o[i] = T(0.5), d[i] = T(0.125) * T(i);
    o[0] = T(-1);
    d[0] = T(1);
    intersect_info<P> info;
    (void)tree.intersect(o, d, T(0), info);
    EXPECT_EQ(tree.last_query_stats().wide_ray_layout, bool(Tree::config::wide_ray_layout));
    return tree.last_query_stats().wide_leaves_in_place;
}

template <class Config>
constexpr bool wants_leaves_in_place() {
    if constexpr (requires { Config::ray_leaves; }) return Config::wide_ray_layout && Config::ray_leaves == bvh_ray_leaves::in_place;
    else return false;
}

template <class T, std::size_t D, class Config = bvh_config<>>
void run_fast_path_case(std::uint64_t seed) {
    using tri = objects::triangle<T, D>;
    std::mt19937_64 rng(seed);
    std::vector<tri> tris;
    for (int k = 0; k < 1500; ++k) tris.push_back(random_triangle<T, D>(rng, k % 3 == 0));
    bvh<tri, aabb<T, D>, Config> tree(tris.begin(), tris.end());
    brute_force<tri> oracle;
    oracle.insert(tris.begin(), tris.end());
    ASSERT_EQ(tree.check_invariants(), "");
    EXPECT_GT(compare_rays(tree, oracle, rng, 3000), 300u);
    // A bulk build into an empty tree stores the objects in leaf order, so leaves in place
    // are possible (and taken when the configuration asks for them).
    EXPECT_EQ(ray_leaves_in_place(tree), wants_leaves_in_place<Config>());

    // Dynamic updates: inserts, erases, moves; the ray path must follow (a layout rebuilt
    // after them holds copies: the new objects' slots are not in leaf order).
    std::vector<typename bvh<tri, aabb<T, D>, Config>::iterator> handles;
    for (int k = 0; k < 300; ++k) {
        const tri t = random_triangle<T, D>(rng, k % 2 == 0);
        handles.push_back(tree.insert(t));
        oracle.insert(t);
    }
    for (int k = 0; k < 100; ++k) {
        const tri gone = *handles[static_cast<std::size_t>(k)];
        tree.erase(handles[static_cast<std::size_t>(k)]);
        oracle.erase(oracle.find(gone));  // one copy: grid triangles can repeat
    }
    for (std::size_t k = 100; k < 200; ++k) {
        const tri old = *handles[k], moved = random_triangle<T, D>(rng, false);
        tree.update(handles[k], moved);
        oracle.erase(oracle.find(old));
        oracle.insert(moved);
    }
    ASSERT_EQ(tree.check_invariants(), "");
    ASSERT_EQ(tree.size(), oracle.size());
    EXPECT_GT(compare_rays(tree, oracle, rng, 3000), 300u);
    EXPECT_FALSE(ray_leaves_in_place(tree));
}

}  // namespace

TEST(bvh_ray_fast_path, triangles_3d_double_match_brute_force_bit_for_bit) {
    const spatial_test::logged_seed seed(31);
    run_fast_path_case<double, 3>(seed);
}

TEST(bvh_ray_fast_path, triangles_3d_float_match_brute_force_bit_for_bit) {
    const spatial_test::logged_seed seed(32);
    run_fast_path_case<float, 3>(seed);
}

TEST(bvh_ray_fast_path, triangles_2d_match_brute_force_bit_for_bit) {
    const spatial_test::logged_seed seed(33);
    run_fast_path_case<double, 2>(seed);
}

TEST(bvh_ray_fast_path, binary_path_3d_double_matches_brute_force_bit_for_bit) {
    const spatial_test::logged_seed seed(34);
    run_fast_path_case<double, 3, binary_rays>(seed);
}

TEST(bvh_ray_fast_path, four_and_eight_wide_layouts_match_brute_force_bit_for_bit) {
    const spatial_test::logged_seed seed(35);
    run_fast_path_case<double, 3, four_wide_rays>(seed);
    run_fast_path_case<float, 3, eight_wide_rays>(seed);
    run_fast_path_case<float, 2, four_wide_rays>(seed);
}

TEST(bvh_ray_fast_path, leaves_in_place_match_brute_force_bit_for_bit) {
    const spatial_test::logged_seed seed(36);
    run_fast_path_case<double, 3, leaves_in_place>(seed);
    run_fast_path_case<float, 3, leaves_in_place>(seed);
    run_fast_path_case<double, 2, four_wide_leaves_in_place>(seed);
    run_fast_path_case<double, 3, eight_leaves_in_place_fitted>(seed);
}

// With leaves in place a bulk-built tree's layout is its wide nodes alone (128 bytes each,
// fewer than one per 4 triangles): no copies. After insertions, whose slots are out of leaf
// order, the rebuilt layout holds copies again, at least the vertices and id per triangle.
TEST(bvh_ray_fast_path, leaves_in_place_keep_no_copies_until_a_change) {
    using tri = objects::triangle<double, 3>;
    std::mt19937_64 rng(12);
    std::vector<tri> tris;
    for (int k = 0; k < 400; ++k) tris.push_back(random_triangle<double, 3>(rng, false));
    bvh<tri, aabb<double, 3>, leaves_in_place> tree(tris.begin(), tris.end());
    const std::size_t bare = tree.memory_bytes();
    tree.prepare_rays();
    EXPECT_GT(tree.memory_bytes(), bare) << "the layout has nodes";
    EXPECT_LT(tree.memory_bytes(), bare + 400 * 32) << "the layout copied triangles it could test in place";
    EXPECT_TRUE(ray_leaves_in_place(tree));
    for (int k = 0; k < 20; ++k) tree.insert(random_triangle<double, 3>(rng, false));
    const std::size_t changed = tree.memory_bytes();
    tree.prepare_rays();
    EXPECT_GT(tree.memory_bytes(), changed + 420 * (3 * sizeof(point<double, 3>) + 4));
    EXPECT_FALSE(ray_leaves_in_place(tree));
}

// A parallel bulk build (insert(first, last, par)) is the sequential tree node for node, so
// it stores the objects in the same leaf order, takes the same memory with its arrays fitted
// exactly, and its layout tests them in place with the same answers.
TEST(bvh_ray_fast_path, leaves_in_place_after_a_parallel_build_are_the_sequential_trees) {
    const spatial_test::logged_seed seed(37);
    using tri = objects::triangle<double, 3>;
    std::mt19937_64 rng(seed);
    std::vector<tri> tris;
    for (int k = 0; k < 5000; ++k) tris.push_back(random_triangle<double, 3>(rng, k % 3 == 0));
    using tree_type = bvh<tri, aabb<double, 3>, eight_leaves_in_place_fitted>;
    tree_type sequential(tris.begin(), tris.end());
    tree_type parallel;
    parallel.insert(tris.begin(), tris.end(), par);
    ASSERT_EQ(parallel.check_invariants(), "");
    EXPECT_TRUE(std::equal(sequential.begin(), sequential.end(), parallel.begin(), parallel.end()))
        << "the same objects in the same slot order";
    sequential.prepare_rays();
    parallel.prepare_rays(par);
    EXPECT_EQ(parallel.memory_bytes(), sequential.memory_bytes());
    EXPECT_TRUE(ray_leaves_in_place(sequential));
    EXPECT_TRUE(ray_leaves_in_place(parallel));
    brute_force<tri> oracle;
    oracle.insert(tris.begin(), tris.end());
    EXPECT_GT(compare_rays(parallel, oracle, rng, 3000), 300u);
}

// The layout is built by the first ray cast (or prepare_rays), used by the casts that
// follow, dropped by any change and rebuilt; copies share it and drop their share alone.
TEST(bvh_ray_fast_path, wide_layout_life_cycle) {
    using tri = objects::triangle<double, 3>;
    std::mt19937_64 rng(11);
    std::vector<tri> tris;
    for (int k = 0; k < 400; ++k) tris.push_back(random_triangle<double, 3>(rng, false));
    bvh<tri> tree(tris.begin(), tris.end());
    brute_force<tri> oracle;
    oracle.insert(tris.begin(), tris.end());
    const std::size_t bare = tree.memory_bytes();
    tree.prepare_rays();
    const std::size_t prepared = tree.memory_bytes();
    // Triangles keep only their vertices (a compact ray form) and a 32-bit id in the layout.
    EXPECT_GT(prepared, bare + 400 * (3 * sizeof(point<double, 3>) + 4)) << "the layout stores every triangle";
    const point<double, 3> o{{0.5, 0.5, -1}}, d{{0.01, -0.02, 1}};
    intersect_info<point<double, 3>> a, b;
    EXPECT_EQ(tree.intersect(o, d, 0.0, a), oracle.intersect(o, d, 0.0, b));
    EXPECT_TRUE(tree.last_query_stats().wide_ray_layout);
    EXPECT_EQ(a.hit_time, b.hit_time);

    bvh<tri> copy = tree;  // shares the layout
    const tri extra = random_triangle<double, 3>(rng, false);
    copy.insert(extra);  // drops the copy's share only
    EXPECT_EQ(tree.memory_bytes(), prepared);
    // The copy no longer holds a layout: preparing its own adds at least one per triangle.
    // (Its tree alone may have grown: the insert can split a full leaf.)
    const std::size_t copy_bare = copy.memory_bytes();
    copy.prepare_rays();
    EXPECT_GT(copy.memory_bytes(), copy_bare + 401 * (3 * sizeof(point<double, 3>) + 4));

    // The original still answers from its layout; the copy rebuilds its own on demand and
    // sees the new triangle.
    brute_force<tri> oracle2 = oracle;
    oracle2.insert(extra);
    for (int r = 0; r < 200; ++r) {
        std::uniform_real_distribution<double> u(-0.2, 1.2);
        const point<double, 3> ro{{u(rng), u(rng), -1}}, rd{{u(rng) - 0.5, u(rng) - 0.5, 1}};
        intersect_info<point<double, 3>> x, y, z, w;
        EXPECT_EQ(tree.intersect(ro, rd, 0.0, x), oracle.intersect(ro, rd, 0.0, y));
        EXPECT_EQ(x.hit_time, y.hit_time);
        EXPECT_EQ(copy.intersect(ro, rd, 0.0, z), oracle2.intersect(ro, rd, 0.0, w));
        EXPECT_TRUE(copy.last_query_stats().wide_ray_layout);
        EXPECT_EQ(z.hit_time, w.hit_time);
    }
    EXPECT_GT(copy.memory_bytes(), bare);
    copy.clear();
    intersect_info<point<double, 3>> none;
    EXPECT_FALSE(copy.intersect(o, d, 0.0, none));
}

// Many threads casting the first rays after a change build the layout once, race-free
// (ASan/UBSan builds run this too), and all get the oracle's answers.
TEST(bvh_ray_fast_path, concurrent_first_queries_share_one_layout) {
    using tri = objects::triangle<double, 3>;
    std::mt19937_64 rng(13);
    std::vector<tri> tris;
    for (int k = 0; k < 2000; ++k) tris.push_back(random_triangle<double, 3>(rng, k % 4 == 0));
    bvh<tri> tree(tris.begin(), tris.end());
    brute_force<tri> oracle;
    oracle.insert(tris.begin(), tris.end());
    struct ray_case {
        point<double, 3> o, d;
        double expected;
    };
    std::vector<ray_case> rays;
    std::uniform_real_distribution<double> u(-0.2, 1.2);
    for (int r = 0; r < 400; ++r) {
        ray_case c{{{u(rng), u(rng), -1}}, {{u(rng) - 0.5, u(rng) - 0.5, 1}}, 0};
        intersect_info<point<double, 3>> info;
        oracle.intersect(c.o, c.d, 0.0, info);
        c.expected = info.hit_time;
        rays.push_back(c);
    }
    for (int round = 0; round < 3; ++round) {
        tree.erase(tree.insert(random_triangle<double, 3>(rng, false)));  // drops the layout
        ASSERT_EQ(tree.size(), tris.size());
        std::vector<int> wrong(4, 0);
        std::vector<std::thread> threads;
        for (int t = 0; t < 4; ++t)
            threads.emplace_back([&, t] {
                for (std::size_t r = static_cast<std::size_t>(t); r < rays.size(); r += 2) {
                    intersect_info<point<double, 3>> info;
                    tree.intersect(rays[r].o, rays[r].d, 0.0, info);
                    if (!(info.hit_time == rays[r].expected)) ++wrong[static_cast<std::size_t>(t)];
                }
            });
        for (auto& th : threads) th.join();
        for (int w : wrong) EXPECT_EQ(w, 0) << "round " << round;
    }
}

// Scenes beyond float's comfortable range (|x| ~ 1e35) and rays with direction components
// below 1e-30 are refused by the layout and answered by the double path: same answers.
TEST(bvh_ray_fast_path, scenes_and_rays_beyond_float_range_fall_back_exactly) {
    using tri = objects::triangle<double, 3>;
    using P = point<double, 3>;
    std::mt19937_64 rng(17);
    for (const double scale : {1e35, 1e-35, 1.0}) {
        std::vector<tri> tris;
        for (int k = 0; k < 300; ++k) {
            tri t = random_triangle<double, 3>(rng, k % 2 == 0);
            P v[3] = {t.vertex(0), t.vertex(1), t.vertex(2)};
            for (auto& p : v)
                for (std::size_t i = 0; i < 3; ++i) p[i] *= scale;
            tris.push_back(tri(v[0], v[1], v[2]));
        }
        bvh<tri> tree(tris.begin(), tris.end());
        brute_force<tri> oracle;
        oracle.insert(tris.begin(), tris.end());
        std::size_t hits = 0;
        std::uniform_real_distribution<double> u(-0.2, 1.2);
        for (int r = 0; r < 300; ++r) {
            const P o{{u(rng) * scale, u(rng) * scale, -scale}};
            P d{{u(rng) - 0.5, u(rng) - 0.5, 1}};
            if (r % 3 == 0) d[0] = 1e-31;  // below the layout's direction range
            intersect_info<P> a, b;
            const bool ha = tree.intersect(o, d, 0.0, a), hb = oracle.intersect(o, d, 0.0, b);
            EXPECT_EQ(ha, hb) << "scale " << scale << " ray " << r;
            EXPECT_EQ(a.hit_time, b.hit_time) << "scale " << scale << " ray " << r;
            // Tiny scenes stay within float's normal range: only 1e35 and the 1e-31
            // direction component are refused.
            EXPECT_EQ(tree.last_query_stats().wide_ray_layout, scale != 1e35 && r % 3 != 0);
            hits += ha;
        }
        EXPECT_GT(hits, 20u) << "scale " << scale;
    }
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
