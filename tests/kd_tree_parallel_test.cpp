// spatial::kd_tree's bulk build on every core (insert(first, last, par), kd_tree(first, last,
// par)): into an empty tree it must build the SAME tree as the sequential bulk build, node
// for node and slot for slot — equal heights, leaf counts and memory, the points in the same
// slots (leaf order), and every query visiting the same nodes and answering with the same
// slots — on uniform, clustered, duplicate-heavy, lattice and collinear points, 2D and 3D,
// float and double, several leaf capacities, and on boxes (objects with extent). Below the
// parallel threshold and into a non-empty tree it is the sequential insertion; bad input is
// refused before anything changes. With TBB (the default build) the plan is made on several
// threads; without it `par` is sequential and the tests still check the answers.

#include <gtest/gtest.h>

#include <list>
#include <random>
#include <stdexcept>
#include <vector>

#include "spatial/kdtree/kd_tree.hpp"
#include "spatial/objects/box.hpp"
#include "test_support.hpp"

using namespace spatial;
using spatial_test::seeded_rng;

namespace {

template <class T, std::size_t D>
using stats_tree = kd_tree<point<T, D>, kd_tree_config<32, median_of_widest_spread, true>>;

enum class shape { uniform, clusters, duplicates, lattice, line };

template <class T, std::size_t D>
std::vector<point<T, D>> make_points(shape s, std::size_t n, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(0, 1);
    std::normal_distribution<double> g(0, 0.01);
    std::vector<point<T, D>> out(n);
    std::vector<point<T, D>> centres(20);
    for (auto& c : centres)
        for (std::size_t k = 0; k < D; ++k) c[k] = static_cast<T>(u(rng));
    const std::size_t side = static_cast<std::size_t>(std::ceil(std::pow(static_cast<double>(n), 1.0 / D)));
    for (std::size_t i = 0; i < n; ++i) {
        auto& p = out[i];
        switch (s) {
            case shape::uniform:
                for (std::size_t k = 0; k < D; ++k) p[k] = static_cast<T>(u(rng));
                break;
            case shape::clusters: {
                const auto& c = centres[i % centres.size()];
                for (std::size_t k = 0; k < D; ++k) p[k] = static_cast<T>(c[k] + g(rng));
                break;
            }
            case shape::duplicates:  // about ten copies of each point
                if (i % 10 != 0) {
                    p = out[i - 1 - static_cast<std::size_t>(u(rng) * static_cast<double>(i % 10))];
                    break;
                }
                for (std::size_t k = 0; k < D; ++k) p[k] = static_cast<T>(u(rng));
                break;
            case shape::lattice: {
                std::size_t r = i;
                for (std::size_t k = 0; k < D; ++k, r /= side) p[k] = static_cast<T>(r % side);
                break;
            }
            case shape::line: {
                const double t = u(rng);
                for (std::size_t k = 0; k < D; ++k) p[k] = static_cast<T>(t * static_cast<double>(k + 1));
                break;
            }
        }
    }
    if (s == shape::lattice) std::shuffle(out.begin(), out.end(), rng);
    return out;
}

// The same tree as far as every observer can tell: shape figures, the value in each slot,
// and for kNN and ball queries the nodes visited and the slots answered.
template <class Tree>
void expect_same_tree(const Tree& a, const Tree& b, std::mt19937_64& rng) {
    ASSERT_EQ(a.check_invariants(), "");
    ASSERT_EQ(b.check_invariants(), "");
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(a.height(), b.height());
    EXPECT_EQ(a.leaf_count(), b.leaf_count());
    EXPECT_EQ(a.memory_bytes(), b.memory_bytes());
    for (auto i = a.begin(), j = b.begin(); i != a.end(); ++i, ++j) {
        ASSERT_EQ(i.slot(), j.slot());
        ASSERT_TRUE(*i == *j) << "slot " << i.slot();
    }
    using P = typename Tree::point_type;
    using T = typename Tree::scalar_type;
    std::uniform_real_distribution<double> u(-0.1, 1.1);
    for (int q = 0; q < 200; ++q) {
        P x;
        for (std::size_t k = 0; k < Tree::dimension; ++k) x[k] = static_cast<T>(u(rng));
        const auto na = a.find_nearest(x, 10);
        const auto sa = a.last_query_stats();
        const auto nb = b.find_nearest(x, 10);
        const auto sb = b.last_query_stats();
        ASSERT_EQ(na.size(), nb.size());
        for (std::size_t i = 0; i < na.size(); ++i) EXPECT_EQ(na[i].slot(), nb[i].slot()) << "query " << q;
        EXPECT_EQ(sa.nodes_visited, sb.nodes_visited) << "query " << q;
        auto ba = a.find_in_ball(x, T(0.05)), bb = b.find_in_ball(x, T(0.05));
        ASSERT_EQ(ba.size(), bb.size());
        for (std::size_t i = 0; i < ba.size(); ++i) EXPECT_EQ(ba[i].slot(), bb[i].slot()) << "query " << q;
    }
}

template <class T, std::size_t D, class Tree = stats_tree<T, D>>
void expect_parallel_build_is_sequential(shape s, std::size_t n, std::mt19937_64& rng) {
    SCOPED_TRACE(::testing::Message() << "shape " << static_cast<int>(s) << ", n " << n << ", D " << D);
    const auto pts = make_points<T, D>(s, n, rng);
    Tree sequential(pts.begin(), pts.end());
    Tree parallel(pts.begin(), pts.end(), par);
    expect_same_tree(sequential, parallel, rng);
    // insert(first, last, par) into a cleared tree: the same again (the timed rebuild).
    parallel.clear();
    parallel.insert(pts.begin(), pts.end(), par);
    expect_same_tree(sequential, parallel, rng);
}

TEST(kd_tree_parallel, build_of_points_is_the_sequential_tree_on_every_shape) {
    seeded_rng rng(61);
    for (shape s : {shape::uniform, shape::clusters, shape::duplicates, shape::lattice, shape::line})
        expect_parallel_build_is_sequential<double, 3>(s, 60000, rng);
}

TEST(kd_tree_parallel, build_is_the_sequential_tree_in_2d_float_and_other_leaf_capacities) {
    seeded_rng rng(62);
    expect_parallel_build_is_sequential<float, 3>(shape::uniform, 50000, rng);
    expect_parallel_build_is_sequential<double, 2>(shape::clusters, 50000, rng);
    expect_parallel_build_is_sequential<double, 3, kd_tree<point<double, 3>, kd_tree_config<8, median_of_widest_spread, true>>>(
        shape::uniform, 40000, rng);
    expect_parallel_build_is_sequential<double, 3, kd_tree<point<double, 3>, kd_tree_config<64, median_of_widest_spread, true>>>(
        shape::duplicates, 40000, rng);
    // Just above and below the parallel threshold (2 x 8192 points).
    expect_parallel_build_is_sequential<double, 3>(shape::uniform, 16384, rng);
    expect_parallel_build_is_sequential<double, 3>(shape::uniform, 16383, rng);
}

TEST(kd_tree_parallel, build_of_boxes_is_the_sequential_tree) {
    seeded_rng rng(63);
    using B = objects::box<double, 3>;
    std::uniform_real_distribution<double> u(0, 1), h(0.0001, 0.01);
    std::vector<B> boxes;
    for (int i = 0; i < 40000; ++i) {
        const double x = u(rng), y = u(rng), z = u(rng), e = h(rng);
        boxes.push_back(B{{x, y, z}, {x + e, y + 2 * e, z + e}});
    }
    kd_tree<B> sequential(boxes.begin(), boxes.end()), parallel(boxes.begin(), boxes.end(), par);
    ASSERT_EQ(parallel.check_invariants(), "");
    EXPECT_EQ(sequential.height(), parallel.height());
    EXPECT_EQ(sequential.memory_bytes(), parallel.memory_bytes());
    for (auto i = sequential.begin(), j = parallel.begin(); i != sequential.end(); ++i, ++j) ASSERT_TRUE(*i == *j);
    for (int q = 0; q < 200; ++q) {
        const double x = u(rng), y = u(rng), z = u(rng);
        const point<double, 3> lo{{x, y, z}}, hi{{x + 0.05, y + 0.05, z + 0.05}};
        const auto a = sequential.find_in_box(lo, hi), b = parallel.find_in_box(lo, hi);
        ASSERT_EQ(a.size(), b.size());
        for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].slot(), b[i].slot());
    }
}

TEST(kd_tree_parallel, into_a_non_empty_tree_and_from_single_pass_input_it_is_the_sequential_insertion) {
    seeded_rng rng(64);
    const auto first = make_points<double, 3>(shape::uniform, 30000, rng);
    const auto more = make_points<double, 3>(shape::clusters, 20000, rng);
    stats_tree<double, 3> sequential(first.begin(), first.end()), parallel(first.begin(), first.end(), par);
    sequential.insert(more.begin(), more.end());
    parallel.insert(more.begin(), more.end(), par);
    expect_same_tree(sequential, parallel, rng);
    // A list is copied once, then built on every core.
    const std::list<point<double, 3>> listed(first.begin(), first.end());
    stats_tree<double, 3> from_list(listed.begin(), listed.end(), par), from_vector(first.begin(), first.end());
    expect_same_tree(from_vector, from_list, rng);
}

TEST(kd_tree_parallel, bad_input_is_refused_before_anything_changes) {
    seeded_rng rng(65);
    auto pts = make_points<double, 3>(shape::uniform, 40000, rng);
    pts[31234][1] = std::numeric_limits<double>::quiet_NaN();
    kd_tree<point<double, 3>> empty;
    EXPECT_THROW(empty.insert(pts.begin(), pts.end(), par), std::invalid_argument);
    EXPECT_EQ(empty.size(), 0u);
    EXPECT_EQ(empty.check_invariants(), "");
    const auto good = make_points<double, 3>(shape::uniform, 100, rng);
    kd_tree<point<double, 3>> some(good.begin(), good.end());
    EXPECT_THROW(some.insert(pts.begin(), pts.end(), par), std::invalid_argument);
    EXPECT_EQ(some.size(), good.size());
    EXPECT_EQ(some.check_invariants(), "");
}

}  // namespace
