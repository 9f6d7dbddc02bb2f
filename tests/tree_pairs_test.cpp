// The trees' own broad phases — spatial::octree and spatial::kd_tree: self_pairs descends the
// tree against itself, pairs_with another tree of the same type descends the two together —
// against brute force's O(n^2) oracle, on the cases that break such a descent: objects of
// different subtrees touching on shared faces, edges and corners (integer grids), objects
// exactly on split planes, duplicates, zero-extent boxes, one object covering everything,
// points, spheres and triangles, 2D and 3D, float and double; for the octree loose factor 1 and
// 2 and leaf capacity 1 (deep trees), for the kd-tree small leaves and both splitters; after
// erases and inserts (merging in the octree; loose node extents in the kd-tree). The exact
// pairs must equal brute force's and the candidates its bounding-box pairs (as multisets of
// object signatures: the kd-tree's bulk build numbers slots in leaf order), each pair once as
// (lower slot, higher slot). Seeds are logged; replay one with SPATIAL_TEST_SEED.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <set>
#include <type_traits>
#include <utility>
#include <vector>

#include "spatial/brute/brute_force.hpp"
#include "spatial/core/point.hpp"
#include "spatial/kdtree/kd_tree.hpp"
#include "spatial/objects/box.hpp"
#include "spatial/objects/sphere.hpp"
#include "spatial/objects/triangle.hpp"
#include "spatial/octree/octree.hpp"
#include "test_support.hpp"

namespace {

using namespace spatial;

// Objects built from an axis-aligned box [lo, hi] (corners on an integer grid times a dyadic
// step, so faces meet exactly): the box itself, the point lo, the sphere inscribed in the
// box's first edge, the triangle on three of its corners.
template <class O>
struct from_box;
template <class T, std::size_t D>
struct from_box<objects::box<T, D>> {
    static objects::box<T, D> make(const point<T, D>& lo, const point<T, D>& hi) {
        objects::box<T, D> b;
        for (std::size_t i = 0; i < D; ++i) b.lo[i] = lo[i], b.hi[i] = hi[i];
        return b;
    }
};
template <class T, std::size_t D>
struct from_box<point<T, D>> {
    static point<T, D> make(const point<T, D>& lo, const point<T, D>&) { return lo; }
};
template <class T, std::size_t D>
struct from_box<objects::sphere<T, D>> {
    static objects::sphere<T, D> make(const point<T, D>& lo, const point<T, D>& hi) {
        point<T, D> c;
        for (std::size_t i = 0; i < D; ++i) c[i] = lo[i] + (hi[i] - lo[i]) / 2;
        return objects::sphere<T, D>(c, (hi[0] - lo[0]) / 2);
    }
};
template <class T, std::size_t D>
struct from_box<objects::triangle<T, D>> {
    static objects::triangle<T, D> make(const point<T, D>& lo, const point<T, D>& hi) {
        point<T, D> b = lo, c = hi;
        b[0] = hi[0];
        c[0] = lo[0];
        return objects::triangle<T, D>(lo, b, c);
    }
};

template <class O>
using scalar_of = typename O::scalar_type;

// A random object with integer corners in [0, grid] (extent 0 to 3 cells on each axis: zero
// extent, shared faces, edges and corners, duplicates when the grid is small), scaled by step.
template <class O>
O grid_object(std::mt19937_64& rng, int grid, scalar_of<O> step) {
    using T = scalar_of<O>;
    constexpr std::size_t D = O::dimension;
    std::uniform_int_distribution<int> pos(0, grid), ext(0, 3);
    point<T, D> lo, hi;
    const int e = ext(rng);  // one extent for all axes keeps spheres inside their box
    for (std::size_t i = 0; i < D; ++i) {
        lo[i] = static_cast<T>(pos(rng)) * step;
        hi[i] = lo[i] + static_cast<T>(e) * step;
    }
    return from_box<O>::make(lo, hi);
}

// An object with every face on a split plane of a root cell [origin, origin + size]^D: its
// corners at multiples of size / 2^levels.
template <class O>
O on_split_planes(std::mt19937_64& rng, scalar_of<O> origin, scalar_of<O> size, int levels) {
    using T = scalar_of<O>;
    constexpr std::size_t D = O::dimension;
    const int cells = 1 << levels;
    std::uniform_int_distribution<int> pos(0, cells - 1), ext(0, 2);
    const T cell = size / static_cast<T>(cells);
    point<T, D> lo, hi;
    const int e = ext(rng);
    for (std::size_t i = 0; i < D; ++i) {
        const int k = pos(rng);
        lo[i] = origin + static_cast<T>(k) * cell;
        hi[i] = origin + static_cast<T>(std::min(cells, k + e)) * cell;
    }
    return from_box<O>::make(lo, hi);
}

using spatial_test::slot_pair;
using spatial_test::slots_of;

// Exact == brute force's exact, candidates == brute force's bounding-box pairs (so a superset
// of the exact ones), compared as multisets of object signatures (the kd-tree's bulk build
// allocates slots in leaf order, not in brute force's); within the tree each pair once,
// (lower slot, higher slot), sorted. Returns the exact count.
template <class Tree>
std::size_t expect_pairs_equal_oracle(const Tree& tree, const brute_force<typename Tree::value_type>& oracle) {
    EXPECT_EQ(tree.check_invariants(), "");
    const auto exact_pairs = tree.self_pairs(pair_filter::exact);
    const auto candidate_pairs = tree.self_pairs(pair_filter::candidates);
    const auto exact = slots_of(exact_pairs);
    const auto candidates = slots_of(candidate_pairs);
    for (const auto* s : {&exact, &candidates}) {
        EXPECT_TRUE(std::is_sorted(s->begin(), s->end()));
        EXPECT_EQ(std::set<slot_pair>(s->begin(), s->end()).size(), s->size()) << "a pair reported twice";
        for (const auto& [a, b] : *s) EXPECT_LT(a, b);
    }
    EXPECT_TRUE(std::includes(candidates.begin(), candidates.end(), exact.begin(), exact.end()));
    const auto want = oracle.self_pairs(pair_filter::exact);
    EXPECT_EQ(spatial_test::signature_pairs(exact_pairs), spatial_test::signature_pairs(want));
    EXPECT_EQ(spatial_test::signature_pairs(candidate_pairs),
              spatial_test::signature_pairs(oracle.self_pairs(pair_filter::candidates)));
    return want.size();
}

template <class Tree>
class tree_pairs : public ::testing::Test {};

template <std::size_t Capacity, std::intmax_t Loose>
using cfg = octree_config<Capacity, 32, std::ratio<Loose>>;
template <std::size_t Capacity, class Splitter = median_of_widest_spread>
using kd_cfg = kd_tree_config<Capacity, Splitter>;
// The sanitizer build runs a representative subset (SPATIAL_TEST_FULL_MATRIX=0).
#if SPATIAL_TEST_FULL_MATRIX
using tree_pair_types = ::testing::Types<
    octree<objects::box<double, 3>>, octree<objects::box<double, 3>, classic_octree_config>,
    octree<objects::box<double, 3>, cfg<1, 2>>, octree<objects::box<float, 3>, cfg<2, 1>>,
    octree<objects::box<float, 2>, cfg<1, 2>>, octree<objects::box<double, 2>, classic_octree_config>,
    octree<objects::sphere<double, 3>>, octree<objects::sphere<float, 2>, cfg<2, 1>>,
    octree<objects::triangle<double, 3>, classic_octree_config>, octree<objects::triangle<float, 2>, cfg<1, 2>>,
    octree<point<double, 3>, cfg<1, 2>>, octree<point<float, 2>, classic_octree_config>,
    kd_tree<objects::box<double, 3>>, kd_tree<objects::box<double, 3>, kd_cfg<2>>,
    kd_tree<objects::box<float, 2>, kd_cfg<2, midpoint_of_max_spread>>, kd_tree<objects::sphere<double, 3>, kd_cfg<4>>,
    kd_tree<objects::sphere<float, 2>>, kd_tree<objects::triangle<double, 3>, kd_cfg<3, midpoint_of_max_spread>>,
    kd_tree<objects::triangle<float, 2>, kd_cfg<2>>, kd_tree<point<double, 3>, kd_cfg<2>>>;
#else
using tree_pair_types =
    ::testing::Types<octree<objects::box<double, 3>>, octree<objects::box<float, 2>, cfg<1, 1>>,
                     octree<objects::sphere<double, 3>, cfg<2, 2>>,
                     octree<objects::triangle<float, 3>, classic_octree_config>, octree<point<double, 2>, cfg<1, 2>>,
                     kd_tree<objects::box<double, 3>, kd_cfg<2>>,
                     kd_tree<objects::triangle<float, 2>, kd_cfg<3, midpoint_of_max_spread>>>;
#endif
TYPED_TEST_SUITE(tree_pairs, tree_pair_types);

// Integer grids of several densities (small grids: many duplicates and touching objects),
// with and without one object covering everything, built in bulk and one by one.
TYPED_TEST(tree_pairs, grid_objects_equal_brute_force) {
    using Tree = TypeParam;
    using O = typename Tree::value_type;
    using T = scalar_of<O>;
    for (const int grid : {3, 8, 40}) {
        const std::uint64_t seed = spatial_test::test_seed(1000 + static_cast<std::uint64_t>(grid));
        SCOPED_TRACE(spatial_test::replay_hint(seed));
        std::mt19937_64 rng(seed);
        std::vector<O> objects;
        for (int k = 0; k < 600; ++k) objects.push_back(grid_object<O>(rng, grid, T(0.25)));
        for (const bool huge : {false, true}) {
            std::vector<O> all = objects;
            if (huge) {
                point<T, O::dimension> lo, hi;
                for (std::size_t i = 0; i < O::dimension; ++i) lo[i] = T(-1), hi[i] = T(grid + 4) * T(0.25);
                all.insert(all.begin() + 300, from_box<O>::make(lo, hi));
            }
            const Tree bulk(all.begin(), all.end());
            const brute_force<O> oracle(all.begin(), all.end());
            const std::size_t found = expect_pairs_equal_oracle(bulk, oracle);
            if (grid <= 8) {
                EXPECT_GT(found, 0u);
            }
            Tree one_by_one;
            for (const O& x : all) one_by_one.insert(x);
            expect_pairs_equal_oracle(one_by_one, oracle);
        }
    }
}

// Objects whose faces lie exactly on the split planes of the first levels (the octree's root
// cell is [0, root_size()]^D after a bulk build whose objects start at 0; the kd-tree's median
// splits of grid objects fall on the same dyadic planes of [0, 16]), next to grid objects.
TYPED_TEST(tree_pairs, objects_on_split_planes_equal_brute_force) {
    using Tree = TypeParam;
    using O = typename Tree::value_type;
    using T = scalar_of<O>;
    spatial_test::seeded_rng rng(2024);
    std::vector<O> objects;
    for (int k = 0; k < 400; ++k) objects.push_back(grid_object<O>(rng, 16, T(1)));
    point<T, O::dimension> zero{};
    objects.push_back(from_box<O>::make(zero, zero));  // the root's corner is exactly 0
    Tree tree(objects.begin(), objects.end());
    brute_force<O> oracle(objects.begin(), objects.end());
    T size = T(16);
    if constexpr (requires { tree.root_size(); }) size = tree.root_size();
    for (int k = 0; k < 400; ++k) {
        const O x = on_split_planes<O>(rng, T(0), size, 1 + k % 5);
        ASSERT_EQ(tree.insert(x).slot(), oracle.insert(x).slot());
    }
    // A sphere's box is its centre +- radius rounded outward, so spheres may stick out of the
    // root by an ulp and re-root it: on the planes within rounding then, still a valid test.
    if constexpr (requires { tree.root_size(); } && !std::is_same_v<O, objects::sphere<T, O::dimension>>) {
        EXPECT_EQ(tree.root_size(), size) << "the split planes moved";
    }
    EXPECT_GT(expect_pairs_equal_oracle(tree, oracle), 0u);
}

// Continuous random objects, then rounds of erasing and inserting (merges, splits, reuse of
// slots and node blocks; loose kd-tree extents); bipartite pairs against a second tree of the
// same type and a brute force.
TYPED_TEST(tree_pairs, after_erases_and_inserts_and_bipartite_equal_brute_force) {
    using Tree = TypeParam;
    using O = typename Tree::value_type;
    using T = scalar_of<O>;
    spatial_test::seeded_rng rng(77);
    auto random_object = [&](int k) {  // every fourth on a coarse grid: touching and duplicates
        if (k % 4 == 0) return grid_object<O>(rng, 10, T(0.5));
        std::uniform_real_distribution<T> u(0, 5), e(0, T(0.3));
        point<T, O::dimension> lo, hi;
        const T ext = e(rng);
        for (std::size_t i = 0; i < O::dimension; ++i) lo[i] = u(rng), hi[i] = lo[i] + ext;
        return from_box<O>::make(lo, hi);
    };
    Tree tree;
    brute_force<O> oracle;
    std::vector<typename Tree::iterator> handles;
    std::vector<typename brute_force<O>::iterator> oracle_handles;
    for (int k = 0; k < 800; ++k) {
        const O x = random_object(k);
        handles.push_back(tree.insert(x));
        oracle_handles.push_back(oracle.insert(x));
        ASSERT_EQ(handles.back().slot(), oracle_handles.back().slot());
    }
    expect_pairs_equal_oracle(tree, oracle);
    for (int round = 0; round < 4; ++round) {
        // Erase most (merges cascade), then refill.
        std::shuffle(handles.begin(), handles.end(), rng);
        for (std::size_t i = 0; i + 100 < handles.size(); ++i) {
            tree.erase(handles[i]);
            const auto it = std::find_if(oracle_handles.begin(), oracle_handles.end(),
                                         [&](const auto& h) { return h.slot() == handles[i].slot(); });
            oracle.erase(*it);
            oracle_handles.erase(it);
        }
        handles.erase(handles.begin(), handles.end() - 100);
        expect_pairs_equal_oracle(tree, oracle);
        for (int k = 0; k < 700; ++k) {
            const O x = random_object(k);
            handles.push_back(tree.insert(x));
            oracle_handles.push_back(oracle.insert(x));
            ASSERT_EQ(handles.back().slot(), oracle_handles.back().slot());
        }
        EXPECT_GT(expect_pairs_equal_oracle(tree, oracle), 0u);
    }
    std::vector<O> more;
    for (int k = 0; k < 300; ++k) more.push_back(random_object(k + 1));
    const Tree other(more.begin(), more.end());
    const brute_force<O> other_oracle(more.begin(), more.end());
    for (const pair_filter f : {pair_filter::exact, pair_filter::candidates}) {
        const auto pairs = tree.pairs_with(other, f);
        const auto got = slots_of(pairs);
        EXPECT_TRUE(std::is_sorted(got.begin(), got.end()));
        EXPECT_EQ(std::set<slot_pair>(got.begin(), got.end()).size(), got.size()) << "a pair reported twice";
        EXPECT_EQ(spatial_test::signature_pairs(pairs),
                  spatial_test::signature_pairs(oracle.pairs_with(other_oracle, f)));
    }
    EXPECT_EQ(spatial_test::signature_pairs(tree.pairs_with(other_oracle)),
              spatial_test::signature_pairs(oracle.pairs_with(other_oracle)));
}

TYPED_TEST(tree_pairs, empty_single_and_identical_objects) {
    using Tree = TypeParam;
    using O = typename Tree::value_type;
    using T = scalar_of<O>;
    Tree tree;
    EXPECT_TRUE(tree.self_pairs().empty());
    EXPECT_TRUE(tree.pairs_with(tree).empty());
    point<T, O::dimension> lo{}, hi;
    for (std::size_t i = 0; i < O::dimension; ++i) hi[i] = T(1);
    const O x = from_box<O>::make(lo, hi);
    tree.insert(x);
    EXPECT_TRUE(tree.self_pairs().empty());
    EXPECT_EQ(tree.pairs_with(tree).size(), 1u);
    for (int k = 0; k < 40; ++k) tree.insert(x);  // 41 identical objects: unsplittable
    EXPECT_EQ(tree.self_pairs().size(), 41u * 40u / 2u);
    EXPECT_EQ(tree.self_pairs(pair_filter::candidates).size(), 41u * 40u / 2u);
}

}  // namespace
