// knn_result_set (core/knn_result_set.hpp), the k-best set every kNN search fills: against a
// stable sort of everything offered, for k on both sides of the inline array's limit, with
// many equal distances; reset() empties it for the next query of a batch.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "spatial/core/knn_result_set.hpp"
#include "test_support.hpp"

namespace {

using spatial::knn_result_set;
using spatial::neighbor_candidate;
using spatial::slot_index;
using spatial_test::seeded_rng;

// The k smallest of `offered` by (distance, order offered): the first found wins a tie.
std::vector<std::pair<double, slot_index>> k_smallest(const std::vector<double>& offered, std::size_t k) {
    std::vector<std::pair<double, slot_index>> all;
    for (std::size_t i = 0; i < offered.size(); ++i) all.push_back({offered[i], static_cast<slot_index>(i)});
    std::stable_sort(all.begin(), all.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    all.resize(std::min(k, all.size()));
    return all;
}

std::vector<std::pair<double, slot_index>> as_pairs(std::span<const neighbor_candidate<double>> found) {
    std::vector<std::pair<double, slot_index>> out;
    for (const auto& c : found) out.push_back({c.distance_squared, c.slot});
    return out;
}

std::vector<double> distances_of(const std::vector<std::pair<double, slot_index>>& pairs) {
    std::vector<double> d;
    for (const auto& p : pairs) d.push_back(p.first);
    return d;
}

// Small k (the inline sorted array) keeps exactly the first-found k smallest; large k (the
// heap) the same distances (the heap does not order equal distances among themselves).
TEST(knn_result_set, keeps_the_k_smallest_on_both_sides_of_the_inline_limit) {
    seeded_rng rng(36);
    constexpr std::size_t limit = knn_result_set<double>::sorted_array_limit;
    for (const std::size_t k : {std::size_t{1}, std::size_t{2}, std::size_t{10}, limit, limit + 1, 2 * limit}) {
        for (int trial = 0; trial < 50; ++trial) {
            SCOPED_TRACE(testing::Message() << "k = " << k << ", trial " << trial);
            const std::size_t n = rng() % (3 * k + 5);
            std::vector<double> offered;
            for (std::size_t i = 0; i < n; ++i) offered.push_back(static_cast<double>(rng() % 12));  // many ties
            knn_result_set<double> best(k);
            for (std::size_t i = 0; i < n; ++i) {
                best.add(offered[i], static_cast<slot_index>(i));
                EXPECT_EQ(best.size(), std::min(k, i + 1));
            }
            const auto expected = k_smallest(offered, k);
            EXPECT_EQ(best.worst(), n >= k ? expected.back().first : std::numeric_limits<double>::infinity());
            const auto found = as_pairs(best.finish());
            if (k <= limit) EXPECT_EQ(found, expected);
            else EXPECT_EQ(distances_of(found), distances_of(expected));
        }
    }
}

// A candidate equal to the current worst is not accepted, on either side of the limit.
TEST(knn_result_set, a_candidate_equal_to_the_worst_is_refused) {
    constexpr std::size_t limit = knn_result_set<double>::sorted_array_limit;
    for (const std::size_t k : {std::size_t{3}, limit + 3}) {
        knn_result_set<double> best(k);
        for (std::size_t i = 0; i < k; ++i) best.add(static_cast<double>(i), static_cast<slot_index>(i));
        best.add(static_cast<double>(k - 1), 999);
        const auto found = as_pairs(best.finish());
        ASSERT_EQ(found.size(), k);
        for (const auto& [d, s] : found) EXPECT_NE(s, slot_index{999}) << "k = " << k;
    }
}

// reset() empties the set (worst back to +inf) and keeps k: a batch reuses one set.
TEST(knn_result_set, reset_empties_the_set_for_the_next_query) {
    constexpr std::size_t limit = knn_result_set<double>::sorted_array_limit;
    for (const std::size_t k : {std::size_t{4}, limit + 4}) {
        knn_result_set<double> best(k);
        for (std::size_t i = 0; i < 2 * k; ++i) best.add(static_cast<double>(i), static_cast<slot_index>(i));
        best.reset();
        EXPECT_EQ(best.size(), 0u);
        EXPECT_EQ(best.worst(), std::numeric_limits<double>::infinity());
        EXPECT_TRUE(best.finish().empty());
        best.add(7.0, 70);
        best.add(5.0, 50);
        EXPECT_EQ(as_pairs(best.finish()), (std::vector<std::pair<double, slot_index>>{{5.0, 50}, {7.0, 70}}));
    }
}

}  // namespace
