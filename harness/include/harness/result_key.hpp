#pragma once
// harness::result_key — what a result row measures, without the measurement: the columns that
// name a figure (suite, structure, bv, workload, n, dim, scalar, operation, params, metric).
// Two rows with the same key are the same figure taken twice (two runs, two machines), which
// is what comparing runs pairs up and what merging shards must never see twice.
//
// The members are declared in the order a reader scans a table, so the defaulted ordering
// sorts rows that way (n and dim numerically).

#include <compare>
#include <cstddef>
#include <functional>
#include <initializer_list>
#include <string>

#include "harness/csv_writer.hpp"

namespace harness {

struct result_key {
    std::string suite, structure, bv, workload;
    std::size_t n = 0;
    std::size_t dim = 0;
    std::string scalar, operation, params, metric;

    auto operator<=>(const result_key&) const = default;
    bool operator==(const result_key&) const = default;
};

inline result_key key_of(const result_row& r) {
    return {r.suite, r.structure, r.bv, r.workload, r.n, r.dim, r.scalar, r.operation, r.params, r.metric};
}

// The key as the table writes those columns (comma-separated, quoted where needed): what error
// messages and the comparison summary show, so that it can be searched for in the table.
inline std::string to_string(const result_key& k) {
    return csv_field(k.suite) + ',' + csv_field(k.structure) + ',' + csv_field(k.bv) + ',' + csv_field(k.workload) +
           ',' + std::to_string(k.n) + ',' + std::to_string(k.dim) + ',' + csv_field(k.scalar) + ',' +
           csv_field(k.operation) + ',' + csv_field(k.params) + ',' + csv_field(k.metric);
}

}  // namespace harness

// For unordered containers keyed by figure. (Within one process only: std::hash differs
// between standard libraries, so it must never name anything written to disk.)
template <>
struct std::hash<harness::result_key> {
    std::size_t operator()(const harness::result_key& k) const noexcept {
        std::size_t h = 0;
        auto mix = [&h](std::size_t x) { h ^= x + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2); };
        const std::hash<std::string> s;
        for (const std::string* f : {&k.suite, &k.structure, &k.bv, &k.workload}) mix(s(*f));
        mix(k.n);
        mix(k.dim);
        for (const std::string* f : {&k.scalar, &k.operation, &k.params, &k.metric}) mix(s(*f));
        return h;
    }
};
