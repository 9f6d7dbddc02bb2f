#pragma once
// harness::row_scope — the one place a result_row is filled in. A case fixes once what all of
// its rows share (suite, run id, workload, n, dim, scalar); each figure then names only what
// varies: structure, bounding volume, operation, params, metric, value and unit. A timed
// figure carries its repetitions and spread (min, max), scaled like the value.
//
// `check` says what verified the case's answers (check.hpp); it starts as "none", so a row is
// validated only where the code that ran a check said so: set it once the case's answers have
// passed, or use with_check() for figures another check covers.

#include <cstddef>
#include <string>

#include "harness/check.hpp"
#include "harness/csv_writer.hpp"
#include "harness/timing.hpp"

namespace harness {

struct row_scope {
    std::string suite, run_id, workload;
    std::size_t n = 0;
    std::size_t dim = 3;
    std::string scalar = "double";
    std::string check = check::none;

    // The same scope with another check (for the figures a different check covers).
    row_scope with_check(std::string c) const {
        row_scope s = *this;
        s.check = std::move(c);
        return s;
    }

    // An untimed figure: a count, a ratio, a size.
    result_row figure(const std::string& structure, const std::string& bv, const std::string& operation,
                      const std::string& params, const std::string& metric, double value, const std::string& unit) const {
        return {.suite = suite, .structure = structure, .bv = bv, .workload = workload, .n = n, .dim = dim,
                .scalar = scalar, .operation = operation, .params = params, .metric = metric, .value = value,
                .unit = unit, .check = check, .run_id = run_id};
    }

    // A timed figure: the median of `t` times `scale` (say 1e9 / queries for ns per query).
    result_row timed(const std::string& structure, const std::string& bv, const std::string& operation,
                     const std::string& params, const std::string& metric, const timing_result& t,
                     const std::string& unit, double scale = 1) const {
        result_row r = figure(structure, bv, operation, params, metric, t.median_seconds * scale, unit);
        r.repetitions = t.repetitions;
        r.min_value = t.min_seconds * scale;
        r.max_value = t.max_seconds * scale;
        return r;
    }
};

}  // namespace harness
