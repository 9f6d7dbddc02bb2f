#pragma once
// spatial::knn_batch — many k-nearest-neighbour queries answered at once: the result type,
// the query order, and the driver that the structures' find_nearest_batch members share.
//
// Order. query_order::as_given searches the queries in the caller's order; query_order::morton
// searches them in the Morton order of the query points (morton_order.hpp), so consecutive
// searches descend to neighbouring leaves whose nodes and points are still in cache. Either
// way query i's answer is stored at i and is the answer find_nearest(queries[i], k, eps) gives
// (the same search runs), so the caller never sees the order; the reordering's cost (an O(Q)
// radix sort) is part of the batch. How much it saves depends on how densely the queries
// cover the data: many queries per leaf share cached paths, a few scattered ones do not.
// Policy. spatial::par splits the ordered queries into chunks of consecutive queries answered
// concurrently (in Morton order, one thread's chunk is one region of space); the answers do
// not depend on the schedule. Without the parallel back end, par runs sequentially.
//
// Memory: Q * min(k, size) iterators and squared distances, plus 16 Q bytes while sorting.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "spatial/core/input_checks.hpp"
#include "spatial/core/knn_result_set.hpp"
#include "spatial/core/morton_order.hpp"
#include "spatial/core/parallel.hpp"
#include "spatial/core/point.hpp"

namespace spatial {

enum class query_order { as_given, morton };

// The answers of a batch: query q's neighbours, nearest first, are neighbors(q), their squared
// distances distances_squared(q). Every query has per_query() of them: min(k, size of the
// container) — a k-NN query returns that many.
template <class Iterator, class T>
class knn_batch {
public:
    knn_batch() = default;
    knn_batch(std::size_t queries, std::size_t per_query)
        : queries_(queries), per_query_(per_query), items_(queries * per_query), distances_(queries * per_query) {}

    std::size_t size() const { return queries_; }  // the number of queries
    std::size_t per_query() const { return per_query_; }
    std::span<const Iterator> neighbors(std::size_t q) const {
        return std::span<const Iterator>(items_).subspan(q * per_query_, per_query_);
    }
    std::span<const T> distances_squared(std::size_t q) const {
        return std::span<const T>(distances_).subspan(q * per_query_, per_query_);
    }

    // For the driver: query q's result, written once.
    template <class Make>
    void store(std::size_t q, std::span<const neighbor_candidate<T>> found, Make&& make) {
        for (std::size_t j = 0; j < found.size(); ++j) {
            items_[q * per_query_ + j] = make(found[j].slot);
            distances_[q * per_query_ + j] = found[j].distance_squared;
        }
    }

private:
    std::size_t queries_ = 0, per_query_ = 0;
    std::vector<Iterator> items_;
    std::vector<T> distances_;
};

namespace detail {

// Every query point must be finite; the message names the first bad one by its index.
template <class T, std::size_t D, class Where>
void require_finite_queries(std::span<const point<T, D>> queries, Where where) {
    for (std::size_t i = 0; i < queries.size(); ++i)
        for (std::size_t d = 0; d < D; ++d)
            if (!std::isfinite(queries[i][d])) [[unlikely]] {
                const std::string what = "query point " + std::to_string(i);
                require_finite(queries[i], where, what.c_str());
            }
}

// Answers every query with search(query, result_set) — a result set of capacity per_query,
// empty on entry — and stores the finished set with make(slot) -> Iterator. `Concurrent`:
// whether the search may run on several threads at once (the structure's queries write no
// shared state). Reordering costs an O(Q) radix sort.
template <bool Concurrent, class Iterator, class T, std::size_t D, class Search, class Make>
knn_batch<Iterator, T> answer_knn_batch(std::span<const point<T, D>> queries, std::size_t per_query, query_order order,
                                        Search&& search, Make&& make) {
    knn_batch<Iterator, T> out(queries.size(), per_query);
    if (per_query == 0 || queries.empty()) return out;
    std::vector<std::uint32_t> sequence;
    if (order == query_order::morton) sequence = morton_order(queries);
    auto answer_range = [&](std::size_t b, std::size_t e) {
        knn_result_set<T> best(per_query);
        for (std::size_t i = b; i < e; ++i) {
            const std::size_t q = sequence.empty() ? i : sequence[i];
            best.reset();
            search(queries[q], best);
            out.store(q, best.finish(), make);
        }
    };
    // 64 queries a chunk: a few microseconds of work each, so the scheduling costs little.
    if constexpr (Concurrent) parallel_chunks(queries.size(), 64, answer_range);
    else answer_range(0, queries.size());
    return out;
}

}  // namespace detail
}  // namespace spatial
