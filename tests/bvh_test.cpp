// spatial::bvh, part 1: differential tests against brute force for aabb, sphere and kdop<18>
// volumes over points and boxes (both builders), the hard numerical cases, bad input,
// the traversal stack, rebuild policy and statistics. Part 2 (bvh_volumes_test.cpp): obb,
// ellipsoid, convex_hull, 2D and float, the other object types, and the contract suite.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "bvh_test_support.hpp"
#include "spatial/bvh/traversal_stack.hpp"

using namespace spatial;
using bvh_test::differential;

namespace {

using spatial_test::B3, spatial_test::P3;

template <class Tree>
class bvh_differential : public ::testing::Test {};

// The sanitizer build runs a representative subset (CI time: SPATIAL_TEST_FULL_MATRIX=0): every
// structure, scalar, dimension and object kind still appears; the release build runs them all.
#if SPATIAL_TEST_FULL_MATRIX
using part1_trees = ::testing::Types<
    bvh<P3, aabb<double, 3>, bvh_sah_config<>>, bvh<P3, aabb<double, 3>, bvh_median_config<8>>,
    bvh<B3, aabb<double, 3>, bvh_sah_config<>>, bvh<B3, aabb<double, 3>, bvh_median_config<2>>,
    bvh<P3, sphere<double, 3>, bvh_sah_config<>>, bvh<B3, sphere<double, 3>, bvh_median_config<>>,
    bvh<P3, kdop<double, 3, 18>, bvh_median_config<>>, bvh<B3, kdop<double, 3, 18>, bvh_sah_config<4, 32>>>;
#else
using part1_trees = ::testing::Types<bvh<P3, aabb<double, 3>, bvh_sah_config<>>, bvh<B3, aabb<double, 3>, bvh_median_config<2>>,
                                     bvh<B3, sphere<double, 3>, bvh_median_config<>>,
                                     bvh<B3, kdop<double, 3, 18>, bvh_sah_config<4, 32>>>;
#endif
TYPED_TEST_SUITE(bvh_differential, part1_trees);

TYPED_TEST(bvh_differential, matches_brute_force_under_interleaved_updates_and_motion) {
    for (std::uint64_t seed : {1u, 2u, 3u}) differential<TypeParam>(spatial_test::test_seed(seed * 7919), 300, 6);
}
TYPED_TEST(bvh_differential, matches_brute_force_at_huge_and_tiny_scales) {
    differential<TypeParam>(spatial_test::test_seed(11), 200, 2, 1e15, 1e15);    // 1e15 coordinates
    differential<TypeParam>(spatial_test::test_seed(12), 200, 2, 0, 1e-15);      // 1e-15 extents
    differential<TypeParam>(spatial_test::test_seed(13), 200, 2, 1e8, 1e-4);     // offset 1e8
}
TYPED_TEST(bvh_differential, small_trees_and_single_objects) {
    for (std::size_t n : {0u, 1u, 2u, 5u}) differential<TypeParam>(spatial_test::test_seed(100 + n), n, 3);
}

// ---------------------------------------------------------------- hard cases, per volume
template <class Tree>
class bvh_hard_cases : public ::testing::Test {};
using hard_trees = ::testing::Types<bvh<P3, aabb<double, 3>>, bvh<P3, sphere<double, 3>, bvh_median_config<>>,
                                    bvh<P3, kdop<double, 3, 14>>, bvh<P3, obb<double, 3>>,
                                    bvh<P3, ellipsoid<double, 3>>, bvh<P3, convex_hull<double, 3>>,
                                    bvh<point<float, 3>, kdop<float, 3, 26>>>;
TYPED_TEST_SUITE(bvh_hard_cases, hard_trees);

// Integer lattice points: every node boundary passes through stored points, and axis-parallel
// rays with zero / negative-zero components run exactly along lattice lines and node faces.
TYPED_TEST(bvh_hard_cases, axis_rays_along_lattice_lines_and_node_faces_find_every_hit) {
    using Pt = typename TypeParam::value_type;
    using T = typename TypeParam::scalar_type;
    TypeParam tree;
    brute_force<Pt> oracle;
    std::vector<Pt> pts;
    for (int x = 0; x < 6; ++x)
        for (int y = 0; y < 6; ++y)
            for (int z = 0; z < 6; ++z) pts.push_back(Pt{{T(x), T(y), T(z)}});
    tree.insert(pts.begin(), pts.end());
    oracle.insert(pts.begin(), pts.end());
    int hits = 0;
    const T zeros[2] = {T(0.0), T(-0.0)};
    for (int axis = 0; axis < 3; ++axis)
        for (int sgn : {-1, 1})
            for (int a = 0; a < 6; ++a)
                for (int b = 0; b < 6; ++b)
                    for (T z : zeros) {
                        Pt o{}, d{};
                        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
                        o[axis] = sgn > 0 ? T(-2) : T(8);
                        o[u] = T(a);
                        o[v] = T(b);
                        d[axis] = T(sgn);
                        d[u] = z;
                        d[v] = -z;
                        intersect_info<Pt> i1, i2;
                        const bool h1 = tree.intersect(o, d, T(0), i1), h2 = oracle.intersect(o, d, T(0), i2);
                        ASSERT_EQ(h1, h2);
                        ASSERT_EQ(i1.hit_time, i2.hit_time);
                        hits += h1;
                    }
    EXPECT_EQ(hits, 3 * 2 * 36 * 2);  // every lattice line is hit
    // Origins ON stored points (and so on node boundaries), oblique directions.
    for (const Pt& p : pts) {
        intersect_info<Pt> info;
        const Pt d{{T(0.3), T(-0.0), T(-1)}};
        ASSERT_TRUE(tree.intersect(p, d, T(0), info));
        EXPECT_EQ(info.hit_time, T(0));
    }
}

TYPED_TEST(bvh_hard_cases, all_objects_identical) {
    using Pt = typename TypeParam::value_type;
    using T = typename TypeParam::scalar_type;
    const Pt same{{T(0.25), T(-3), T(7)}};
    std::vector<Pt> pts(300, same);
    TypeParam tree(pts.begin(), pts.end());
    ASSERT_EQ(tree.check_invariants(), "");
    EXPECT_LE(tree.height(), 12u) << "identical objects must still give a balanced tree";
    const auto nn = tree.find_nearest(Pt{{T(1), T(1), T(1)}}, 7);
    ASSERT_EQ(nn.size(), 7u);
    for (const auto& it : nn) EXPECT_EQ(*it, same);
    intersect_info<Pt> info;
    const Pt o{{T(0.25), T(-3), T(5)}}, d{{T(0), T(-0.0), T(1)}};
    ASSERT_TRUE(tree.intersect(o, d, T(0), info));
    EXPECT_EQ(info.hit_time, T(2));
    EXPECT_EQ(tree.find_in_ball(same, T(0)).size(), 300u);
    EXPECT_EQ(tree.count(same), 300u);
    for (int i = 0; i < 50; ++i) tree.insert(same);  // incremental inserts into identical leaves
    ASSERT_EQ(tree.check_invariants(), "");
    EXPECT_EQ(tree.erase(same), 350u);
    EXPECT_TRUE(tree.empty());
    ASSERT_EQ(tree.check_invariants(), "");
}

TYPED_TEST(bvh_hard_cases, bad_input_throws_and_leaves_contents_unchanged) {
    using Pt = typename TypeParam::value_type;
    using T = typename TypeParam::scalar_type;
    const T nan = std::numeric_limits<T>::quiet_NaN(), inf = std::numeric_limits<T>::infinity();
    std::vector<Pt> pts;
    for (int i = 0; i < 40; ++i) pts.push_back(Pt{{T(i), T(i % 7), T(i % 3)}});
    TypeParam tree(pts.begin(), pts.end());
    const auto before = bvh_test::signatures_of(bvh_test::all_iterators(tree));
    const Pt good{{1, 2, 3}}, bad{{1, nan, 3}}, zero{{0, T(-0.0), 0}};
    intersect_info<Pt> info;
    EXPECT_THROW(tree.insert(bad), std::invalid_argument);
    EXPECT_THROW(tree.insert(tree.begin(), Pt{{inf, 0, 0}}), std::invalid_argument);
    std::vector<Pt> batch{good, good, bad, good};
    EXPECT_THROW(tree.insert(batch.begin(), batch.end()), std::invalid_argument);
    EXPECT_THROW((void)tree.erase(bad), std::invalid_argument);
    EXPECT_THROW((void)tree.find(bad), std::invalid_argument);
    EXPECT_THROW((void)tree.count(bad), std::invalid_argument);
    EXPECT_THROW((void)tree.intersect(bad, good, info), std::invalid_argument);
    EXPECT_THROW((void)tree.intersect(good, zero, info), std::invalid_argument);
    EXPECT_THROW((void)tree.intersect(good, bad, info), std::invalid_argument);
    EXPECT_THROW((void)tree.intersect(good, good, T(-1), info), std::invalid_argument);
    EXPECT_THROW((void)tree.intersect(good, good, nan, info), std::invalid_argument);
    EXPECT_THROW(tree.set_ray_thickness(T(-0.5)), std::invalid_argument);
    EXPECT_THROW((void)tree.find_nearest(bad, 3), std::invalid_argument);
    EXPECT_THROW((void)tree.find_nearest(good, 3, T(-1)), std::invalid_argument);
    EXPECT_THROW((void)tree.find_in_ball(good, T(-1)), std::invalid_argument);
    EXPECT_THROW((void)tree.find_in_ball(bad, T(1)), std::invalid_argument);
    EXPECT_THROW((void)tree.find_in_box(bad, good), std::invalid_argument);
    EXPECT_THROW((void)tree.update(tree.begin(), bad), std::invalid_argument);
    EXPECT_THROW((void)tree.update(tree.end(), good), std::invalid_argument);
    try {
        tree.intersect(good, zero, info);
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("bvh::intersect"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("zero"), std::string::npos) << e.what();
    }
    EXPECT_EQ(tree.size(), pts.size());
    EXPECT_EQ(bvh_test::signatures_of(bvh_test::all_iterators(tree)), before);
    EXPECT_EQ(tree.check_invariants(), "");
}

// ---------------------------------------------------------------- structure and policies
TEST(bvh_structure, traversal_stack_spills_to_the_heap_and_keeps_lifo_order) {
    bvh_detail::traversal_stack<int, 4> s;
    for (int i = 0; i < 1000; ++i) s.push(i);
    EXPECT_EQ(s.size(), 1000u);
    for (int i = 999; i >= 0; --i) ASSERT_EQ(s.pop(), i);
    EXPECT_TRUE(s.empty());
}

struct no_rebuild : bvh_config<2, bvh_build_method::median_split> {
    static constexpr double rebuild_factor = 1e9;
};

TEST(bvh_structure, deep_trees_from_sorted_incremental_inserts_are_traversed_without_overflow) {
    // Points inserted one by one along a line, with no rebuild (a huge rebuild threshold):
    // the greedy insertion makes a deep tree; every query must still be right.
    bvh<P3, aabb<double, 3>, no_rebuild> tree;
    brute_force<P3> oracle;
    for (int i = 0; i < 3000; ++i) {
        const P3 p{{std::ldexp(1.0, i % 200 - 100), 0.5 * i, 0}};
        tree.insert(p);
        oracle.insert(p);
    }
    EXPECT_EQ(tree.full_rebuilds(), 0u);
    ASSERT_EQ(tree.check_invariants(), "");
    const P3 q{{0, 700, 0}};
    EXPECT_EQ(spatial_test::distances_from(q, tree.find_nearest(q, 20)),
              spatial_test::distances_from(q, oracle.find_nearest(q, 20)));
    intersect_info<P3> a, b;
    const P3 o{{0, -1, 0}}, d{{0, 1, -0.0}};
    EXPECT_EQ(tree.intersect(o, d, 0.25, a), oracle.intersect(o, d, 0.25, b));
    EXPECT_EQ(a.hit_time, b.hit_time);
}

TEST(bvh_structure, rebuilds_happen_at_geometrically_growing_sizes) {
    bvh<P3> tree;
    bvh_test::scene_source<P3> g(spatial_test::test_seed(5));
    for (int i = 0; i < 4000; ++i) tree.insert(g.object());
    // thresholds 32 -> 65 -> 131 -> ... : about log2(4000 / 32) + 1 rebuilds
    EXPECT_GE(tree.full_rebuilds(), 5u);
    EXPECT_LE(tree.full_rebuilds(), 10u);
    EXPECT_EQ(tree.check_invariants(), "");
}

// Config::build_headroom = false (the registry's bvh_in_place): the same tree as the default,
// node for node, with its node and leaf-block arrays fitted exactly instead of an eighth spare,
// so it takes less memory by at least an eighth of its nodes' boxes; it still takes updates.
struct exact_fit_config : bvh_config<> {
    static constexpr bool build_headroom = false;
};
TEST(bvh_structure, a_build_without_headroom_fits_its_arrays_exactly_and_still_takes_updates) {
    bvh_test::scene_source<B3> g(spatial_test::test_seed(8));
    std::vector<B3> boxes;
    for (int i = 0; i < 20000; ++i) boxes.push_back(g.object());
    const bvh<B3> spare(boxes.begin(), boxes.end());
    for (const bool parallel : {false, true}) {
        bvh<B3, aabb<double, 3>, exact_fit_config> exact;
        if (parallel) exact.insert(boxes.begin(), boxes.end(), par);
        else exact.insert(boxes.begin(), boxes.end());
        const char* how = parallel ? "parallel build" : "sequential build";
        ASSERT_EQ(exact.check_invariants(), "") << how;
        EXPECT_EQ(exact.node_count(), spare.node_count()) << how << ": the same build";
        EXPECT_EQ(exact.height(), spare.height()) << how;
        const std::size_t box_bytes = sizeof(aabb<double, 3>);
        EXPECT_GE(spare.memory_bytes(), exact.memory_bytes() + spare.node_count() / 8 * box_bytes)
            << how << ": the spare eighth of the node array is gone";
        // Updates after the build grow the arrays as usual.
        std::vector<B3> more;
        for (int i = 0; i < 500; ++i) more.push_back(g.object());
        for (const B3& b : more) exact.insert(b);
        EXPECT_EQ(exact.check_invariants(), "") << how;
        EXPECT_EQ(exact.size(), boxes.size() + more.size()) << how;
        // The source repeats a few objects: each is counted as often as it was inserted.
        auto inserted = [&](const B3& x) {
            return static_cast<std::size_t>(std::count(boxes.begin(), boxes.end(), x) + std::count(more.begin(), more.end(), x));
        };
        for (std::size_t i = 0; i < boxes.size(); i += 97) EXPECT_EQ(exact.count(boxes[i]), inserted(boxes[i])) << how;
        for (const B3& b : more) EXPECT_EQ(exact.count(b), inserted(b)) << how;
    }
}

TEST(bvh_structure, sah_point_trees_fill_half_their_leaves_instead_of_splitting_to_single_points) {
    // A point's box has no area: counted per point, the SAH finds every split of two points
    // cheaper than their leaf and makes 2n - 1 nodes. Half a leaf of points counts as one
    // test (bvh::sah_block), so a uniform set of points makes leaves of about leaf_size / 2
    // points: between n / 3 and 0.75 n nodes for the default leaves of 8 (an average leaf of
    // 2.6 to 6 points), and under 1.5 n for leaves of 4 (above 1.3 points).
    bvh_test::scene_source<P3> g(spatial_test::test_seed(7));
    std::vector<P3> pts;
    for (int i = 0; i < 20000; ++i) pts.push_back(g.object());
    const double n = static_cast<double>(pts.size());
    auto check = [&](const auto& tree, double fewest, double most, const char* what) {
        EXPECT_EQ(tree.check_invariants(), "") << what;
        EXPECT_GT(static_cast<double>(tree.node_count()), fewest * n) << what << ": leaves left no room for insertions";
        EXPECT_LT(static_cast<double>(tree.node_count()), most * n) << what;
    };
    static_assert(bvh<P3>::leaf_size == 8 && bvh<B3>::leaf_size == 4);
    check(bvh<P3>(pts.begin(), pts.end()), 1.0 / 3, 0.75, "aabb");
    check(bvh<P3, sphere<double, 3>>(pts.begin(), pts.end()), 1.0 / 3, 0.75, "sphere");
    check(bvh<P3, aabb<double, 3>, bvh_sah_config<4>>(pts.begin(), pts.end()), 0.0, 1.5, "aabb, leaves of 4");
    // Insertions into the built tree fill the free half of its leaves: a batch of a fifth of
    // the tree splits few of them.
    bvh<P3> grown(pts.begin(), pts.begin() + 10000);
    const std::size_t builds = grown.full_rebuilds(), nodes = grown.node_count();
    grown.insert(pts.begin() + 10000, pts.begin() + 12000);
    EXPECT_EQ(grown.full_rebuilds(), builds) << "a batch of a fifth is placed, not rebuilt";
    EXPECT_EQ(grown.check_invariants(), "");
    EXPECT_LT(grown.node_count() - nodes, 2000u / 4) << "most of the 2000 insertions found room in their leaf";
}

TEST(bvh_structure, ray_queries_prune_and_report_nodes_visited) {
    bvh_test::scene_source<P3> g(spatial_test::test_seed(6));
    std::vector<P3> pts;
    for (int i = 0; i < 20000; ++i) pts.push_back(g.object());
    for (const bool sah : {true, false}) {
        std::size_t visited = 0, nodes = 0;
        auto run = [&](const auto& tree) {
            nodes = tree.node_count();
            for (int r = 0; r < 50; ++r) {
                intersect_info<P3> info;
                (void)tree.intersect(g.point_in(0, 1), g.direction(), 0.002, info);
                visited += tree.last_query_stats().nodes_visited;
                EXPECT_GT(tree.last_query_stats().nodes_visited, 0u);
            }
        };
        if (sah) run(bvh<P3, aabb<double, 3>, bvh_sah_config<>>(pts.begin(), pts.end()));
        else run(bvh<P3, aabb<double, 3>, bvh_median_config<>>(pts.begin(), pts.end()));
        EXPECT_LT(static_cast<double>(visited) / 50, 0.05 * static_cast<double>(nodes)) << (sah ? "sah" : "median");
    }
}

TEST(bvh_structure, move_leaves_an_empty_usable_tree_and_copies_are_independent) {
    bvh_test::scene_source<B3> g(spatial_test::test_seed(8));
    std::vector<B3> v;
    for (int i = 0; i < 100; ++i) v.push_back(g.object());
    bvh<B3, sphere<double, 3>> a(v.begin(), v.end());
    auto copy = a;
    auto moved = std::move(a);
    EXPECT_TRUE(a.empty());
    EXPECT_EQ(a.check_invariants(), "");
    a.insert(v[0]);
    EXPECT_EQ(a.size(), 1u);
    copy.erase(copy.begin());
    EXPECT_EQ(copy.size(), 99u);
    EXPECT_EQ(moved.size(), 100u);
    EXPECT_EQ(moved.check_invariants(), "");
    EXPECT_EQ(copy.check_invariants(), "");
    EXPECT_GT(moved.memory_bytes(), 100 * sizeof(B3));
}

// The empty tree holds no node until the first insertion (the "unallocated" state that makes
// the default constructor and the moves noexcept): it owns no heap memory, and every query,
// statistic, motion and ray form (the wide layout's too) works on it. A cleared tree returns
// to it; a rebuild or the first insertion gives it its root.
// never_filled: the vectors have no capacity either (a cleared tree keeps its capacities).
template <class Tree>
void expect_unallocated(const Tree& t, const std::string& state, bool never_filled = true) {
    using Q = typename Tree::point_type;
    const std::size_t bytes = t.memory_bytes();
    if (never_filled) { EXPECT_EQ(bytes, sizeof(Tree)) << state; }
    EXPECT_EQ(t.node_count(), 0u) << state;
    EXPECT_EQ(t.height(), 0u) << state;
    EXPECT_EQ(t.quality(), 1.0) << state;
    EXPECT_EQ(t.node_surface_areas(), (std::pair<double, double>{0, 0})) << state;
    EXPECT_TRUE(t.root_volume().is_empty()) << state;
    EXPECT_EQ(t.check_invariants(), "") << state;
    t.prepare_rays();
    EXPECT_EQ(t.memory_bytes(), bytes) << state << ": no ray layout for no objects";
    const std::vector<ray<Q>> rays{{Q{{-1, 0.5, 0.5}}, Q{{1, 0, 0}}, 0.1}, {Q{{0.5, -1, 0.5}}, Q{{0, 1, 0}}, 0}};
    std::vector<typename Tree::iterator> hits(rays.size());
    std::vector<intersect_info<Q>> infos(rays.size());
    t.intersect_batch(std::span<const ray<Q>>(rays), std::span<typename Tree::iterator>(hits),
                      std::span<intersect_info<Q>>(infos), par);
    for (const auto& h : hits) EXPECT_TRUE(h == t.end()) << state;
}

template <class Tree>
void empty_state_round_trip() {
    using O = typename Tree::value_type;
    static_assert(std::is_nothrow_default_constructible_v<Tree> && std::is_nothrow_move_constructible_v<Tree> &&
                  std::is_nothrow_move_assignable_v<Tree>);
    bvh_test::scene_source<O> g(spatial_test::test_seed(20));
    std::vector<O> v;
    for (int i = 0; i < 300; ++i) v.push_back(g.object());
    Tree fresh;
    expect_unallocated(fresh, "default-constructed");
    fresh.refit();  // nothing to refit: stays without nodes
    expect_unallocated(fresh, "refitted");
    std::vector<std::pair<typename Tree::iterator, O>> no_moves;
    EXPECT_EQ(fresh.update(no_moves.begin(), no_moves.end(), motion_strategy::rebuild), motion_strategy::rebuild);
    expect_unallocated(fresh, "after a batch of no moves");
    Tree full(v.begin(), v.end());
    const Tree copy = full;
    intersect_info<typename Tree::point_type> info;
    (void)full.intersect(g.point_in(0, 1), g.direction(), 0.01, info);  // builds the ray layout (aabb)
    Tree target(std::move(full));
    expect_unallocated(full, "moved from");  // NOLINT(bugprone-use-after-move)
    EXPECT_TRUE(full.pairs_with(target).empty());
    EXPECT_TRUE(target.pairs_with(full).empty());
    EXPECT_EQ(spatial_test::signature_pairs(target.self_pairs()), spatial_test::signature_pairs(copy.self_pairs()));
    // The target answers with the source's nodes and ray layout.
    brute_force<O> oracle(v.begin(), v.end());
    bvh_test::compare_queries(target, oracle, g, 60);
    // The moved-from tree grows again, by each path that allocates the root.
    full.insert(full.end(), v[0]);
    EXPECT_EQ(full.node_count(), 1u);
    full.insert(v.begin() + 1, v.begin() + 50);
    for (std::size_t i = 50; i < 80; ++i) full.insert(v[i]);
    EXPECT_EQ(full.check_invariants(), "");
    brute_force<O> first80(v.begin(), v.begin() + 80);
    bvh_test::compare_queries(full, first80, g, 60);
    // Motion on it: a path refit, a reinsert, batches with each strategy.
    auto it = full.begin();
    const O moved = g.moved(*it);
    full.update(it, moved);
    full.reinsert(it, g.moved(moved));
    for (motion_strategy s : {motion_strategy::refit, motion_strategy::rebuild, motion_strategy::reinsert}) {
        std::vector<std::pair<typename Tree::iterator, O>> moves;
        for (auto m = full.begin(); m != full.end(); ++m)
            if (g.below(3) == 0) moves.emplace_back(m, g.moved(*m));
        full.update(moves.begin(), moves.end(), s);
        EXPECT_EQ(full.check_invariants(), "");
    }
    brute_force<O> after(full.begin(), full.end());
    bvh_test::compare_queries(full, after, g, 40);
    EXPECT_EQ(full.pairs_with(target, pair_filter::exact).size(), after.pairs_with(oracle, pair_filter::exact).size());
    // Clear returns to the unallocated tree; a rebuild of it gives the root (an empty leaf).
    full.clear();
    expect_unallocated(full, "cleared", false);
    full.rebuild();
    EXPECT_EQ(full.node_count(), 1u);
    EXPECT_EQ(full.check_invariants(), "");
    full = Tree{};
    expect_unallocated(full, "move-assigned a default-constructed tree");
    // A std::vector of trees moves them when it grows (the moves are noexcept): the stored
    // objects' storage is not copied.
    std::vector<Tree> trees(1);
    trees[0].insert(v[0]);
    const O* stored = &*trees[0].begin();
    trees.reserve(trees.capacity() + 8);
    EXPECT_EQ(&*trees[0].begin(), stored);
}

TEST(bvh_structure, unallocated_empty_tree_of_boxes_with_the_wide_ray_layout) {
    empty_state_round_trip<bvh<B3, aabb<double, 3>>>();
}
TEST(bvh_structure, unallocated_empty_tree_of_boxes_with_spheres) { empty_state_round_trip<bvh<B3, sphere<double, 3>>>(); }
TEST(bvh_structure, unallocated_empty_tree_of_points_with_obbs) {
    empty_state_round_trip<bvh<P3, obb<double, 3>, bvh_median_config<2>>>();
}

TEST(bvh_structure, refit_after_moving_every_object_matches_the_oracle) {
    bvh_test::scene_source<B3> g(spatial_test::test_seed(9));
    std::vector<B3> v;
    for (int i = 0; i < 500; ++i) v.push_back(g.object());
    bvh<B3, kdop<double, 3, 26>> tree(v.begin(), v.end());
    brute_force<B3> oracle;
    for (auto it = tree.begin(); it != tree.end(); ++it) {  // translate everything by (10, 0, -3)
        B3 w = *it;
        for (int i = 0; i < 3; ++i) w.lo[i] += i == 0 ? 10 : (i == 2 ? -3 : 0), w.hi[i] += i == 0 ? 10 : (i == 2 ? -3 : 0);
        tree.update(it, w, false);
        oracle.insert(w);
    }
    tree.refit();
    ASSERT_EQ(tree.check_invariants(), "");
    bvh_test::scene_source<B3> q(spatial_test::test_seed(10), 0, 1);
    for (int i = 0; i < 100; ++i) {
        P3 o = q.point_in(0, 1);
        o[0] += 10;
        o[2] -= 3;
        const P3 d = q.direction();
        intersect_info<P3> a, b;
        EXPECT_EQ(tree.intersect(o, d, 0.0, a), oracle.intersect(o, d, 0.0, b));
        EXPECT_EQ(a.hit_time, b.hit_time);
        EXPECT_EQ(spatial_test::distances_from(o, tree.find_nearest(o, 5)),
                  spatial_test::distances_from(o, oracle.find_nearest(o, 5)));
    }
}

}  // namespace
