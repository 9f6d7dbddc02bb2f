#pragma once
// harness::compare_results — run B against run A, figure by figure (`spatialbench compare A B`;
// docs/harness.md, "Comparing runs"). The machine is noisy (single figures swing by up to 2x
// between runs), so a ratio alone says little: a change counts only when B's spread and A's
// spread do not overlap, and the verdict says which way the figure moved, not whether that is
// better (higher recall is, higher time is not; the metric decides).
//
// Per key (result_key.hpp):
//   * the rows of each side are pooled: repeated runs of a case (several rows, distinguished by
//     run_id) give the median of their values, the least min, the greatest max and their count.
//     A row without repetitions (an untimed figure: a count, a size, a ratio) spans its value;
//   * rows whose check is "none" are never compared (no check covered them); each side's count
//     of them is reported instead, and a key whose rows on one side are all unvalidated counts
//     as absent there;
//   * verdict: `higher` when B's [min, max] lies entirely above A's, `lower` entirely below,
//     `within_spread` otherwise (and whenever the values are equal); `no_spread` when the
//     values differ and one side is a single `derived` row (a ratio of other figures, written
//     without a spread of its own: its components' verdicts say whether it moved);
//     `only_in_a` / `only_in_b` when the other side has no
//     validated row of the key;
//   * ratio = B's value / A's value (1 when they are equal, zeros included);
//   * every row of a key must have the same unit, or the comparison stops naming the key.

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "harness/csv_writer.hpp"
#include "harness/result_key.hpp"

namespace harness {

enum class verdict { within_spread, higher, lower, only_in_a, only_in_b, no_spread };
std::string_view to_string(verdict v);

// One side's figure for a key, pooled over its validated rows.
struct pooled_figure {
    double value = 0;  // median of the rows' values
    double min = 0;    // least min (least value for rows without repetitions)
    double max = 0;    // greatest max
    std::size_t rows = 0;
    bool derived = true;  // every row's check is "derived" (a ratio of other figures)
};

struct comparison_entry {
    result_key key;
    std::string unit;
    std::optional<pooled_figure> a, b;  // empty on the side that lacks the key
    double ratio = 0;                   // b->value / a->value; NaN unless both sides have the key
    verdict outcome = verdict::within_spread;
};

struct comparison {
    std::vector<comparison_entry> entries;             // one per key, in key order
    std::size_t unvalidated_a = 0, unvalidated_b = 0;  // rows left out: check "none"

    std::size_t count(verdict v) const;
};

comparison compare_results(const std::vector<result_row>& a, const std::vector<result_row>& b);

// Two result folders: their tables (*.csv at the top level) paired by file name.
struct table_comparison {
    std::string table;  // the file name, e.g. "knn.csv"
    comparison result;
};
struct folder_comparison {
    std::vector<table_comparison> tables;           // by file name
    std::vector<std::string> only_in_a, only_in_b;  // tables one side lacks (file names)
};

folder_comparison compare_result_folders(const std::filesystem::path& a, const std::filesystem::path& b);
// What `spatialbench compare A B` takes: two tables (one table_comparison, named by A's file
// name) or two folders. A folder against a table is an error.
folder_comparison compare_result_paths(const std::filesystem::path& a, const std::filesystem::path& b);

// The comparison as a tidy CSV, one row per key, written atomically. Columns:
//   table                        the table's file name
//   suite ... metric             the key, as in the tables
//   unit                         the figure's unit
//   verdict                      within_spread, higher, lower, only_in_a, only_in_b, no_spread
//   ratio                        B / A (empty unless both sides have the key)
//   a_value, a_min, a_max, a_rows   A's pooled figure (empty when A lacks the key)
//   b_value, b_min, b_max, b_rows   B's pooled figure
void write_comparison_csv(const std::filesystem::path& file, const folder_comparison& c);

// A few lines for the terminal: the count per verdict, the unvalidated rows left out, the tables
// one side lacks, and the `most` largest changes beyond spread (largest |log ratio| first).
std::string comparison_summary(const folder_comparison& c, std::size_t most = 12);

}  // namespace harness
