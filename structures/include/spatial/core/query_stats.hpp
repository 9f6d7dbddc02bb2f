#pragma once
// spatial::query_stats — the ONE statistics type every structure reports, the same way:
// `last_query_stats()` returns the counts of the most recent query (a kNN, ball, box or ray
// query, a find/count, an insertion's descent, or a pair search), reset when the next query
// starts. Structures that keep more (bvh: whether the wide ray layout answered) derive from
// it, so code that reads statistics needs to know only this struct (see the
// `reports_query_stats` capability in core/capabilities.hpp).
//
// The counters are plain members updated on the query path: where counting costs time a
// structure compiles it out with a configuration flag (kd_tree_config<..., CollectStats>),
// as madmann91/bvh does, and then does not model `reports_query_stats`. Not thread-safe:
// concurrent const queries race on these counters only (their answers are unaffected).

#include <cstddef>

namespace spatial {

struct query_stats {
    std::size_t nodes_visited = 0;   // tree nodes or grid cells entered
    std::size_t objects_tested = 0;  // exact object tests (distances, ray tests, pair tests)
};

}  // namespace spatial
