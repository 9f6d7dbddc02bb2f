// Batched kNN (core/knn_batch.hpp, kd_tree::find_nearest_batch) and the Morton order it
// reorders queries by (core/morton_order.hpp): every batch answer, in either order and on
// one or several threads, is exactly the single query's answer; the order is the Morton
// order; bad input is refused before any search.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <vector>

#include "spatial/core/capabilities.hpp"
#include "spatial/core/morton_order.hpp"
#include "spatial/kdtree/kd_tree.hpp"
#include "test_support.hpp"

namespace {

using spatial::query_order;
using spatial_test::seeded_rng;

// The bit-by-bit interleaving the magic-number spreads must equal.
template <std::size_t D>
std::uint64_t interleaved_by_loop(const std::array<std::uint64_t, D>& q) {
    constexpr unsigned bits = spatial::morton_encoder<double, D>::bits_per_axis;
    std::uint64_t out = 0;
    for (std::size_t i = 0; i < D; ++i)
        for (unsigned b = 0; b < bits; ++b) out |= ((q[i] >> b) & 1u) << (b * D + i);
    return out;
}

// An encoder over [0, 2^bits - 1] per axis maps integer coordinates to themselves.
template <std::size_t D>
void expect_codes_interleave_bits(std::mt19937_64& rng) {
    constexpr unsigned bits = spatial::morton_encoder<double, D>::bits_per_axis;
    const double top = std::ldexp(1.0, static_cast<int>(bits)) - 1;
    std::array<double, D> lo{}, hi;
    hi.fill(top);
    const spatial::morton_encoder<double, D> enc(lo, hi);
    for (int i = 0; i < 2000; ++i) {
        std::array<std::uint64_t, D> q;
        std::array<double, D> c;
        for (std::size_t d = 0; d < D; ++d) {
            q[d] = rng() & ((std::uint64_t{1} << bits) - 1);
            if (i == 0) q[d] = (std::uint64_t{1} << bits) - 1;  // every bit set
            c[d] = static_cast<double>(q[d]);
        }
        ASSERT_EQ(enc.code(c), interleaved_by_loop<D>(q)) << "D=" << D << " draw " << i;
    }
}

TEST(morton_order, codes_interleave_the_quantised_coordinates_bit_by_bit) {
    seeded_rng rng(4101);
    expect_codes_interleave_bits<1>(rng);
    expect_codes_interleave_bits<2>(rng);
    expect_codes_interleave_bits<3>(rng);
    expect_codes_interleave_bits<4>(rng);
}

TEST(morton_order, sorts_by_code_and_keeps_ties_in_input_order) {
    seeded_rng rng(4102);
    using P = spatial::point<double, 3>;
    std::uniform_real_distribution<double> u(-5, 5);
    std::vector<P> pts(3000);
    for (auto& p : pts) p = P{{u(rng), u(rng), u(rng)}};
    for (std::size_t i = 0; i < 200; ++i) pts.push_back(pts[i * 7]);  // exact duplicates: equal codes
    const auto order = spatial::morton_order(std::span<const P>(pts));
    ASSERT_EQ(order.size(), pts.size());
    std::vector<std::uint32_t> seen(order);
    std::sort(seen.begin(), seen.end());
    for (std::uint32_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i], i) << "not a permutation";
    const auto enc = spatial::morton_encoder<double, 3>::bounding(pts);
    for (std::size_t i = 1; i < order.size(); ++i) {
        const auto a = enc.code(pts[order[i - 1]]), b = enc.code(pts[order[i]]);
        ASSERT_LE(a, b) << "position " << i;
        if (a == b) {
            ASSERT_LT(order[i - 1], order[i]) << "ties keep the input order, position " << i;
        }
    }
}

TEST(morton_order, degenerate_boxes_huge_extents_and_empty_input) {
    using P = spatial::point<double, 2>;
    EXPECT_TRUE(spatial::morton_order(std::span<const P>()).empty());
    // All equal: one code, input order.
    const std::vector<P> same(5, P{{1, 2}});
    EXPECT_EQ(spatial::morton_order(std::span<const P>(same)), (std::vector<std::uint32_t>{0, 1, 2, 3, 4}));
    // A flat set (zero extent on y) is ordered by x alone.
    const std::vector<P> flat{P{{3, 0}}, P{{1, 0}}, P{{2, 0}}, P{{0, 0}}};
    EXPECT_EQ(spatial::morton_order(std::span<const P>(flat)), (std::vector<std::uint32_t>{3, 1, 2, 0}));
    // An extent that overflows to infinity (-1e308 .. 1e308) orders by the other axis and
    // never produces NaN codes or a crash.
    const std::vector<P> wide{P{{1e308, 3}}, P{{-1e308, 1}}, P{{0, 2}}};
    EXPECT_EQ(spatial::morton_order(std::span<const P>(wide)), (std::vector<std::uint32_t>{1, 2, 0}));
    // An extent of one denormal on x makes that axis's scale +inf (found by the operations
    // fuzzer: 0 * inf = NaN converted to an integer, caught by -fsanitize=float-cast-overflow):
    // the point at the low end goes to cell 0, the other to the last cell.
    constexpr double denormal = std::numeric_limits<double>::denorm_min();
    const std::vector<P> thin{P{{denormal, 1}}, P{{0, 1}}, P{{denormal, 0}}};
    EXPECT_EQ(spatial::morton_order(std::span<const P>(thin)), (std::vector<std::uint32_t>{2, 1, 0}));
}

template <class Tree, class P>
void expect_batch_equals_single_queries(const Tree& t, const std::vector<P>& queries, std::size_t k,
                                        typename P::scalar_type eps) {
    for (query_order order : {query_order::as_given, query_order::morton}) {
        for (bool parallel : {false, true}) {
            SCOPED_TRACE(std::string("order=") + (order == query_order::morton ? "morton" : "as_given") +
                         (parallel ? " par" : " seq") + " k=" + std::to_string(k));
            const auto batch = parallel ? t.find_nearest_batch(queries, k, eps, order, spatial::par)
                                        : t.find_nearest_batch(queries, k, eps, order);
            ASSERT_EQ(batch.size(), queries.size());
            ASSERT_EQ(batch.per_query(), std::min(k, t.size()));
            for (std::size_t q = 0; q < queries.size(); ++q) {
                const auto single = t.find_nearest(queries[q], k, eps);
                const auto got = batch.neighbors(q);
                const auto d2 = batch.distances_squared(q);
                ASSERT_EQ(got.size(), single.size()) << "query " << q;
                for (std::size_t j = 0; j < single.size(); ++j) {
                    ASSERT_EQ(got[j], single[j]) << "query " << q << " neighbour " << j;
                    ASSERT_EQ(d2[j], spatial::squared_distance(*single[j], queries[q])) << "query " << q;
                }
            }
        }
    }
}

TEST(kd_tree_batch, every_answer_is_the_single_querys_in_both_orders_and_on_every_core) {
    seeded_rng rng(4103);
    using P = spatial::point<double, 3>;
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<P> pts(5000), queries(700);
    for (auto& p : pts) p = P{{u(rng), u(rng), u(rng)}};
    for (std::size_t i = 0; i < 500; ++i) pts.push_back(pts[i]);  // duplicates: distance ties
    for (auto& q : queries) q = P{{u(rng), u(rng), u(rng)}};
    for (std::size_t i = 0; i < 100; ++i) queries[i] = pts[i * 3];  // queries on data points
    spatial::kd_tree<P> t(pts.begin(), pts.end());
    for (std::size_t i = 0; i < 300; ++i) t.insert(P{{u(rng), u(rng), u(rng)}});  // incremental part too
    for (std::size_t k : {1, 10, 40})  // 40: the result set's heap form
        expect_batch_equals_single_queries(t, queries, k, 0.0);
    expect_batch_equals_single_queries(t, queries, 10, 0.5);  // approximate: the same search
}

TEST(kd_tree_batch, float_2d_and_objects_with_extent) {
    seeded_rng rng(4104);
    using P = spatial::point<float, 2>;
    std::uniform_real_distribution<float> u(-1, 1);
    std::vector<P> pts(2000), queries(300);
    for (auto& p : pts) p = P{{u(rng), u(rng)}};
    for (auto& q : queries) q = P{{u(rng), u(rng)}};
    const spatial::kd_tree<P> t(pts.begin(), pts.end());
    expect_batch_equals_single_queries(t, queries, 5, 0.0f);
    using B = spatial::objects::box<double, 3>;
    std::vector<B> boxes;
    std::uniform_real_distribution<double> c(0, 10), w(0, 0.5);
    for (int i = 0; i < 1500; ++i) {
        const double x = c(rng), y = c(rng), z = c(rng);
        boxes.emplace_back(spatial::point<double, 3>{{x, y, z}}, spatial::point<double, 3>{{x + w(rng), y + w(rng), z + w(rng)}});
    }
    const spatial::kd_tree<B> bt(boxes.begin(), boxes.end());
    std::vector<spatial::point<double, 3>> bq(200);
    for (auto& q : bq) q = spatial::point<double, 3>{{c(rng), c(rng), c(rng)}};
    for (query_order order : {query_order::as_given, query_order::morton}) {
        const auto batch = bt.find_nearest_batch(bq, 4, 0.0, order, spatial::par);
        for (std::size_t q = 0; q < bq.size(); ++q) {
            const auto single = bt.find_nearest(bq[q], 4);
            ASSERT_TRUE(std::equal(single.begin(), single.end(), batch.neighbors(q).begin(), batch.neighbors(q).end()))
                << "query " << q;
        }
    }
}

TEST(kd_tree_batch, empty_trees_k_zero_k_beyond_size_and_no_queries) {
    using P = spatial::point<double, 3>;
    const std::vector<P> queries{P{{0, 0, 0}}, P{{1.5, 0, 0}}};
    const spatial::kd_tree<P> empty;
    const auto none = empty.find_nearest_batch(queries, 3);
    EXPECT_EQ(none.size(), 2u);
    EXPECT_EQ(none.per_query(), 0u);
    EXPECT_TRUE(none.neighbors(1).empty());
    const std::vector<P> pts{P{{0, 0, 0}}, P{{2, 0, 0}}, P{{5, 0, 0}}};
    const spatial::kd_tree<P> t(pts.begin(), pts.end());
    EXPECT_EQ(t.find_nearest_batch(queries, 0).per_query(), 0u);
    const auto all = t.find_nearest_batch(queries, 10, 0.0, query_order::morton);
    ASSERT_EQ(all.per_query(), 3u);
    EXPECT_EQ(*all.neighbors(1)[0], (P{{2, 0, 0}}));
    EXPECT_EQ(*all.neighbors(1)[1], (P{{0, 0, 0}}));
    EXPECT_EQ(*all.neighbors(1)[2], (P{{5, 0, 0}}));
    EXPECT_EQ(all.distances_squared(1)[0], 0.25);
    EXPECT_EQ(t.find_nearest_batch(std::span<const P>(), 2).size(), 0u);
}

TEST(kd_tree_batch, a_non_finite_query_or_bad_eps_is_refused_naming_it_before_any_search) {
    using P = spatial::point<double, 3>;
    const std::vector<P> pts{P{{0, 0, 0}}, P{{1, 0, 0}}};
    const spatial::kd_tree<P> t(pts.begin(), pts.end());
    std::vector<P> queries(5, P{{0, 0, 0}});
    queries[3][1] = std::numeric_limits<double>::quiet_NaN();
    try {
        (void)t.find_nearest_batch(queries, 1, 0.0, query_order::morton);
        FAIL() << "a NaN query was accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("kd_tree::find_nearest_batch: query point 3 has a non-finite coordinate 1"),
                  std::string::npos)
            << e.what();
    }
    queries[3][1] = 0;
    EXPECT_THROW((void)t.find_nearest_batch(queries, 1, -1.0), std::invalid_argument);
    EXPECT_EQ(t.size(), 2u);
}

static_assert(spatial::batched_knn<spatial::kd_tree<spatial::point<double, 3>>>);

}  // namespace
