// Collision under motion: the counting-sort grid (collide/cell_sort_grid.hpp) against an
// O(n^2) loop on hard inputs (touching faces on an integer grid, identical boxes, zero
// extents, one huge box, heavy-tailed sizes, 2D and 3D, bipartite); the BVH's motion API
// (update(first, last, strategy) with refit / rebuild / reinsert / automatic) against
// brute force over many steps; and the pair-set tracker's added / removed sets.
// Seeds are logged.

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <iterator>
#include <limits>
#include <mutex>
#include <random>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include "spatial/brute/brute_force.hpp"
#include "spatial/bv/obb.hpp"
#include "spatial/bv/sphere.hpp"
#include "spatial/bvh/bvh.hpp"
#include "spatial/collide/cell_sort_grid.hpp"
#include "spatial/collide/collision_grid.hpp"
#include "spatial/collide/pair_changes.hpp"
#include "test_support.hpp"

using namespace spatial;

namespace {

using pair32 = std::pair<std::uint32_t, std::uint32_t>;

template <class T, std::size_t D>
std::vector<pair32> brute_pairs(const std::vector<collide::box_bounds<T, D>>& a,
                                const std::vector<collide::box_bounds<T, D>>* b = nullptr) {
    std::vector<pair32> out;
    if (b == nullptr) {
        for (std::uint32_t i = 0; i < a.size(); ++i)
            for (std::uint32_t j = i + 1; j < a.size(); ++j)
                if (collide::closed_boxes_overlap(a[i], a[j])) out.emplace_back(i, j);
    } else {
        for (std::uint32_t i = 0; i < a.size(); ++i)
            for (std::uint32_t j = 0; j < b->size(); ++j)
                if (collide::closed_boxes_overlap(a[i], (*b)[j])) out.emplace_back(i, j);
    }
    return out;
}

template <class T, std::size_t D>
std::vector<pair32> grid_self(collide::cell_sort_grid<T, D>& g, const std::vector<collide::box_bounds<T, D>>& boxes) {
    std::vector<pair32> out;
    g.self_pairs(boxes, [&](std::uint32_t i, std::uint32_t j) { out.emplace_back(std::min(i, j), std::max(i, j)); });
    const std::size_t reported = out.size();
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    EXPECT_EQ(out.size(), reported) << "a pair reported twice";
    return out;
}

// Boxes of several kinds: integer-grid boxes (shared faces, edges, corners; duplicates),
// zero-extent boxes (points), heavy-tailed sizes, and optionally one box covering all.
template <class T, std::size_t D>
std::vector<collide::box_bounds<T, D>> hard_boxes(std::mt19937_64& rng, std::size_t n, bool huge) {
    std::vector<collide::box_bounds<T, D>> out(n);
    std::uniform_real_distribution<double> u(0, 1);
    std::uniform_int_distribution<int> g(0, 10);
    for (std::size_t k = 0; k < n; ++k) {
        auto& b = out[k];
        for (std::size_t i = 0; i < D; ++i) {
            switch (k % 4) {
                case 0:  // grid cell boxes: touching neighbours
                    b.lo[i] = static_cast<T>(g(rng));
                    b.hi[i] = b.lo[i] + 1;
                    break;
                case 1:  // zero extent on the grid
                    b.lo[i] = b.hi[i] = static_cast<T>(g(rng));
                    break;
                case 2: {  // heavy tail: Pareto(1.5) edge, capped at the domain
                    const double edge = std::min(0.05 / std::pow(1 - u(rng), 1 / 1.5), 11.0);
                    b.lo[i] = static_cast<T>(u(rng) * 11);
                    b.hi[i] = static_cast<T>(b.lo[i] + edge);
                    break;
                }
                default:
                    b.lo[i] = static_cast<T>(u(rng) * 11);
                    b.hi[i] = static_cast<T>(b.lo[i] + 0.3 * u(rng));
            }
        }
    }
    if (huge && n > 0)
        for (std::size_t i = 0; i < D; ++i) out[n / 2].lo[i] = -1, out[n / 2].hi[i] = 12;
    return out;
}

template <class T, std::size_t D>
void check_cell_sort_grid(std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    collide::cell_sort_grid<T, D> g;
    for (std::size_t n : {0u, 1u, 2u, 50u, 1500u})
        for (bool huge : {false, true}) {
            SCOPED_TRACE(::testing::Message() << "n " << n << " huge " << huge);
            const auto boxes = hard_boxes<T, D>(rng, n, huge);
            EXPECT_EQ(grid_self(g, boxes), brute_pairs(boxes));
            const auto other = hard_boxes<T, D>(rng, n / 2 + 1, false);
            std::vector<pair32> bi;
            g.bipartite_pairs(boxes, other, [&](std::uint32_t i, std::uint32_t j) { bi.emplace_back(i, j); });
            std::sort(bi.begin(), bi.end());
            EXPECT_TRUE(std::adjacent_find(bi.begin(), bi.end()) == bi.end()) << "a pair reported twice";
            EXPECT_EQ(bi, brute_pairs(boxes, &other));
        }
    // Identical boxes: every pair once, in one cell. 31 to 33 straddle the largest cell that
    // is joined in a local SIMD block (32 entries); 40 takes the plain loop.
    for (std::size_t m : {3u, 4u, 5u, 31u, 32u, 33u, 40u}) {
        const std::vector<collide::box_bounds<T, D>> same(m, hard_boxes<T, D>(rng, 1, false)[0]);
        EXPECT_EQ(grid_self(g, same).size(), m * (m - 1) / 2) << m << " identical boxes";
    }
    // All boxes the same point: the mean edge is 0, the grid must still work.
    collide::box_bounds<T, D> p;
    p.lo.fill(T(3));
    p.hi.fill(T(3));
    EXPECT_EQ(grid_self(g, std::vector<collide::box_bounds<T, D>>(10, p)).size(), 45u);
}

TEST(collide_cell_sort_grid, equals_the_quadratic_loop_on_hard_inputs) {
    const spatial_test::logged_seed seed(201);
    check_cell_sort_grid<double, 3>(seed);
    check_cell_sort_grid<float, 3>(seed);
    check_cell_sort_grid<double, 2>(seed);
    check_cell_sort_grid<float, 2>(seed);
    check_cell_sort_grid<double, 4>(seed);  // the last dimension with 32-bit entries
    check_cell_sort_grid<double, 5>(seed);  // 64-bit entries, no small-span tables
}

// The parallel query's slabs (cut along the last axis, boxes clipped to each) give the
// sequential answer for every slab count: each pair once, none lost at a slab boundary.
// Counts beyond the grid's layers collapse to fewer slabs.
template <class T, std::size_t D>
void check_slabs(std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    collide::cell_sort_grid<T, D> g;
    const auto keep_all = [](std::uint32_t, std::uint32_t) { return true; };
    for (std::size_t n : {0u, 1u, 2u, 50u, 1500u})
        for (bool huge : {false, true}) {
            const auto boxes = hard_boxes<T, D>(rng, n, huge);
            const auto want = brute_pairs(boxes);
            for (std::size_t slabs : {1u, 2u, 3u, 7u, 64u, 100000u}) {
                SCOPED_TRACE(::testing::Message() << "n " << n << " huge " << huge << " slabs " << slabs);
                std::vector<pair32> got;
                g.self_pairs_in_slabs(boxes, slabs, keep_all, [&](std::uint32_t i, std::uint32_t j) { got.emplace_back(i, j); });
                const std::size_t reported = got.size();
                for (auto& [i, j] : got) {
                    ASSERT_NE(i, j);
                    if (i > j) std::swap(i, j);
                }
                std::sort(got.begin(), got.end());
                EXPECT_EQ(std::unique(got.begin(), got.end()), got.end()) << "a pair reported twice";
                EXPECT_EQ(got.size(), reported);
                EXPECT_EQ(got, want);
                // Delivered where found: each pair once, from a slab below the count asked.
                std::vector<pair32> where_found;
                std::size_t bad_slab = 0;
                std::mutex lock;  // the slabs' threads report concurrently
                g.self_pairs_in_slabs_concurrently(boxes, slabs, [&](std::size_t k, std::uint32_t i, std::uint32_t j) {
                    const std::lock_guard<std::mutex> hold(lock);
                    bad_slab += k >= slabs;
                    where_found.emplace_back(std::min(i, j), std::max(i, j));
                });
                EXPECT_EQ(bad_slab, 0u);
                std::sort(where_found.begin(), where_found.end());
                EXPECT_EQ(where_found, want);
            }
        }
    // Enough boxes for several chunks of the slabs' member lists (16,384 boxes a chunk): each
    // slab's list in input order, against the sequential query (checked against brute force
    // above), pair for pair and in the same order within a slab count's answer.
    {
        std::uniform_real_distribution<double> u(0, 1);
        std::vector<collide::box_bounds<T, D>> many(70000);
        const double edge = 0.5 * std::pow(2.0 / 70000, 1.0 / static_cast<double>(D));  // ~2 overlaps a box
        for (auto& b : many)
            for (std::size_t i = 0; i < D; ++i) b.lo[i] = static_cast<T>(u(rng)), b.hi[i] = static_cast<T>(b.lo[i] + edge);
        std::vector<pair32> want;
        g.self_pairs(many, [&](std::uint32_t i, std::uint32_t j) { want.emplace_back(std::min(i, j), std::max(i, j)); });
        std::sort(want.begin(), want.end());
        for (std::size_t slabs : {2u, 3u, 7u}) {
            SCOPED_TRACE(::testing::Message() << "70000 boxes, slabs " << slabs);
            std::vector<pair32> got, again;
            g.self_pairs_in_slabs(many, slabs, keep_all, [&](std::uint32_t i, std::uint32_t j) { got.emplace_back(i, j); });
            g.self_pairs_in_slabs(many, slabs, keep_all, [&](std::uint32_t i, std::uint32_t j) { again.emplace_back(i, j); });
            EXPECT_EQ(got, again) << "the order of the answer changed between two runs";
            for (auto& [i, j] : got)
                if (i > j) std::swap(i, j);
            std::sort(got.begin(), got.end());
            EXPECT_EQ(got, want);
        }
    }
    // The filter runs on candidates whose boxes overlap: keeping the pairs of even sums keeps
    // exactly those of the brute-force answer.
    const auto boxes = hard_boxes<T, D>(rng, 800, false);
    std::vector<pair32> want, got;
    for (const auto& pr : brute_pairs(boxes))
        if ((pr.first + pr.second) % 2 == 0) want.push_back(pr);
    g.self_pairs_in_slabs(boxes, 3, [](std::uint32_t i, std::uint32_t j) { return (i + j) % 2 == 0; },
                          [&](std::uint32_t i, std::uint32_t j) { got.emplace_back(i, j); });
    for (auto& [i, j] : got)
        if (i > j) std::swap(i, j);
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, want);
}

TEST(collide_cell_sort_grid, slabs_of_a_parallel_query_give_the_sequential_answer_for_any_count) {
    const spatial_test::logged_seed seed(202);
    check_slabs<double, 3>(seed);
    check_slabs<float, 3>(seed);
    check_slabs<double, 2>(seed);
    check_slabs<double, 5>(seed);  // no small-span tables: every box on the general path
}

// The primitive behind the slabs' query (core/parallel.hpp): every part runs once, part 0
// and then() on the calling thread, then() after part 0 and before the call returns; an
// exception from any of them comes out of the call (the parts not yet started may be
// cancelled: TBB cancels a task group on an exception).
TEST(parallel_for_then, runs_every_part_and_then_follows_part_zero_on_the_calling_thread) {
    const auto caller = std::this_thread::get_id();
    for (const std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{2}, std::size_t{7}}) {
        SCOPED_TRACE(::testing::Message() << n << " parts");
        std::vector<std::atomic<int>> ran(n);
        bool zero_on_caller = false, then_on_caller = false, zero_before_then = n == 0;
        int thens = 0;
        spatial::detail::parallel_for_then(
            n,
            [&](std::size_t k) {
                ran[k].fetch_add(1);
                if (k == 0) zero_on_caller = std::this_thread::get_id() == caller;
            },
            [&] {
                ++thens;
                then_on_caller = std::this_thread::get_id() == caller;
                if (n > 0) zero_before_then = ran[0].load() == 1;
            });
        for (std::size_t k = 0; k < n; ++k) EXPECT_EQ(ran[k].load(), 1) << "part " << k;
        EXPECT_EQ(thens, 1);
        EXPECT_TRUE(then_on_caller);
        EXPECT_TRUE(zero_before_then);
        if (n > 0) {
            EXPECT_TRUE(zero_on_caller);
        }
    }
    std::vector<std::atomic<int>> ran(6);
    EXPECT_THROW(spatial::detail::parallel_for_then(
                     6,
                     [&](std::size_t k) {
                         ran[k].fetch_add(1);
                         if (k == 3) throw std::runtime_error("part 3");
                     },
                     [] { throw std::logic_error("then"); }),
                 std::exception);
    EXPECT_EQ(ran[0].load(), 1);
    for (std::size_t k = 0; k < 6; ++k) EXPECT_LE(ran[k].load(), 1) << "part " << k << " ran at most once (a failure may cancel the rest)";
}

TEST(collide_cell_sort_grid, memory_stays_linear_when_boxes_are_spread_out) {
    // Two clusters of tiny boxes far apart: the cell cap keeps cells <= 4 n.
    std::vector<collide::box_bounds<double, 3>> boxes(2000);
    for (std::size_t k = 0; k < boxes.size(); ++k) {
        const double base = k % 2 ? 1e6 : 0;
        for (std::size_t i = 0; i < 3; ++i) boxes[k].lo[i] = base + 1e-3 * static_cast<double>(k), boxes[k].hi[i] = boxes[k].lo[i] + 1e-4;
    }
    collide::cell_sort_grid<double, 3> g;
    EXPECT_EQ(grid_self(g, boxes), brute_pairs(boxes));
    EXPECT_LE(g.last_query_stats().cells, 4 * boxes.size());
}

// ---- BVH motion ------------------------------------------------------------------------

using B3 = objects::box<double, 3>;
using P3 = point<double, 3>;

template <class Tree>
class bvh_motion : public ::testing::Test {};
using motion_trees = ::testing::Types<bvh<B3>, bvh<B3, aabb<double, 3>, bvh_median_config<>>, bvh<B3, sphere<double, 3>>,
                                      bvh<objects::sphere<double, 3>, obb<double, 3>>>;
TYPED_TEST_SUITE(bvh_motion, motion_trees);

template <class O>
O moved(const O& x, const P3& d) {
    if constexpr (std::is_same_v<O, B3>) {
        B3 b = x;
        for (std::size_t i = 0; i < 3; ++i) b.lo[i] += d[i], b.hi[i] += d[i];
        return b;
    } else {
        P3 c = x.center();
        for (std::size_t i = 0; i < 3; ++i) c[i] += d[i];
        return O(c, x.radius());
    }
}
template <class O>
O random_object(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(0, 1), r(0.005, 0.03);
    const P3 c{{u(rng), u(rng), u(rng)}};
    const double h = r(rng);
    if constexpr (std::is_same_v<O, B3>) return B3(P3{{c[0] - h, c[1] - h, c[2] - h}}, P3{{c[0] + h, c[1] + h, c[2] + h}});
    else return O(c, h);
}
// n objects of random_object<O>(rng).
template <class O>
std::vector<O> random_objects(std::mt19937_64& rng, int n) {
    std::vector<O> v;
    for (int k = 0; k < n; ++k) v.push_back(random_object<O>(rng));
    return v;
}

TYPED_TEST(bvh_motion, every_strategy_keeps_pairs_equal_to_brute_force_over_many_steps) {
    using Tree = TypeParam;
    using O = typename Tree::value_type;
    spatial_test::seeded_rng rng(202);
    std::vector<O> objects = random_objects<O>(rng, 800);
    std::normal_distribution<double> step(0, 0.01);
    for (motion_strategy strategy : {motion_strategy::refit, motion_strategy::rebuild, motion_strategy::reinsert,
                                     motion_strategy::automatic}) {
        SCOPED_TRACE(to_string(strategy));
        Tree tree(objects.begin(), objects.end());
        std::vector<typename Tree::iterator> handles;
        for (auto it = tree.begin(); it != tree.end(); ++it) handles.push_back(it);
        for (int s = 0; s < 12; ++s) {
            // Steps alternate between moving everything and moving a few (automatic: refit
            // or rebuild, then reinsert).
            const std::size_t stride = s % 2 ? 1 : 50;
            std::vector<std::pair<typename Tree::iterator, O>> moves;
            for (std::size_t i = static_cast<std::size_t>(s) % stride; i < handles.size(); i += stride)
                moves.emplace_back(handles[i], moved(*handles[i], P3{{step(rng), step(rng), step(rng)}}));
            const motion_strategy ran = tree.update(moves.begin(), moves.end(), strategy);
            if (strategy != motion_strategy::automatic) {
                EXPECT_EQ(ran, strategy);
            } else if (stride == 50) {
                EXPECT_EQ(ran, motion_strategy::reinsert);
            } else {
                EXPECT_NE(ran, motion_strategy::reinsert);
            }
            for (const auto& [it, v] : moves) EXPECT_EQ(*it, v) << "the handle no longer holds its object";
            brute_force<O> oracle;
            for (auto h : handles) oracle.insert(*h);
            auto sig = [&](const auto& pairs, auto slot_of) {
                std::vector<pair32> out;
                for (const auto& [a, b] : pairs) {
                    auto x = slot_of(a), y = slot_of(b);
                    out.emplace_back(std::min(x, y), std::max(x, y));
                }
                std::sort(out.begin(), out.end());
                return out;
            };
            // handle i <-> oracle slot i (the oracle was filled in handle order)
            std::vector<std::uint32_t> index_of_slot(tree.end().slot() + 1);
            for (std::uint32_t i = 0; i < handles.size(); ++i) index_of_slot[handles[i].slot()] = i;
            EXPECT_EQ(sig(tree.self_pairs(), [&](auto it) { return index_of_slot[it.slot()]; }),
                      sig(oracle.self_pairs(), [](auto it) { return static_cast<std::uint32_t>(it.slot()); }));
        }
        if (strategy == motion_strategy::automatic) {
            EXPECT_LE(tree.quality(), Tree::config::refit_quality_limit * tree.quality_at_build() * 1.0000001);
        }
    }
}

TEST(bvh_motion_rules, a_nan_in_a_batch_leaves_the_tree_unchanged_and_refit_quality_decays) {
    std::mt19937_64 rng(spatial_test::test_seed(203));
    std::vector<B3> boxes = random_objects<B3>(rng, 2000);
    bvh<B3> tree(boxes.begin(), boxes.end());
    std::vector<std::pair<bvh<B3>::iterator, B3>> moves;
    for (auto it = tree.begin(); it != tree.end(); ++it) moves.emplace_back(it, moved(*it, P3{{0.5, 0, 0}}));
    moves[1000].second.lo[1] = std::nan("");
    const auto before = tree.self_pairs();
    EXPECT_THROW(tree.update(moves.begin(), moves.end(), motion_strategy::refit), std::invalid_argument);
    EXPECT_EQ(tree.self_pairs(), before);
    EXPECT_EQ(*moves[0].first, boxes[0]);
    // Shuffle every box to a random new place and only refit: the tree keeps its old
    // topology, so its quality (expected nodes entered per ray) gets much worse; a rebuild
    // restores it.
    for (auto& [it, v] : moves) v = random_object<B3>(rng);
    const double fresh = tree.quality();
    tree.update(moves.begin(), moves.end(), motion_strategy::refit);
    EXPECT_GT(tree.quality(), 2 * fresh);
    tree.rebuild();
    EXPECT_LT(tree.quality(), 1.2 * fresh);
}

TEST(collide_collision_grid_motion, a_bulk_move_is_all_or_nothing_and_pairs_follow_it) {
    std::mt19937_64 rng(spatial_test::test_seed(205));
    std::vector<B3> boxes = random_objects<B3>(rng, 1500);
    collision_grid<B3> grid(boxes.begin(), boxes.end());
    std::vector<std::pair<collision_grid<B3>::iterator, B3>> moves;
    for (auto it = grid.begin(); it != grid.end(); ++it) moves.emplace_back(it, random_object<B3>(rng));
    moves[700].second.hi[2] = std::numeric_limits<double>::infinity();
    const auto before = grid.self_pairs();
    EXPECT_THROW(grid.update(moves.begin(), moves.end()), std::invalid_argument);
    EXPECT_EQ(grid.self_pairs(), before);
    EXPECT_EQ(*moves[0].first, boxes[0]);
    moves[700].second = random_object<B3>(rng);
    grid.update(moves.begin(), moves.end());
    brute_force<B3> oracle;
    for (const auto& [it, v] : moves) {
        EXPECT_EQ(*it, v);
        oracle.insert(v);
    }
    // Both allocated slots in order, so pairs compare slot for slot.
    auto slots = [](const auto& pairs) {
        std::vector<pair32> out;
        for (const auto& [a, b] : pairs) out.emplace_back(a.slot(), b.slot());
        return out;
    };
    EXPECT_EQ(slots(grid.self_pairs()), slots(oracle.self_pairs()));
}

// The pairs of for_each_self_pair_concurrently, collected per part and sorted. Checks the
// delivery's promises on the way: every part below parallel_threads(), lower slot first, and
// no two calls of one part at once (a call that finds its part busy fails).
template <class Grid>
auto concurrently_delivered_pairs(const Grid& grid, pair_filter filter) {
    const std::size_t parts = detail::parallel_threads();
    std::vector<std::vector<std::pair<typename Grid::iterator, typename Grid::iterator>>> found(parts);
    std::vector<std::atomic<int>> busy(parts);
    std::atomic<std::size_t> bad_part{0}, overlapping{0}, unordered{0};
    grid.for_each_self_pair_concurrently(par, filter, [&](std::size_t part, auto a, auto b) {
        if (part >= parts) {
            ++bad_part;
            return;
        }
        if (busy[part].fetch_add(1) != 0) ++overlapping;
        if (!(a.slot() < b.slot())) ++unordered;
        found[part].emplace_back(a, b);
        busy[part].fetch_sub(1);
    });
    EXPECT_EQ(bad_part.load(), 0u);
    EXPECT_EQ(overlapping.load(), 0u);
    EXPECT_EQ(unordered.load(), 0u);
    std::vector<std::pair<typename Grid::iterator, typename Grid::iterator>> all;
    for (const auto& part : found) all.insert(all.end(), part.begin(), part.end());
    sort_pairs(all);
    return all;
}

// self_pairs(par) is self_pairs(): boxes (the grid's test is exact), spheres (the narrow
// phase runs in the slabs' threads), and a grid with erased slots (boxes gathered with
// their slots, not in parallel chunks). Under TBB this runs on every core of the machine.
template <class O>
void check_parallel_self_pairs(std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    const std::vector<O> objects = random_objects<O>(rng, 3000);
    collision_grid<O> grid(objects.begin(), objects.end());
    for (pair_filter filter : {pair_filter::exact, pair_filter::candidates}) {
        const auto want = grid.self_pairs(filter);
        EXPECT_FALSE(want.empty());
        EXPECT_EQ(grid.self_pairs(par, filter), want);
        EXPECT_EQ(concurrently_delivered_pairs(grid, filter), want);
    }
    std::vector<typename collision_grid<O>::iterator> erased;
    for (auto it = grid.begin(); it != grid.end(); ++it)
        if (rng() % 3 == 0) erased.push_back(it);
    for (auto it : erased) grid.erase(it);
    const auto want = grid.self_pairs();
    EXPECT_EQ(grid.self_pairs(par), want);
    std::size_t streamed = 0;
    grid.for_each_self_pair(par, pair_filter::exact, [&](auto a, auto b) {
        EXPECT_LT(a.slot(), b.slot());
        ++streamed;
    });
    EXPECT_EQ(streamed, want.size());
    for (pair_filter filter : {pair_filter::exact, pair_filter::candidates})
        EXPECT_EQ(concurrently_delivered_pairs(grid, filter), grid.self_pairs(filter));
}

TEST(collide_collision_grid_motion, self_pairs_on_several_threads_equal_the_sequential_ones) {
    const spatial_test::logged_seed seed(212);
    check_parallel_self_pairs<B3>(seed);
    check_parallel_self_pairs<objects::sphere<double, 3>>(seed);
}

// A pair list as (slot, slot) pairs.
template <class Pairs>
std::vector<pair32> slot_pairs(const Pairs& pairs) {
    std::vector<pair32> out;
    for (const auto& [a, b] : pairs) out.emplace_back(static_cast<std::uint32_t>(a.slot()), static_cast<std::uint32_t>(b.slot()));
    return out;
}
// Brute force's self pairs of a container's live objects, as sorted (lower slot, higher slot).
template <class Container>
std::vector<pair32> brute_force_slot_pairs(const Container& c) {
    using O = typename Container::value_type;
    std::vector<std::uint32_t> slot_of;
    std::vector<O> live;
    for (auto it = c.begin(); it != c.end(); ++it) live.push_back(*it), slot_of.push_back(static_cast<std::uint32_t>(it.slot()));
    brute_force<O> oracle(live.begin(), live.end());
    std::vector<pair32> out;
    for (const auto& [a, b] : oracle.self_pairs())
        out.emplace_back(std::min(slot_of[a.slot()], slot_of[b.slot()]), std::max(slot_of[a.slot()], slot_of[b.slot()]));
    std::sort(out.begin(), out.end());
    return out;
}

// A parallel query reuses the boxes the last query gathered while nothing changed
// (collision_grid::gather_on_every_core). Every change between queries must still reach it,
// and a parallel query must not hide an update from the next sequential one (whose
// candidate list measures motion since its own last query): updates, an insert and an erase,
// with parallel and sequential queries interleaved, each answer against brute force.
TEST(collide_collision_grid_motion, parallel_pairs_follow_every_change_between_queries) {
    spatial_test::seeded_rng rng(213);
    std::vector<B3> boxes = random_objects<B3>(rng, 2000);
    collision_grid<B3> grid(boxes.begin(), boxes.end());
    auto oracle_slots = [&] { return brute_force_slot_pairs(grid); };
    auto slots = [](const auto& pairs) { return slot_pairs(pairs); };
    auto move_some = [&] {  // a small step for every box (the candidate list's case), a jump for a few
        std::vector<std::pair<collision_grid<B3>::iterator, B3>> moves;
        std::uniform_real_distribution<double> u(-0.002, 0.002);
        for (auto it = grid.begin(); it != grid.end(); ++it) {
            B3 b = *it;
            const P3 d{{u(rng), u(rng), u(rng)}};
            for (std::size_t i = 0; i < 3; ++i) b.lo[i] += d[i], b.hi[i] += d[i];
            moves.emplace_back(it, rng() % 50 == 0 ? random_object<B3>(rng) : b);
        }
        grid.update(moves.begin(), moves.end());
    };
    auto check = [&](const char* when) {
        SCOPED_TRACE(when);
        const auto want = oracle_slots();
        ASSERT_FALSE(want.empty());
        EXPECT_EQ(slots(grid.self_pairs(par)), want);
        EXPECT_EQ(slots(grid.self_pairs(par)), want);  // nothing changed: the gathered boxes serve again
        EXPECT_EQ(slots(concurrently_delivered_pairs(grid, pair_filter::exact)), want);
        EXPECT_EQ(slots(grid.self_pairs()), want);
        EXPECT_EQ(slots(grid.self_pairs(par)), want);  // after a sequential query
    };
    check("as built");
    for (int step = 0; step < 4; ++step) {
        move_some();
        check("after an update");
    }
    // Updates seen by parallel queries only, then a sequential query: its list must see them.
    for (int step = 0; step < 3; ++step) {
        move_some();
        const auto want = oracle_slots();
        EXPECT_EQ(slots(grid.self_pairs(par)), want);
        move_some();
        EXPECT_EQ(slots(grid.self_pairs()), oracle_slots());
    }
    grid.insert(random_object<B3>(rng));
    check("after an insert");
    grid.erase(std::next(grid.begin(), 17));
    check("after an erase (slots no longer dense)");
    move_some();
    check("after an update with a free slot");
}

// The moving set's candidate list (collide/fat_box_pairs.hpp): over steps of small motions
// the pairs are answered from a list (built, then reused: checked in the statistics) and
// equal brute force's at every step; a reused list delivers in increasing slot order. Then
// the cases that must leave it: a box jumping out of its fat box, an erase and an insert
// (renumbering), a query with no update (the list still serves), motion that turns at every
// step (own margins give way to a single one), motion too fast for the boxes' size (no list
// at all), and a grid with erased slots (boxes mapped to slots). Boxes and spheres (whose
// narrow phase runs on the list's candidates).
template <class O>
void check_candidate_list(std::uint64_t seed) {
    spatial_test::seeded_rng rng(seed);
    std::vector<O> objects = random_objects<O>(rng, 1200);
    std::vector<P3> velocity(objects.size());
    std::uniform_real_distribution<double> u(-1, 1);
    for (P3& v : velocity) v = P3{{0.0004 * u(rng), 0.0004 * u(rng), 0.0004 * u(rng)}};
    collision_grid<O> grid(objects.begin(), objects.end());
    std::vector<typename collision_grid<O>::iterator> handle;
    for (auto it = grid.begin(); it != grid.end(); ++it) handle.push_back(it);
    auto slots = [](const auto& pairs) { return slot_pairs(pairs); };
    // The oracle: brute force over the live objects, in slot order.
    auto expected = [&]() { return brute_force_slot_pairs(grid); };
    auto streamed = [&]() {
        std::vector<pair32> out;
        grid.for_each_self_pair(pair_filter::exact, [&](auto a, auto b) {
            out.emplace_back(static_cast<std::uint32_t>(a.slot()), static_cast<std::uint32_t>(b.slot()));
        });
        return out;
    };
    auto step = [&](double speed) {
        for (std::size_t k = 0; k < handle.size(); ++k) {
            const P3 d{{speed * velocity[k][0], speed * velocity[k][1], speed * velocity[k][2]}};
            handle[k] = grid.update(handle[k], moved(*handle[k], d));
        }
    };
    for (int s = 0; s < 12; ++s) {
        SCOPED_TRACE(::testing::Message() << "slow step " << s);
        step(1);
        const std::size_t reused = grid.candidate_list_stats().reused;
        const auto got = streamed();
        if (grid.candidate_list_stats().reused > reused) {
            EXPECT_TRUE(std::is_sorted(got.begin(), got.end())) << "a reused list's order";
        }
        auto sorted = got;
        std::sort(sorted.begin(), sorted.end());
        ASSERT_EQ(sorted, expected());
    }
    EXPECT_GE(grid.candidate_list_stats().built, 1u);
    EXPECT_GE(grid.candidate_list_stats().reused, 6u);
    EXPECT_GT(grid.candidate_list_stats().candidates, 0u);
    EXPECT_TRUE(grid.candidate_list_stats().own_margins) << "constant velocities: each box's margin from its own motion";
    // No update: the list answers again (nothing left its fat box).
    const std::size_t reused = grid.candidate_list_stats().reused;
    EXPECT_EQ(slots(grid.self_pairs()), expected());
    EXPECT_EQ(grid.candidate_list_stats().reused, reused + 1);
    // One object jumps onto another: out of its fat box, so a full query finds the new pair.
    handle[0] = grid.update(handle[0], *handle[1]);
    EXPECT_EQ(slots(grid.self_pairs()), expected());
    // Erase and insert renumber the boxes: no list survives them.
    grid.erase(handle.back());
    handle.pop_back();
    step(1);
    EXPECT_EQ(slots(grid.self_pairs()), expected());
    handle.push_back(grid.insert(*handle[2]));
    step(1);
    EXPECT_EQ(slots(grid.self_pairs()), expected());
    for (int s = 0; s < 6; ++s) {
        step(1);
        EXPECT_EQ(slots(grid.self_pairs()), expected()) << "after renumbering, step " << s;
    }
    // Motion that turns at every step (a random walk): some box soon outruns the margin its
    // own last move gave it, and the lists that follow give every box the largest move's.
    bool single_margin = false;
    for (int s = 0; s < 16; ++s) {
        for (P3& v : velocity) v = P3{{0.0004 * u(rng), 0.0004 * u(rng), 0.0004 * u(rng)}};
        step(1);
        EXPECT_EQ(slots(grid.self_pairs()), expected()) << "turning step " << s;
        single_margin |= grid.candidate_list_stats().built > 0 && !grid.candidate_list_stats().own_margins;
    }
    EXPECT_TRUE(single_margin) << "no list with a single margin after own margins failed";
    // Too fast for the objects' size (about their size per step): full queries, no new list.
    const std::size_t built = grid.candidate_list_stats().built;
    for (int s = 0; s < 4; ++s) {
        step(60);
        EXPECT_EQ(slots(grid.self_pairs()), expected()) << "fast step " << s;
    }
    EXPECT_EQ(grid.candidate_list_stats().built, built);
}

TEST(collide_collision_grid_motion, moving_objects_answered_from_a_candidate_list_equal_brute_force) {
    check_candidate_list<B3>(213);
    check_candidate_list<objects::sphere<double, 3>>(214);
}

// Boxes mirrored back from a wall (as the scene runner bounces them: moved in by twice the
// overshoot, the velocity flipped) have barely moved over the query where they bounced. Their
// margins come from the larger of their last two changes, so the lists keep own margins and
// serve several queries each; measured over the last query alone, a bounce at a list's build
// ended it at once and single margins followed. Every step against brute force.
TEST(collide_collision_grid_motion, boxes_mirrored_off_a_wall_keep_lists_with_own_margins) {
    constexpr double wall = 1.2, edge = 0.2;  // walls at x = 0 and x = wall
    std::vector<B3> boxes;
    std::vector<double> velocity;
    for (int k = 0; k < 64; ++k) {  // an 8 x 8 layer in y and z (neighbours overlap), spread in x
        const double x = 0.9 * ((k * 37) % 64) / 64.0, y = 0.15 * (k % 8), z = 0.15 * (k / 8);
        boxes.push_back(B3(P3{{x, y, z}}, P3{{x + edge, y + edge, z + edge}}));
        velocity.push_back((k % 2 ? 1 : -1) * (0.008 + 0.0005 * (k % 7)));
    }
    collision_grid<B3> grid(boxes.begin(), boxes.end());
    std::vector<collision_grid<B3>::iterator> handle;
    for (auto it = grid.begin(); it != grid.end(); ++it) handle.push_back(it);
    std::size_t bounces = 0;
    bool single_margin = false;
    for (int s = 0; s < 80; ++s) {
        for (std::size_t k = 0; k < boxes.size(); ++k) {
            B3& b = boxes[k];
            b.lo[0] += velocity[k], b.hi[0] += velocity[k];
            if (b.lo[0] < 0 || b.hi[0] > wall) {
                const double shift = b.lo[0] < 0 ? -2 * b.lo[0] : -2 * (b.hi[0] - wall);
                b.lo[0] += shift, b.hi[0] += shift;
                velocity[k] = -velocity[k];
                ++bounces;
            }
            handle[k] = grid.update(handle[k], b);
        }
        brute_force<B3> oracle(boxes.begin(), boxes.end());  // box k in slot k, as in the grid
        std::vector<pair32> want;
        for (const auto& [a, b] : oracle.self_pairs())
            want.emplace_back(static_cast<std::uint32_t>(std::min(a.slot(), b.slot())), static_cast<std::uint32_t>(std::max(a.slot(), b.slot())));
        std::sort(want.begin(), want.end());
        std::vector<pair32> got;
        for (const auto& [a, b] : grid.self_pairs()) got.emplace_back(static_cast<std::uint32_t>(a.slot()), static_cast<std::uint32_t>(b.slot()));
        ASSERT_EQ(got, want) << "step " << s;
        single_margin |= grid.candidate_list_stats().built > 1 && !grid.candidate_list_stats().own_margins;
    }
    EXPECT_GE(bounces, 40u);
    EXPECT_FALSE(single_margin) << "a bounce at a list's build ended it early";
    EXPECT_GE(grid.candidate_list_stats().reused, 3 * grid.candidate_list_stats().built);
}

// Near the top of double's range a fat box would overflow: the query takes the boxes as they
// are (no list), and the answer is still exact.
TEST(collide_collision_grid_motion, boxes_near_the_largest_double_take_no_candidate_list) {
    const double big = std::numeric_limits<double>::max();
    std::vector<B3> boxes;
    for (int k = 0; k < 6; ++k) boxes.push_back(B3(P3{{big * 0.5, big * 0.5, -1.0 + k}}, P3{{big, big, 0.5 + k}}));
    collision_grid<B3> grid(boxes.begin(), boxes.end());
    std::vector<collision_grid<B3>::iterator> handle;
    for (auto it = grid.begin(); it != grid.end(); ++it) handle.push_back(it);
    for (int s = 0; s < 4; ++s) {
        for (auto& h : handle) {
            B3 b = *h;
            b.lo[0] -= big * 1e-3;  // a margin of 3e-3 * big on x: past the largest double
            b.lo[2] += 0.01, b.hi[2] += 0.01;
            h = grid.update(h, b);
        }
        EXPECT_EQ(grid.self_pairs().size(), 5u) << "step " << s;  // neighbours in z overlap by 0.5
    }
    EXPECT_EQ(grid.candidate_list_stats().built, 0u);
}

// A bulk insert validates the whole batch before storing any of it, whether the range can be
// read twice (validated in place) or only once (copied first).
TEST(collide_collision_grid_motion, a_bulk_insert_with_a_nan_stores_nothing_from_either_kind_of_range) {
    std::mt19937_64 rng(spatial_test::test_seed(211));
    const std::vector<B3> boxes = random_objects<B3>(rng, 300);
    std::vector<B3> batch = random_objects<B3>(rng, 200);
    batch[150].lo[0] = std::nan("");
    collision_grid<B3> grid(boxes.begin(), boxes.end());
    const auto before = grid.self_pairs();
    EXPECT_THROW(grid.insert(batch.begin(), batch.end()), std::invalid_argument);  // forward range
    EXPECT_EQ(grid.size(), boxes.size());
    struct once {
        const std::vector<B3>* v;
        std::size_t i;
        using iterator_category = std::input_iterator_tag;
        using value_type = B3;
        using difference_type = std::ptrdiff_t;
        using pointer = const B3*;
        using reference = const B3&;
        const B3& operator*() const { return (*v)[i]; }
        once& operator++() { ++i; return *this; }
        void operator++(int) { ++i; }
        bool operator==(const once& o) const { return i == o.i; }
    };
    static_assert(!std::forward_iterator<once>);
    EXPECT_THROW(grid.insert(once{&batch, 0}, once{&batch, batch.size()}), std::invalid_argument);
    EXPECT_EQ(grid.size(), boxes.size());
    EXPECT_EQ(grid.self_pairs(), before);
    batch[150] = random_object<B3>(rng);
    grid.insert(once{&batch, 0}, once{&batch, batch.size()});
    grid.insert(batch.begin(), batch.end());
    EXPECT_EQ(grid.size(), boxes.size() + 2 * batch.size());
}

// 50 steps of `per_step` random pairs of ids in [low, high] (plus one duplicate each step;
// every third step sorted, and every third in canonical form, strictly increasing) against
// std::set differences.
template <class Id>
void check_tracker_against_sets(std::uint64_t seed, int per_step, Id low, Id high) {
    using pair_type = std::pair<Id, Id>;
    spatial_test::seeded_rng rng(seed);
    std::uniform_int_distribution<Id> id(low, high);
    collide::pair_set_tracker<Id> tracker;
    std::set<pair_type> previous;
    for (int step = 0; step < 50; ++step) {
        std::vector<pair_type> now;
        for (int k = 0; k < per_step; ++k) now.emplace_back(id(rng), id(rng));
        now.push_back(now.front());  // a duplicate is one pair
        if (step % 3 == 2) std::sort(now.begin(), now.end());  // sorted with its duplicate: the O(p) path
        const std::set<pair_type> cur(now.begin(), now.end());
        if (step % 3 == 1) now.assign(cur.begin(), cur.end());  // canonical form: merged where it is
        std::vector<pair_type> added, removed;
        std::set_difference(cur.begin(), cur.end(), previous.begin(), previous.end(), std::back_inserter(added));
        std::set_difference(previous.begin(), previous.end(), cur.begin(), cur.end(), std::back_inserter(removed));
        ASSERT_EQ(tracker.step(now), added.size() + removed.size());
        ASSERT_EQ(tracker.added(), added);
        ASSERT_EQ(tracker.removed(), removed);
        ASSERT_EQ(tracker.pairs(), std::vector<pair_type>(cur.begin(), cur.end()));
        previous = cur;
    }
}

TEST(collide_pair_set_tracker, added_and_removed_are_the_set_differences) {
    check_tracker_against_sets<std::uint32_t>(204, 40, 0, 30);
}

// Steps of at least 4096 pairs of unsigned ids below 2^32 are sorted by radix sort on one
// 64-bit key per pair (collide/pair_sort.hpp), the others by std::sort: both must give the
// same sets, with keys of one to six 12-bit digits and at the 32-bit edge.
TEST(collide_pair_set_tracker, large_steps_give_the_same_sets_by_either_sort) {
    check_tracker_against_sets<std::uint32_t>(205, 5000, 0, 2000);               // radix, 22-bit keys
    check_tracker_against_sets<std::uint64_t>(206, 5000, 0, 0xffffffffu);        // radix, 64-bit keys
    check_tracker_against_sets<std::uint32_t>(207, 5000, 0xfffff000u, 0xffffffffu);  // radix, high ids
    check_tracker_against_sets<std::uint64_t>(208, 5000, 0, 1ull << 40);         // past 2^32: std::sort
    check_tracker_against_sets<std::int64_t>(209, 5000, -1000, 1000);            // signed: std::sort
    check_tracker_against_sets<std::uint32_t>(210, 5000, 0, 3);                  // radix, many duplicates
    check_tracker_against_sets<std::uint32_t>(212, 5000, 0, 1);                  // radix, 2-bit keys
}

}  // namespace
