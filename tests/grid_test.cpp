// spatial::uniform_grid and spatial::hashed_grid: the shared contract suite, differential
// tests against brute force under interleaved updates, the numerically hard cases
// (octree_grid_checks.hpp), and grid-specific properties: amortised re-gridding, sparse
// hashed scenes spanning 1e15 cells, no duplicate reports for objects spanning many cells.

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <random>
#include <set>
#include <type_traits>
#include <vector>

#include "container_contract.hpp"
#include "octree_grid_checks.hpp"
#include "spatial/brute/brute_force.hpp"
#include "spatial/grid/hashed_grid.hpp"
#include "spatial/grid/uniform_grid.hpp"
#include "spatial/objects/box.hpp"
#include "spatial/objects/sphere.hpp"
#include "spatial/objects/triangle.hpp"
#include "test_support.hpp"

using namespace spatial;
using spatial_test::tagged_point;
using P3 = point<double, 3>;
using B3 = objects::box<double, 3>;
using B2f = objects::box<float, 2>;

// A hashed grid with a fixed small cell (objects span many cells; sparse fall-backs trigger).
template <class O>
struct fine_hashed_grid : hashed_grid<O> {
    fine_hashed_grid() : hashed_grid<O>(typename O::scalar_type(0.1)) {}
};
static_assert(spatial_container<fine_hashed_grid<B3>>);

// The sanitizer build runs a representative subset (CI time: SPATIAL_TEST_FULL_MATRIX=0): every
// structure, scalar, dimension and object kind still appears; the release build runs them all.
#if SPATIAL_TEST_FULL_MATRIX
using grid_point_types = ::testing::Types<uniform_grid<P3>, uniform_grid<point<float, 2>>, uniform_grid<tagged_point>,
                                          hashed_grid<P3>, hashed_grid<point<float, 2>>, fine_hashed_grid<P3>>;
using grid_object_types =
    ::testing::Types<uniform_grid<B3>, uniform_grid<B2f>, uniform_grid<objects::sphere<double, 3>>,
                     uniform_grid<objects::triangle<float, 3>>, hashed_grid<B3>, hashed_grid<B2f>,
                     fine_hashed_grid<B3>, hashed_grid<spatial_test::tagged_box>>;
using grid_hard_types = ::testing::Types<uniform_grid<P3>, uniform_grid<point<float, 2>>, uniform_grid<tagged_point>,
                                         uniform_grid<B3>, uniform_grid<B2f>, hashed_grid<P3>, hashed_grid<B3>,
                                         hashed_grid<B2f>, fine_hashed_grid<B3>>;
#else
using grid_point_types = ::testing::Types<uniform_grid<P3>, uniform_grid<tagged_point>, hashed_grid<point<float, 2>>>;
using grid_object_types = ::testing::Types<uniform_grid<B3>, uniform_grid<objects::triangle<float, 3>>, hashed_grid<B2f>,
                                           hashed_grid<spatial_test::tagged_box>>;
using grid_hard_types = ::testing::Types<uniform_grid<point<float, 2>>, uniform_grid<B3>, fine_hashed_grid<B3>>;
#endif

namespace spatial_contract {
INSTANTIATE_TYPED_TEST_SUITE_P(grid_points, container_contract, grid_point_types);
INSTANTIATE_TYPED_TEST_SUITE_P(grid_objects, container_contract, grid_object_types);
}  // namespace spatial_contract
namespace og_test {
INSTANTIATE_TYPED_TEST_SUITE_P(grid, octree_grid_hard_cases, grid_hard_types);
}

namespace {

template <class C>
class grid_differential_objects : public ::testing::Test {};
using grid_round_objects = ::testing::Types<uniform_grid<objects::sphere<double, 3>>, hashed_grid<objects::triangle<float, 3>>>;
TYPED_TEST_SUITE(grid_differential_objects, grid_round_objects);
TYPED_TEST(grid_differential_objects, spheres_and_triangles_match_brute_force) {
    spatial_test::run_all_distributions<TypeParam>(77, 300);
}

TEST(uniform_grid, re_gridding_is_amortised_for_a_sorted_outward_stream) {
    uniform_grid<P3> g;
    const std::size_t n = 100000;
    for (std::size_t i = 0; i < n; ++i) g.insert(P3{{static_cast<double>(i), 0.5 * static_cast<double>(i % 7), 0.25}});
    EXPECT_EQ(g.size(), n);
    // Count doubling (log2 n) and box growth by a factor >= 1.25 (log_1.25 n ~ 3.1 log2 n)
    // each: O(log n) re-grids of geometrically growing sizes, O(n) total work.
    EXPECT_LE(g.regrid_count(), 5 * static_cast<std::size_t>(std::log2(static_cast<double>(n))) + 16);
    EXPECT_EQ(g.check_invariants(), "");
    double cells = 1;
    for (auto d : g.grid_dims()) cells *= static_cast<double>(d);
    EXPECT_LE(cells, 4.0 * static_cast<double>(n) / 2 + 64) << "the dense array stays O(n)";
}

TEST(uniform_grid, shrinking_re_grids_to_a_smaller_array) {
    uniform_grid<P3> g;
    spatial_test::point_source<P3> src(spatial_test::distribution::uniform, 4);
    std::vector<P3> pts;
    for (int i = 0; i < 20000; ++i) pts.push_back(src.next());
    g.insert(pts.begin(), pts.end());
    const std::size_t grids = g.regrid_count();
    for (int i = 0; i < 19000; ++i) g.erase(g.begin());
    EXPECT_GT(g.regrid_count(), grids);
    EXPECT_EQ(g.check_invariants(), "");
    EXPECT_EQ(g.size(), 1000u);
}

TEST(hashed_grid, sparse_scene_spanning_1e15_cells_answers_quickly_and_exactly) {
    hashed_grid<P3> g(1.0);
    brute_force<P3> b;
    for (int i = 0; i < 50; ++i) {
        const P3 p{{i * 1.0, 0, 0}}, q{{1e15 + i, 0, 0}};
        g.insert(p);
        g.insert(q);
        b.insert(p);
        b.insert(q);
    }
    EXPECT_LE(g.occupied_cells(), 100u);
    const auto start = std::chrono::steady_clock::now();
    const P3 mid{{5e14, 0.25, 0}};
    EXPECT_EQ(spatial_test::distances_from(mid, g.find_nearest(mid, 3)), spatial_test::distances_from(mid, b.find_nearest(mid, 3)));
    intersect_info<P3> a, e;
    const P3 o{{-5, 0, 0}}, d{{1, -0.0, 0.0}};
    ASSERT_EQ(g.intersect(o, d, a), b.intersect(o, d, e));
    EXPECT_EQ(a.hit_time, e.hit_time);
    intersect_info<P3> a2, e2;
    const P3 o2{{60, 0, 0}};
    ASSERT_EQ(g.intersect(o2, d, a2), b.intersect(o2, d, e2));  // crosses the 1e15-cell gap
    EXPECT_EQ(a2.hit_time, e2.hit_time);
    EXPECT_EQ(g.find_in_box(P3{{-1, -1, -1}}, P3{{2e15, 1, 1}}).size(), 100u);
    EXPECT_EQ(g.find_in_ball(mid, 6e14).size(), 100u);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_LT(seconds, 1.0) << "sparse fall-backs must avoid walking empty cells";
}

// k nearest from between dense clusters: the shells of cells around such a query grow far
// past two blocks before they reach an object, so the search goes on a block at a time
// (cell_blocks.hpp, grid_core's nearest_by_blocks), skipping empty blocks and pruning blocks
// and cells beyond the k-th distance. Exact against brute force for points and small boxes,
// in a uniform grid and in hashed grids around negative coordinates (cells below zero: the
// block of a cell is floor(c / 8)), with queries inside and outside the data's bounds, k up
// to more than a cluster holds, eps 0 and 0.5 (within the bound), among a sparse background
// of objects; then again after one
// cluster is erased (its blocks counted empty) and after a batch is put back in its place.
template <class G>
void check_knn_between_clusters(G g, std::uint64_t seed, std::size_t clustered = 12000) {
    using O = typename G::value_type;
    using T = typename O::scalar_type;
    constexpr std::size_t D = O::dimension;
    using P = point<T, D>;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> spread(-4, 4), noise(-0.03, 0.03), wide(-5.5, 5.5);
    std::vector<P> centres(6);
    for (P& c : centres)
        for (std::size_t i = 0; i < D; ++i) c[i] = static_cast<T>(spread(rng));
    auto make = [&](std::size_t cluster) {
        P p;
        for (std::size_t i = 0; i < D; ++i) p[i] = static_cast<T>(centres[cluster][i] + noise(rng));
        if constexpr (std::is_same_v<O, P>) {
            return p;
        } else {
            P hi = p;
            for (std::size_t i = 0; i < D; ++i) hi[i] = static_cast<T>(p[i] + 0.004);
            return O(p, hi);
        }
    };
    std::vector<O> objects;
    for (std::size_t k = 0; k < clustered; ++k) objects.push_back(make(k % centres.size()));
    // A sparse background between the clusters: the k nearest of a far query then lie at
    // many distances, so a search that stopped a shell of blocks too early would miss one.
    for (std::size_t k = 0; k < 300; ++k) {
        P c;
        for (std::size_t i = 0; i < D; ++i) c[i] = static_cast<T>(wide(rng));
        if constexpr (std::is_same_v<O, P>) objects.push_back(c);
        else objects.push_back(O(c, c));
    }
    g.insert(objects.begin(), objects.end());
    brute_force<O> b(objects.begin(), objects.end());
    auto compare = [&](const char* when) {
        SCOPED_TRACE(when);
        for (std::size_t q = 0; q < 40; ++q) {
            P x;
            for (std::size_t i = 0; i < D; ++i) x[i] = static_cast<T>(wide(rng));
            for (std::size_t k : {std::size_t{1}, std::size_t{7}, std::size_t{2500}}) {
                const auto want = spatial_test::distances_from(x, b.find_nearest(x, k));
                ASSERT_EQ(spatial_test::distances_from(x, g.find_nearest(x, k)), want) << "query " << q << " k " << k;
                const auto approx = spatial_test::distances_from(x, g.find_nearest(x, k, T(0.5)));
                ASSERT_EQ(approx.size(), want.size());
                EXPECT_LE(approx.back(), 1.5 * 1.5 * want.back() * (1 + 1e-5)) << "query " << q << " k " << k;
            }
        }
    };
    compare("all clusters");
    // Cluster 0 goes: the grid's slots follow the batch, so slot i holds objects[i]. The
    // oracle is built anew from the objects kept (erasing each by value from it cost a scan
    // of every object per erase: most of this test's time under the sanitizers).
    auto in_cluster_0 = [&](std::size_t i) { return i < clustered && i % centres.size() == 0; };
    std::vector<typename G::iterator> erased;
    for (auto it = g.begin(); it != g.end(); ++it)
        if (in_cluster_0(it.slot())) erased.push_back(it);
    for (auto it : erased) g.erase(it);
    std::vector<O> kept;
    for (std::size_t i = 0; i < objects.size(); ++i)
        if (!in_cluster_0(i)) kept.push_back(objects[i]);
    b = brute_force<O>(kept.begin(), kept.end());
    compare("one cluster erased");
    std::vector<O> batch;
    for (std::size_t k = 0; k < 2000; ++k) batch.push_back(make(0));
    g.insert(batch.begin(), batch.end());
    b.insert(batch.begin(), batch.end());
    compare("a batch in its place");
}

TEST(grid_knn, between_dense_clusters_goes_on_by_blocks_and_stays_exact) {
    const spatial_test::logged_seed seed(120);
    // A uniform grid goes by blocks once its occupied cells span a block's worth (512 cells
    // in 3D); with one cell an object, 40,000 objects span many blocks.
    check_knn_between_clusters(uniform_grid<P3, uniform_grid_config<1>>(), seed, 40000);
    check_knn_between_clusters(hashed_grid<P3>(0.01), seed);
    check_knn_between_clusters(hashed_grid<B3>(0.01), seed);
    check_knn_between_clusters(uniform_grid<B2f>(), seed);
    check_knn_between_clusters(hashed_grid<point<float, 2>>(0.005f), seed);
}

TEST(hashed_grid, an_object_spanning_many_cells_is_reported_once_and_erased_from_all) {
    hashed_grid<B3> g(0.1);
    const B3 big(P3{{0, 0, 0}}, P3{{0.35, 0.35, 0.35}});  // 4^3 cells: still listed in its cells
    g.insert(big);
    g.insert(B3(P3{{0.2, 0.2, 0.2}}, P3{{0.2, 0.2, 0.2}}));
    EXPECT_EQ(g.occupied_cells(), 64u);
    EXPECT_EQ(g.large_objects(), 0u);
    EXPECT_EQ(g.find_in_box(P3{{-1, -1, -1}}, P3{{2, 2, 2}}).size(), 2u);
    EXPECT_EQ(g.find_in_ball(P3{{0.2, 0.2, 0.2}}, 3).size(), 2u);
    EXPECT_EQ(g.find_nearest(P3{{0.2, 0.2, 0.2}}, 5).size(), 2u);
    EXPECT_EQ(g.self_pairs().size(), 1u);
    intersect_info<P3> info;
    const auto it = g.intersect_object(P3{{-1, 0.1, 0.1}}, P3{{1, 0, 0}}, 0, info);
    ASSERT_TRUE(it != g.end());
    EXPECT_EQ(*it, big);
    EXPECT_EQ(info.hit_time, 1.0);
    EXPECT_EQ(g.erase(big), 1u);
    EXPECT_EQ(g.occupied_cells(), 1u);
    EXPECT_EQ(g.check_invariants(), "");
}

// An object over more than 4^D cells is kept in the list of large objects, not in its cells:
// a box of 10^12 cells (it was refused with std::length_error past 2^24 cells, and one of
// 2^24 cells cost 2^24 map entries) is stored in O(1), found by every query, paired, erased.
TEST(hashed_grid, an_object_over_many_cells_is_kept_among_the_large_objects_and_answered_exactly) {
    hashed_grid<B3> g(1e-3);
    brute_force<B3> b;
    const B3 small(P3{{0, 0, 0}}, P3{{0.001, 0.001, 0.001}}), floor(P3{{-500, -500, -1}}, P3{{500, 500, 0}}),
        wall(P3{{0.0005, -10, -10}}, P3{{0.0006, 10, 10}}), far(P3{{2, 2, 2}}, P3{{2.0005, 2.0005, 2.0005}});
    for (const B3& x : {small, floor, wall, far}) {
        g.insert(x);
        b.insert(x);
    }
    EXPECT_EQ(g.size(), 4u);
    EXPECT_EQ(g.large_objects(), 2u);
    EXPECT_LE(g.occupied_cells(), 16u);
    EXPECT_EQ(g.check_invariants(), "");
    EXPECT_EQ(g.count(floor), 1u);
    EXPECT_EQ(spatial_test::signatures_of(g.find_in_box(P3{{-1, -1, -1}}, P3{{0.0001, 0.0001, 0.0001}})),
              spatial_test::signatures_of(b.find_in_box(P3{{-1, -1, -1}}, P3{{0.0001, 0.0001, 0.0001}})));
    EXPECT_EQ(g.find_in_box(P3{{1.9, 1.9, 1.9}}, P3{{2.1, 2.1, 2.1}}).size(), 1u);
    EXPECT_EQ(g.find_in_ball(P3{{0, 0, 0.5}}, 0.5).size(), 3u);  // small, floor, wall
    for (std::size_t k = 1; k <= 4; ++k) {
        const P3 q{{2, 2, 1.5}};
        EXPECT_EQ(spatial_test::distances_from(q, g.find_nearest(q, k)), spatial_test::distances_from(q, b.find_nearest(q, k)));
    }
    EXPECT_EQ(g.self_pairs().size(), b.self_pairs().size());
    EXPECT_EQ(g.self_pairs().size(), 3u);  // small-floor, small-wall, floor-wall
    intersect_info<P3> a, e;
    const P3 o{{0.2, 0.2, 5}}, d{{0, 0, -1}};
    const auto hit = g.intersect_object(o, d, 0, a);
    ASSERT_TRUE(hit != g.end());
    EXPECT_EQ(*hit, floor);
    ASSERT_TRUE(b.intersect_object(o, d, 0, e) != b.end());
    EXPECT_EQ(a.hit_time, e.hit_time);
    EXPECT_EQ(g.erase(floor), 1u);
    EXPECT_EQ(g.large_objects(), 1u);
    EXPECT_EQ(g.find_in_ball(P3{{0, 0, 0.5}}, 0.5).size(), 2u);
    EXPECT_EQ(g.check_invariants(), "");
    // A bulk insert of large objects, then a ray that only they can stop.
    const std::vector<B3> slabs{B3(P3{{-1e6, -1e6, 3}}, P3{{1e6, 1e6, 3.5}}), B3(P3{{-1e6, -1e6, 7}}, P3{{1e6, 1e6, 8}})};
    g.insert(slabs.begin(), slabs.end());
    EXPECT_EQ(g.large_objects(), 3u);
    EXPECT_EQ(g.check_invariants(), "");
    intersect_info<P3> up;
    const auto roof = g.intersect_object(P3{{5, 5, 5}}, P3{{0, 0, 1}}, 0, up);
    ASSERT_TRUE(roof != g.end());
    EXPECT_EQ(*roof, slabs[1]);
    EXPECT_EQ(up.hit_time, 2.0);
    g.clear();
    EXPECT_EQ(g.large_objects(), 0u);
    EXPECT_EQ(g.check_invariants(), "");
}

// The uniform grid keeps an object much larger than its cells among the large objects too,
// and a re-grid moves objects between the cells and that list as the cell size changes.
TEST(uniform_grid, objects_much_larger_than_the_cells_are_large_objects_and_a_regrid_reclassifies_them) {
    uniform_grid<B3> g;
    brute_force<B3> b;
    std::mt19937_64 rng(20261127);
    std::uniform_real_distribution<double> u(0, 100);
    std::vector<B3> boxes;
    // 5,000 boxes (brute-force pairs stay quick under the sanitizers): the default cell is
    // then several box widths wide, and the floor still covers far more than the 4^D cells of
    // a large object (asserted below).
    for (int i = 0; i < 5000; ++i) {
        const P3 lo{{u(rng), u(rng), u(rng)}};
        boxes.push_back(B3(lo, P3{{lo[0] + 0.5, lo[1] + 0.5, lo[2] + 0.5}}));
    }
    boxes.push_back(B3(P3{{0, 0, 0}}, P3{{100, 100, 1}}));  // a floor over the whole scene
    g.insert(boxes.begin(), boxes.end());
    b.insert(boxes.begin(), boxes.end());
    EXPECT_GE(g.large_objects(), 1u);
    EXPECT_EQ(g.check_invariants(), "");
    EXPECT_EQ(g.self_pairs().size(), b.self_pairs().size());
    const P3 q{{50, 50, 0.5}};
    EXPECT_EQ(spatial_test::distances_from(q, g.find_nearest(q, 5)), spatial_test::distances_from(q, b.find_nearest(q, 5)));
    // Erasing all but the floor and a few small boxes shrinks the grid's box (a re-grid).
    const std::size_t grids = g.regrid_count();
    while (g.size() > 20) g.erase(g.begin());
    EXPECT_GT(g.regrid_count(), grids);
    EXPECT_EQ(g.check_invariants(), "");
}

TEST(hashed_grid, rejects_bad_cell_sizes) {
    EXPECT_THROW(hashed_grid<P3>(0.0), std::invalid_argument);
    EXPECT_THROW(hashed_grid<P3>(-1.0), std::invalid_argument);
    // Braces: with parentheses, clang reads the statement as a declaration of quiet_NaN.
    EXPECT_THROW(hashed_grid<P3>{std::numeric_limits<double>::quiet_NaN()}, std::invalid_argument);
}

}  // namespace

// hashed_cells::add_batch groups a batch by the low 32 bits of the cells' hashes: two cells
// whose hashes agree there (found by search among 2^18 cells) must still get their own lists.
TEST(hashed_grid, bulk_listing_separates_cells_whose_hashes_collide) {
    using cells = detail::hashed_cells<3>;
    using key = detail::cell_key<3>;
    const detail::teschner_hash<3> hash;
    std::vector<std::pair<std::uint32_t, key>> seen;
    for (std::int64_t i = 0; i < 512; ++i)
        for (std::int64_t j = 0; j < 512; ++j) seen.push_back({static_cast<std::uint32_t>(hash(key{i, j, 0})), key{i, j, 0}});
    std::sort(seen.begin(), seen.end());
    std::size_t at = 0;
    while (at + 1 < seen.size() && seen[at].first != seen[at + 1].first) ++at;
    ASSERT_LT(at + 1, seen.size()) << "no 32-bit hash collision among 2^18 cells";
    const key a = seen[at].second, b = seen[at + 1].second;
    ASSERT_NE(a, b);
    std::vector<detail::cell_entry<3>> batch;
    for (slot_index s = 0; s < 10; ++s) batch.push_back({s % 2 ? a : b, s});
    batch.push_back({key{7, 7, 7}, 10});
    cells c;
    c.add_batch(batch);
    ASSERT_EQ(c.occupied_cells(), 3.0);
    auto sorted_slots = [&](const key& k) {
        const detail::slot_list* list = c.find(k);
        std::vector<slot_index> v(list->begin(), list->end());
        std::sort(v.begin(), v.end());
        return v;
    };
    EXPECT_EQ(sorted_slots(a), (std::vector<slot_index>{1, 3, 5, 7, 9}));
    EXPECT_EQ(sorted_slots(b), (std::vector<slot_index>{0, 2, 4, 6, 8}));
    EXPECT_EQ(sorted_slots(key{7, 7, 7}), (std::vector<slot_index>{10}));
    EXPECT_EQ(c.bounds().lo, (key{std::min({a[0], b[0], std::int64_t{7}}), std::min({a[1], b[1], std::int64_t{7}}), 0}));
}

// A cell's slot list keeps up to four slots in itself and moves to one heap block past that:
// contents, copies (deep), moves (the source left empty), removal and the reservation that
// grows as push_backs would must all behave as the std::vector the grids used before.
TEST(grid_cells, slot_list_keeps_small_cells_inline_and_grows_like_a_vector) {
    using detail::slot_list;
    auto contents_of = [](const slot_list& l) { return std::vector<slot_index>(l.begin(), l.end()); };
    slot_list a;
    EXPECT_TRUE(a.empty());
    for (slot_index s = 0; s < slot_list::inline_slots; ++s) a.push_back(s);
    EXPECT_EQ(a.heap_bytes(), 0u) << "four slots fit in the list itself";
    a.push_back(4);
    EXPECT_EQ(a.capacity(), 8u) << "a full list doubles";
    EXPECT_EQ(a.heap_bytes(), 8 * sizeof(slot_index));
    EXPECT_EQ(contents_of(a), (std::vector<slot_index>{0, 1, 2, 3, 4}));

    slot_list copy = a;  // deep: changing the copy leaves a alone
    copy.remove(0);
    EXPECT_EQ(contents_of(copy), (std::vector<slot_index>{4, 1, 2, 3})) << "the last slot takes the removed one's place";
    EXPECT_EQ(contents_of(a), (std::vector<slot_index>{0, 1, 2, 3, 4}));
    copy.remove(99);  // absent: nothing changes
    EXPECT_EQ(copy.size(), 4u);

    slot_list small;
    small.push_back(7);
    slot_list moved_small = std::move(small), moved_big = std::move(a);
    EXPECT_EQ(contents_of(moved_small), (std::vector<slot_index>{7}));
    EXPECT_EQ(contents_of(moved_big), (std::vector<slot_index>{0, 1, 2, 3, 4}));
    EXPECT_TRUE(small.empty());
    EXPECT_TRUE(a.empty());
    EXPECT_EQ(a.heap_bytes(), 0u) << "a moved-from list owns no block";

    moved_small.swap(moved_big);
    EXPECT_EQ(contents_of(moved_small), (std::vector<slot_index>{0, 1, 2, 3, 4}));
    EXPECT_EQ(contents_of(moved_big), (std::vector<slot_index>{7}));
    moved_big = moved_small;  // copy assignment from a heap list
    EXPECT_EQ(contents_of(moved_big), contents_of(moved_small));

    slot_list reserved;  // reserve_for_push grows to the capacity the push_backs would reach
    detail::reserve_for_push(reserved, 9);
    EXPECT_EQ(reserved.capacity(), 16u);
    detail::reserve_for_push(reserved, 3);
    EXPECT_EQ(reserved.capacity(), 16u);
}

// A bulk batch into a grid holding objects: same contents and answers as the loop, and the
// dense grid's lists are filled in one pass (the batch grouped by cell).
TEST(uniform_grid, bulk_merge_into_a_filled_grid_matches_a_loop) {
    std::mt19937_64 rng(20261127);
    auto unit = [&] { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };
    std::vector<P3> base(3000), more(300);
    for (auto& p : base) p = P3{unit(), unit(), unit()};
    for (auto& p : more) p = P3{unit(), unit(), unit()};
    more.insert(more.end(), base.begin(), base.begin() + 50);  // duplicates of stored points
    uniform_grid<P3> bulk(base.begin(), base.end()), loop(base.begin(), base.end());
    bulk.insert(more.begin(), more.end());
    for (const P3& p : more) loop.insert(p);
    ASSERT_EQ(bulk.check_invariants(), "");
    ASSERT_EQ(spatial_test::contents(bulk), spatial_test::contents(loop));
    for (int q = 0; q < 50; ++q) {
        const P3 x{unit(), unit(), unit()};
        ASSERT_EQ(spatial_test::distances_from(x, bulk.find_nearest(x, 7)), spatial_test::distances_from(x, loop.find_nearest(x, 7)));
        ASSERT_EQ(spatial_test::distances_from(x, bulk.find_in_ball(x, 0.1)), spatial_test::distances_from(x, loop.find_in_ball(x, 0.1)));
    }
    for (std::size_t i = 0; i < 50; ++i) ASSERT_EQ(bulk.count(base[i]), 2u);
}
