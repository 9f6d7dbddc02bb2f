// Collision pairs (collide/pairs.hpp): bvh's self_pairs and pairs_with, for several bounding
// volumes and both builders — and the other structures' (kd_tree, octree, grids: through
// their box queries) — against brute_force's O(n^2) oracle — the exact pair sets must
// be IDENTICAL; candidate sets must contain them; every pair reported once, sorted, self
// pairs as (lower slot, higher slot). Objects: boxes (3D and 2D, some on a grid so that
// touching faces and duplicates occur), spheres, triangles (3D), points (duplicates only).
// Also after updates (moves, erases, inserts) and bipartite (bvh with bvh, bvh with
// brute_force through the generic path). Seeds are logged.

#include <gtest/gtest.h>

#include <random>
#include <set>
#include <vector>

#include "spatial/brute/brute_force.hpp"
#include "spatial/bv/kdop.hpp"
#include "spatial/bv/obb.hpp"
#include "spatial/bv/sphere.hpp"
#include "spatial/bvh/bvh.hpp"
#include "spatial/collide/collision_grid.hpp"
#include "spatial/collide/pairs.hpp"
#include "spatial/collide/sweep_and_prune.hpp"
#include "spatial/grid/hashed_grid.hpp"
#include "spatial/grid/uniform_grid.hpp"
#include "spatial/kdtree/kd_tree.hpp"
#include "spatial/octree/octree.hpp"
#include "test_support.hpp"

using namespace spatial;

namespace {

template <class O>
struct make_object;
template <class T, std::size_t D>
struct make_object<objects::box<T, D>> {
    static objects::box<T, D> random(std::mt19937_64& rng, int k) {
        std::uniform_real_distribution<T> u(0, 1), h(T(0.002), T(0.04));
        std::uniform_int_distribution<int> g(0, 16);
        point<T, D> a, b;
        for (std::size_t i = 0; i < D; ++i) {
            if (k % 3 == 0) {  // grid boxes: shared faces and duplicates
                a[i] = static_cast<T>(g(rng)) / 16;
                b[i] = a[i] + T(1) / 16;
            } else {
                const T c = u(rng), r = h(rng);
                a[i] = c - r;
                b[i] = c + r;
            }
        }
        return objects::box<T, D>(a, b);
    }
};
template <class T>
struct make_object<objects::sphere<T, 3>> {
    static objects::sphere<T, 3> random(std::mt19937_64& rng, int) {
        std::uniform_real_distribution<T> u(0, 1), r(T(0.005), T(0.04));
        return objects::sphere<T, 3>(point<T, 3>{{u(rng), u(rng), u(rng)}}, r(rng));
    }
};
template <class T>
struct make_object<objects::triangle<T, 3>> {
    static objects::triangle<T, 3> random(std::mt19937_64& rng, int k) {
        std::uniform_real_distribution<T> u(0, 1), s(T(-0.05), T(0.05));
        std::uniform_int_distribution<int> g(0, 8);
        point<T, 3> c{{u(rng), u(rng), u(rng)}}, v[3];
        for (auto& p : v)
            for (std::size_t i = 0; i < 3; ++i)
                p[i] = k % 4 == 0 ? static_cast<T>(g(rng)) / 8 : c[i] + s(rng);  // grid: coplanar / touching
        return objects::triangle<T, 3>(v[0], v[1], v[2]);
    }
};
template <class T>
struct make_object<point<T, 3>> {
    static point<T, 3> random(std::mt19937_64& rng, int) {
        std::uniform_int_distribution<int> g(0, 12);  // few distinct values: duplicates
        return point<T, 3>{{static_cast<T>(g(rng)), static_cast<T>(g(rng)), static_cast<T>(g(rng))}};
    }
};

using spatial_test::slot_pair;
using spatial_test::slots_of;

template <class Pairs>
void expect_well_formed(const Pairs& pairs, bool self) {
    const auto s = slots_of(pairs);
    EXPECT_TRUE(std::is_sorted(s.begin(), s.end()));
    EXPECT_EQ(std::set<slot_pair>(s.begin(), s.end()).size(), s.size()) << "a pair reported twice";
    if (self) {
        for (const auto& [a, b] : s) EXPECT_LT(a, b);
    }
}

template <class Tree>
void check_against_oracle(const Tree& tree, const brute_force<typename Tree::value_type>& oracle) {
    const auto exact = tree.self_pairs(pair_filter::exact);
    const auto candidates = tree.self_pairs(pair_filter::candidates);
    expect_well_formed(exact, true);
    expect_well_formed(candidates, true);
    const auto want = slots_of(oracle.self_pairs(pair_filter::exact));
    EXPECT_EQ(slots_of(exact), want);
    const auto c = slots_of(candidates);
    EXPECT_TRUE(std::includes(c.begin(), c.end(), want.begin(), want.end())) << "a candidate set misses a pair";
}

// n objects, the k-th being make_object<O>::random(rng, first + k).
template <class O>
std::vector<O> random_objects(std::mt19937_64& rng, int n, int first = 0) {
    std::vector<O> v;
    for (int k = 0; k < n; ++k) v.push_back(make_object<O>::random(rng, k + first));
    return v;
}

template <class Tree>
class collide_pairs : public ::testing::Test {};

using spatial_test::B3, spatial_test::P3;
// The sanitizer build runs a representative subset (CI time: SPATIAL_TEST_FULL_MATRIX=0): every
// object kind, both scalars and dimensions, and the volume families still appear.
#if SPATIAL_TEST_FULL_MATRIX
using trees = ::testing::Types<
    bvh<B3>, bvh<B3, aabb<double, 3>, bvh_median_config<>>, bvh<B3, sphere<double, 3>>, bvh<B3, obb<double, 3>>,
    bvh<B3, kdop<double, 3, 14>>, bvh<objects::box<float, 2>>, bvh<objects::box<double, 2>, kdop<double, 2, 8>>,
    bvh<objects::sphere<double, 3>>, bvh<objects::sphere<double, 3>, sphere<double, 3>>,
    bvh<objects::triangle<double, 3>>, bvh<objects::triangle<double, 3>, obb<double, 3>>, bvh<P3, aabb<double, 3>, bvh_sah_config<8>>>;
#else
using trees = ::testing::Types<bvh<B3>, bvh<B3, obb<double, 3>>, bvh<objects::box<double, 2>, kdop<double, 2, 8>>,
                               bvh<objects::box<float, 2>>, bvh<objects::sphere<double, 3>, sphere<double, 3>>,
                               bvh<objects::triangle<double, 3>>, bvh<P3, aabb<double, 3>, bvh_sah_config<8>>>;
#endif
TYPED_TEST_SUITE(collide_pairs, trees);

TYPED_TEST(collide_pairs, self_pairs_equal_brute_force_before_and_after_updates) {
    using O = typename TypeParam::value_type;
    spatial_test::seeded_rng rng(101);
    std::vector<O> objects = random_objects<O>(rng, 1200);
    TypeParam tree(objects.begin(), objects.end());
    brute_force<O> oracle(objects.begin(), objects.end());
    check_against_oracle(tree, oracle);
    EXPECT_GT(tree.self_pairs().size(), 20u) << "too few pairs to test anything";

    // Move 200, erase 100, insert 150: both containers keep slots in step (erase frees a
    // slot, the next insert reuses it in both, LIFO).
    const auto handles = spatial_test::all_iterators(tree);
    const auto oracle_handles = spatial_test::all_iterators(oracle);
    for (int k = 0; k < 200; ++k) {
        const auto i = static_cast<std::size_t>(k * 5);
        const O moved = make_object<O>::random(rng, k + 1);
        tree.update(handles[i], moved);
        oracle.erase(oracle_handles[i]);
        ASSERT_EQ(oracle.insert(moved).slot(), handles[i].slot());
    }
    for (int k = 0; k < 100; ++k) {
        const auto i = static_cast<std::size_t>(k * 7 + 3);
        tree.erase(handles[i]);
        oracle.erase(oracle_handles[i]);  // same slot as handles[i] (a moved object reused it)
    }
    for (int k = 0; k < 150; ++k) {
        const O x = make_object<O>::random(rng, k);
        ASSERT_EQ(tree.insert(x).slot(), oracle.insert(x).slot());
    }
    ASSERT_EQ(tree.size(), oracle.size());
    ASSERT_EQ(tree.check_invariants(), "");
    check_against_oracle(tree, oracle);
}

TYPED_TEST(collide_pairs, bipartite_pairs_equal_brute_force) {
    using O = typename TypeParam::value_type;
    spatial_test::seeded_rng rng(102);
    std::vector<O> a = random_objects<O>(rng, 700);
    std::vector<O> b = random_objects<O>(rng, 500, 1);
    TypeParam ta(a.begin(), a.end()), tb(b.begin(), b.end());
    brute_force<O> oa, ob;
    oa.insert(a.begin(), a.end());
    ob.insert(b.begin(), b.end());
    const auto want = slots_of(oa.pairs_with(ob));
    EXPECT_GT(want.size(), 10u);
    const auto tree_tree = ta.pairs_with(tb);
    expect_well_formed(tree_tree, false);
    EXPECT_EQ(slots_of(tree_tree), want);
    const auto tree_other = ta.pairs_with(ob);  // generic path: box queries
    expect_well_formed(tree_other, false);
    EXPECT_EQ(slots_of(tree_other), want);
    const auto cand = slots_of(ta.pairs_with(tb, pair_filter::candidates));
    EXPECT_TRUE(std::includes(cand.begin(), cand.end(), want.begin(), want.end()));
}

// Every other structure (tree descents, cell joins, box queries): the same exact sets as
// brute force, before and after erases and inserts, and bipartite with brute force.
template <class C>
class collide_pairs_other : public ::testing::Test {};
using others = ::testing::Types<kd_tree<B3>, octree<B3>, uniform_grid<B3>, hashed_grid<B3>,
                                kd_tree<objects::triangle<double, 3>>, uniform_grid<objects::sphere<double, 3>>>;
TYPED_TEST_SUITE(collide_pairs_other, others);

TYPED_TEST(collide_pairs_other, self_and_bipartite_pairs_equal_brute_force) {
    using O = typename TypeParam::value_type;
    spatial_test::seeded_rng rng(103);
    std::vector<O> objects = random_objects<O>(rng, 1000);
    TypeParam c;
    c.insert(objects.begin(), objects.end());
    brute_force<O> oracle(objects.begin(), objects.end());
    auto check = [&] {
        const auto exact = c.self_pairs();
        expect_well_formed(exact, true);
        const auto want = spatial_test::signature_pairs(oracle.self_pairs());
        EXPECT_EQ(spatial_test::signature_pairs(exact), want);
        const auto cand = spatial_test::signature_pairs(c.self_pairs(pair_filter::candidates));
        EXPECT_TRUE(std::includes(cand.begin(), cand.end(), want.begin(), want.end()));
        return want.size();
    };
    EXPECT_GT(check(), 20u);
    const auto handles = spatial_test::all_iterators(c);
    for (int k = 0; k < 100; ++k) {  // erase one copy of the same value from both
        const auto i = static_cast<std::size_t>(k * 9 + 1);
        const O gone = *handles[i];
        c.erase(handles[i]);
        oracle.erase(oracle.find(gone));
    }
    for (int k = 0; k < 150; ++k) {
        const O x = make_object<O>::random(rng, k);
        c.insert(x);
        oracle.insert(x);
    }
    ASSERT_EQ(c.size(), oracle.size());
    check();
    std::vector<O> more = random_objects<O>(rng, 300, 2);
    brute_force<O> other(more.begin(), more.end());
    EXPECT_EQ(spatial_test::signature_pairs(c.pairs_with(other)), spatial_test::signature_pairs(oracle.pairs_with(other)));
}

// The handle structures (sweep_and_prune, collision_grid) keep slots in step with
// brute_force (all allocate in order, LIFO reuse), so pair sets compare slot for slot — also
// after small motions, large ones, erases and inserts, and (sweep_and_prune) when the sweep
// axis changes.
template <template <class> class S, class O>
void check_handle_structure(std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::vector<O> objects = random_objects<O>(rng, 1500);
    S<O> sap(objects.begin(), objects.end());
    brute_force<O> oracle(objects.begin(), objects.end());
    auto check = [&] {
        const auto exact = sap.self_pairs();
        expect_well_formed(exact, true);
        const auto want = slots_of(oracle.self_pairs());
        EXPECT_EQ(slots_of(exact), want);
        const auto cand = slots_of(sap.self_pairs(pair_filter::candidates));
        EXPECT_EQ(cand, slots_of(oracle.self_pairs(pair_filter::candidates)));  // both: boxes overlap
        return want.size();
    };
    EXPECT_GT(check(), 20u);
    const auto handles = spatial_test::all_iterators(sap);
    const auto oracle_handles = spatial_test::all_iterators(oracle);
    // Replace a fifth of the objects (large motion), erase some, insert some.
    for (std::size_t i = 0; i < handles.size(); i += 5) {
        const O moved = make_object<O>::random(rng, static_cast<int>(i) + 1);
        sap.update(handles[i], moved);
        oracle.erase(oracle_handles[i]);
        ASSERT_EQ(oracle.insert(moved).slot(), handles[i].slot());
    }
    for (std::size_t i = 3; i < handles.size(); i += 11) {
        sap.erase(handles[i]);
        oracle.erase(oracle_handles[i]);
    }
    for (int k = 0; k < 200; ++k) {
        const O x = make_object<O>::random(rng, k);
        ASSERT_EQ(sap.insert(x).slot(), oracle.insert(x).slot());
    }
    check();
    // Bipartite against a brute_force and (same structure) against another instance.
    std::vector<O> more = random_objects<O>(rng, 400, 1);
    brute_force<O> other_oracle(more.begin(), more.end());
    const S<O> other(more.begin(), more.end());
    const auto want = slots_of(oracle.pairs_with(other_oracle));
    EXPECT_EQ(slots_of(sap.pairs_with(other_oracle)), want);
    EXPECT_EQ(slots_of(sap.pairs_with(other)), want);
    if constexpr (requires { sap.grid_stats(); }) {  // one grid over both sets: box overlap exactly
        EXPECT_EQ(slots_of(sap.pairs_with(other, pair_filter::candidates)),
                  slots_of(oracle.pairs_with(other_oracle, pair_filter::candidates)));
    }
    if constexpr (requires { sap.last_repair_swaps(); }) {
        // No motion at all: the order is already sorted, the repair makes no swap.
        (void)sap.self_pairs();
        EXPECT_EQ(sap.last_repair_swaps(), 0u);
    }
}

// check_handle_structure<S, O> for each object type O, all with the same seed.
template <template <class> class S, class... O>
void check_handle_structure_on(std::uint64_t seed) {
    (check_handle_structure<S, O>(seed), ...);
}

TEST(collide_sweep_and_prune, pairs_equal_brute_force_for_boxes_spheres_and_triangles) {
    const spatial_test::logged_seed seed(104);
    check_handle_structure_on<sweep_and_prune, B3, objects::box<float, 2>, objects::sphere<double, 3>,
                              objects::triangle<double, 3>>(seed);
}

TEST(collide_collision_grid, pairs_equal_brute_force_for_boxes_spheres_triangles_and_points) {
    const spatial_test::logged_seed seed(105);
    check_handle_structure_on<collision_grid, B3, objects::box<float, 2>, objects::sphere<double, 3>,
                              objects::triangle<double, 3>, P3>(seed);  // points: all extents zero, many duplicates
}

TEST(collide_sweep_and_prune, coherent_motion_needs_few_swaps_and_the_axis_follows_the_spread) {
    // Boxes along x (the widest spread), moved by a tiny step: few swaps, same pairs as brute force.
    std::vector<B3> boxes;
    for (int i = 0; i < 1000; ++i) {
        const double x = i * 0.01;
        boxes.emplace_back(P3{{x, 0, 0}}, P3{{x + 0.015, 0.01, 0.01}});
    }
    sweep_and_prune<B3> sap(boxes.begin(), boxes.end());
    EXPECT_EQ(sap.self_pairs().size(), 999u);  // each box overlaps its right neighbour only
    const auto handles = spatial_test::all_iterators(sap);
    for (std::size_t i = 0; i < handles.size(); i += 2) {  // every other box moves right by 0.012
        B3 b = *handles[i];
        b.lo[0] += 0.012;
        b.hi[0] += 0.012;
        sap.update(handles[i], b);
    }
    brute_force<B3> oracle;
    for (auto it = sap.begin(); it != sap.end(); ++it) oracle.insert(*it);
    EXPECT_EQ(spatial_test::signature_pairs(sap.self_pairs()), spatial_test::signature_pairs(oracle.self_pairs()));
    EXPECT_LE(sap.last_repair_swaps(), 500u);  // each moved box passes at most one neighbour
    // Turn the row along z: the sweep axis changes and the answers stay right.
    for (std::size_t i = 0; i < handles.size(); ++i) {
        const double z = static_cast<double>(i) * 0.01;
        sap.update(handles[i], B3(P3{{0, 0, z}}, P3{{0.01, 0.01, z + 0.015}}));
    }
    EXPECT_EQ(sap.self_pairs().size(), 999u);
    EXPECT_THROW(sap.erase(sap.end()), std::invalid_argument);
}

TEST(collide_pairs_edge_cases, empty_single_and_identical_objects) {
    bvh<B3> empty;
    EXPECT_TRUE(empty.self_pairs().empty());
    bvh<B3> one;
    one.insert(B3(P3{{0, 0, 0}}, P3{{1, 1, 1}}));
    EXPECT_TRUE(one.self_pairs().empty());
    EXPECT_TRUE(one.pairs_with(empty).empty());
    // 50 identical boxes: every one of the 50 * 49 / 2 pairs, once.
    std::vector<B3> same(50, B3(P3{{0, 0, 0}}, P3{{1, 1, 1}}));
    bvh<B3> tree(same.begin(), same.end());
    EXPECT_EQ(tree.self_pairs().size(), 50u * 49u / 2u);
    // Touching faces intersect (closed sets); a gap of one ulp does not.
    bvh<B3> touching;
    touching.insert(B3(P3{{0, 0, 0}}, P3{{1, 1, 1}}));
    touching.insert(B3(P3{{1, 0, 0}}, P3{{2, 1, 1}}));
    touching.insert(B3(P3{{std::nextafter(2.0, 3.0), 0, 0}}, P3{{3, 1, 1}}));
    EXPECT_EQ(touching.self_pairs().size(), 1u);
}

}  // namespace
