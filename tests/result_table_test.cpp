// Result tables read back, compared and merged (result_table.hpp, result_compare.hpp,
// result_merge.hpp): a reader that misreads a column, or a comparison that calls noise a
// change, would mislead without a sign, so every malformed table must stop with FILE:LINE and
// every verdict is pinned down here.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>
#include <unordered_set>
#include <vector>

#include "harness/csv_writer.hpp"
#include "harness/result_compare.hpp"
#include "harness/result_merge.hpp"
#include "harness/result_table.hpp"

using namespace harness;
namespace fs = std::filesystem;

namespace {

// A validated timed figure; tests change what they need.
result_row row(const std::string& structure, std::size_t n, double value, double min, double max) {
    return {.suite = "knn",
            .structure = structure,
            .bv = "",
            .workload = "uniform",
            .n = n,
            .dim = 3,
            .scalar = "double",
            .operation = "knn",
            .params = "k=10",
            .metric = "time_per_op",
            .value = value,
            .unit = "ns",
            .check = "oracle:all+identity:all",
            .run_id = "run-a",
            .repetitions = 5,
            .min_value = min,
            .max_value = max};
}

// A fresh folder per test, removed afterwards.
class tables : public ::testing::Test {
protected:
    void SetUp() override {
        std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
        std::replace(name.begin(), name.end(), '/', '_');  // parameterised tests: "test/param"
        dir = fs::temp_directory_path() / ("result_table_test_" + name + "_" + std::to_string(::getpid()));
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    void TearDown() override { fs::remove_all(dir); }

    fs::path file(const std::string& name, const std::string& text) const {
        const fs::path p = dir / name;
        std::ofstream(p, std::ios::binary) << text;
        return p;
    }

    fs::path dir;
};

const std::string header = csv_header() + "\n";
const std::string good_line = csv_line(row("kd_tree", 1000, 2.5, 2, 3)) + "\n";

// good_line with its first `from` replaced by `to`: one malformed field.
std::string edited(const std::string& from, const std::string& to) {
    std::string line = good_line;
    return line.replace(line.find(from), from.size(), to);
}

// Reading `p` must fail with "P:LINE: ..." and mention `what`.
void expect_table_error(const fs::path& p, std::size_t line, const std::string& what) {
    try {
        read_results_csv(p);
        ADD_FAILURE() << "no error for " << p;
    } catch (const table_error& e) {
        const std::string msg = e.what();
        EXPECT_EQ(msg.rfind(p.string() + ":" + std::to_string(line) + ": ", 0), 0u) << msg;
        EXPECT_NE(msg.find(what), std::string::npos) << msg;
        EXPECT_EQ(e.line(), line);
        EXPECT_EQ(e.file(), p);
    }
}

}  // namespace

// ---- reading ----

TEST_F(tables, rows_written_by_csv_writer_read_back_equal) {
    std::vector<result_row> rows = {row("kd_tree", 1000, 2.5, 2, 3), row("cgal_kd_tree", 1000000, 1.25e-7, 1e-7, 2e-7)};
    rows[1].params = "k=10,eps=\"0.5\"\nsecond line";  // every character the writer must quote
    rows[1].run_id = "run,b";
    rows[1].check = "oracle:sample=200+cross:all";
    result_row figure = row("kd_tree", 1000, 40, 0, 0);
    figure.metric = "bytes_per_point";
    figure.repetitions = 0;
    figure.check = "none";  // unvalidated rows round-trip too
    rows.push_back(figure);
    rows.push_back(row("kd_tree", 10, std::numeric_limits<double>::infinity(), 1, 2));
    write_csv_atomically(dir / "t.csv", rows);
    EXPECT_EQ(read_results_csv(dir / "t.csv"), rows);
}

TEST_F(tables, columns_are_found_by_name_in_any_order) {
    const auto p = file("t.csv",
                        "check,run_id,validated,unit,value,metric,params,operation,scalar,dim,n,workload,bv,structure,"
                        "suite,max,min,repetitions\n"
                        "size,r1,true,s,0.5,build_time,,build,double,3,100,uniform,,kd_tree,knn,0.75,0.25,3\n");
    const auto rows = read_results_csv(p);
    ASSERT_EQ(rows.size(), 1u);
    result_row expected = row("kd_tree", 100, 0.5, 0.25, 0.75);
    expected.operation = "build";
    expected.params = "";
    expected.metric = "build_time";
    expected.unit = "s";
    expected.check = "size";
    expected.run_id = "r1";
    expected.repetitions = 3;
    EXPECT_EQ(rows[0], expected);
}

TEST_F(tables, tables_written_before_the_check_column_read_as_unchecked) {
    const auto p = file("t.csv",
                        "suite,structure,bv,workload,n,dim,scalar,operation,params,metric,value,unit,validated,run_id\n"
                        "knn,kd_tree,,uniform,1000,3,double,knn,k=1,time_per_op,1.5,ns,true,r1\n");
    const auto rows = read_results_csv(p);
    ASSERT_EQ(rows.size(), 1u);
    EXPECT_EQ(rows[0].check, "none");
    EXPECT_FALSE(rows[0].validated());
    // Without repetitions, min and max, the figure spans its value.
    EXPECT_EQ(rows[0].repetitions, 0u);
    EXPECT_EQ(rows[0].min_value, 1.5);
    EXPECT_EQ(rows[0].max_value, 1.5);
}

TEST_F(tables, crlf_line_ends_are_accepted) {
    std::string text = header + good_line;
    for (std::size_t at = 0; (at = text.find('\n', at)) != std::string::npos; at += 2) text.insert(at, "\r");
    const auto rows = read_results_csv(file("t.csv", text));
    ASSERT_EQ(rows.size(), 1u);
    EXPECT_EQ(rows[0], row("kd_tree", 1000, 2.5, 2, 3));
}

TEST_F(tables, a_header_alone_is_an_empty_table) {
    EXPECT_TRUE(read_results_csv(file("t.csv", header)).empty());
}

// ---- malformed tables: FILE:LINE and what is wrong ----

TEST_F(tables, rejects_a_missing_file) {
    expect_table_error(dir / "absent.csv", 0, "no such file");
}

TEST_F(tables, rejects_a_folder) {
    expect_table_error(dir, 0, "not a regular file");
}

TEST_F(tables, rejects_an_empty_file) {
    expect_table_error(file("t.csv", ""), 1, "empty file");
}

TEST_F(tables, rejects_an_unknown_column) {
    expect_table_error(file("t.csv", csv_header() + ",colour\n"), 1, "unknown column 'colour'");
}

TEST_F(tables, rejects_a_missing_required_column) {
    std::string h = csv_header();
    h.replace(h.find("unit,"), 5, "");
    expect_table_error(file("t.csv", h + "\n"), 1, "missing column 'unit'");
}

TEST_F(tables, rejects_a_repeated_column) {
    expect_table_error(file("t.csv", csv_header() + ",suite\n"), 1, "column 'suite' appears twice");
}

TEST_F(tables, rejects_a_row_with_too_few_fields) {
    const std::string cut = good_line.substr(0, good_line.rfind(',')) + "\n";
    expect_table_error(file("t.csv", header + good_line + cut), 3, "expected 18 fields (as the header), found 17");
}

TEST_F(tables, rejects_a_row_with_too_many_fields) {
    const std::string longer = good_line.substr(0, good_line.size() - 1) + ",extra\n";
    expect_table_error(file("t.csv", header + longer), 2, "expected 18 fields (as the header), found 19");
}

TEST_F(tables, rejects_an_empty_line) {
    expect_table_error(file("t.csv", header + good_line + "\n" + good_line), 3, "empty line");
}

// One field of a good row made malformed: each a test of its own, named after the input.
struct malformed_field {
    const char* name;
    const char* from;  // edited(from, to)
    const char* to;
    const char* what;  // in the message
};
// Test listings show the input's name rather than the struct's bytes.
void PrintTo(const malformed_field& f, std::ostream* os) {
    *os << f.name;
}

const malformed_field malformed_fields[] = {
    {"non_numeric_n", ",1000,", ",1e3,", "n is not a non-negative integer: '1e3'"},
    {"negative_dim", ",3,double", ",-3,double", "dim is not a non-negative integer: '-3'"},
    {"non_numeric_value", ",2.5,", ",fast,", "value is not a number: 'fast'"},
    {"empty_value", ",2.5,", ",,", "value is not a number: ''"},
    {"non_numeric_repetitions", ",5,2,3,", ",five,2,3,", "repetitions is not a non-negative integer: 'five'"},
    {"non_numeric_min", ",5,2,3,", ",5,2x,3,", "min is not a number: '2x'"},
    {"non_numeric_max", ",5,2,3,", ",5,2,3 ,", "max is not a number: '3 '"},
    {"validated_true_when_nothing_checked_the_row", "oracle:all+identity:all", "none",
     "validated is true but check is 'none'"},
    {"validated_false_when_a_check_is_named", ",true,", ",false,",
     "validated is false but check is 'oracle:all+identity:all'"},
    {"validated_neither_true_nor_false", ",true,", ",yes,", "validated is 'yes', neither true nor false"},
    {"quote_inside_an_unquoted_field", "k=10", "k=\"10\"", "a quote inside an unquoted field"},
    {"text_after_a_closing_quote", "k=10", "\"k=10\"x", "text after a closing quote"},
};

class rejects : public tables, public ::testing::WithParamInterface<malformed_field> {};

TEST_P(rejects, a_malformed_field_naming_file_and_line) {
    expect_table_error(file("t.csv", header + edited(GetParam().from, GetParam().to)), 2, GetParam().what);
}

INSTANTIATE_TEST_SUITE_P(table, rejects, ::testing::ValuesIn(malformed_fields),
                         [](const auto& p) { return std::string(p.param.name); });

TEST_F(tables, rejects_a_quoted_field_that_is_never_closed) {
    expect_table_error(file("t.csv", header + good_line + edited("k=10", "\"k=10")), 3,
                       "a quoted field is never closed");
}

TEST_F(tables, errors_name_the_line_a_record_starts_on_after_a_field_spanning_lines) {
    result_row two_lines = row("kd_tree", 1000, 2.5, 2, 3);
    two_lines.params = "k=10\nstill params";
    const std::string bad = edited(",2.5,", ",x,");
    expect_table_error(file("t.csv", header + csv_line(two_lines) + "\n" + bad), 4, "value is not a number");
}

// Every table committed under results/ reads without error.
TEST(committed_tables, every_results_table_reads) {
    std::size_t files = 0;
    for (const auto& entry : fs::directory_iterator(SPATIAL_RESULTS_DIR)) {
        if (entry.path().extension() != ".csv") continue;
        ++files;
        SCOPED_TRACE(entry.path().string());
        std::vector<result_row> rows;
        ASSERT_NO_THROW(rows = read_results_csv(entry.path()));
        EXPECT_FALSE(rows.empty());
    }
    EXPECT_GT(files, 0u);
}

// ---- keys ----

TEST(result_key, orders_by_the_columns_in_table_order_and_n_numerically) {
    const result_key small = key_of(row("kd_tree", 1000, 1, 1, 1));
    const result_key large = key_of(row("kd_tree", 100000, 1, 1, 1));
    EXPECT_LT(small, large);                                // "100000" < "1000" as text, not as a number
    EXPECT_LT(key_of(row("bvh", 100000, 1, 1, 1)), small);  // structure before n
    result_row other_metric = row("kd_tree", 1000, 1, 1, 1);
    other_metric.metric = "build_time";
    EXPECT_LT(key_of(other_metric), small);
    EXPECT_EQ(small, key_of(row("kd_tree", 1000, 5, 4, 6)));  // the measurement is not part of it
}

TEST(result_key, hashes_equal_keys_alike_for_unordered_containers) {
    std::unordered_set<result_key> keys;
    keys.insert(key_of(row("kd_tree", 1000, 1, 1, 1)));
    keys.insert(key_of(row("kd_tree", 1000, 2, 2, 2)));
    keys.insert(key_of(row("kd_tree", 10000, 1, 1, 1)));
    EXPECT_EQ(keys.size(), 2u);
    EXPECT_EQ(std::hash<result_key>{}(key_of(row("bvh", 10, 1, 1, 1))),
              std::hash<result_key>{}(key_of(row("bvh", 10, 3, 3, 3))));
}

TEST(result_key, prints_as_the_table_writes_the_key_columns) {
    result_row r = row("kd_tree", 1000, 1, 1, 1);
    r.params = "a,b";
    EXPECT_EQ(to_string(key_of(r)), "knn,kd_tree,,uniform,1000,3,double,knn,\"a,b\",time_per_op");
}

// ---- comparing runs ----

namespace {

const comparison_entry& only_entry(const comparison& c) {
    EXPECT_EQ(c.entries.size(), 1u);
    return c.entries.at(0);
}

verdict verdict_between(const result_row& a, const result_row& b) {
    return only_entry(compare_results({a}, {b})).outcome;
}

}  // namespace

TEST(compare_results, a_table_against_itself_is_within_spread_everywhere) {
    const std::vector<result_row> rows = {row("kd_tree", 1000, 2.5, 2, 3), row("bvh", 1000, 4, 4, 4),
                                          row("kd_tree", 10000, 3, 2.5, 3.5)};
    const comparison c = compare_results(rows, rows);
    EXPECT_EQ(c.entries.size(), 3u);
    EXPECT_EQ(c.count(verdict::within_spread), 3u);
    for (const auto& e : c.entries) EXPECT_EQ(e.ratio, 1.0);
}

// The committed tables predate the check column, so they read as unchecked; marked checked,
// every one compared with itself is within spread at every key.
TEST(compare_results, every_committed_table_against_itself_is_within_spread) {
    for (const auto& entry : fs::directory_iterator(SPATIAL_RESULTS_DIR)) {
        if (entry.path().extension() != ".csv") continue;
        SCOPED_TRACE(entry.path().string());
        std::vector<result_row> rows = read_results_csv(entry.path());
        const comparison as_read = compare_results(rows, rows);
        std::size_t unchecked = 0;
        for (auto& r : rows)
            if (!r.validated()) {
                ++unchecked;
                r.check = "oracle:all";
            }
        EXPECT_EQ(as_read.unvalidated_a, unchecked);
        const comparison c = compare_results(rows, rows);
        EXPECT_FALSE(c.entries.empty());
        EXPECT_EQ(c.count(verdict::within_spread), c.entries.size());
    }
}

TEST(compare_results, overlapping_spreads_are_within_spread_whatever_the_ratio) {
    const comparison c = compare_results({row("kd_tree", 1000, 1.5, 1, 2)}, {row("kd_tree", 1000, 2.5, 1.9, 3)});
    const auto& e = only_entry(c);
    EXPECT_EQ(e.outcome, verdict::within_spread);
    EXPECT_DOUBLE_EQ(e.ratio, 2.5 / 1.5);
    ASSERT_TRUE(e.a && e.b);
    EXPECT_EQ(e.a->min, 1);
    EXPECT_EQ(e.b->max, 3);
    EXPECT_EQ(e.unit, "ns");
}

TEST(compare_results, higher_when_b_lies_entirely_above_a) {
    EXPECT_EQ(verdict_between(row("kd_tree", 1000, 1.5, 1, 2), row("kd_tree", 1000, 2.5, 2.1, 3)), verdict::higher);
}

TEST(compare_results, lower_when_b_lies_entirely_below_a) {
    EXPECT_EQ(verdict_between(row("kd_tree", 1000, 1.5, 1, 2), row("kd_tree", 1000, 0.7, 0.5, 0.9)), verdict::lower);
}

// A figure taken once (no repetitions: a count, a size, a recall) has no spread: any change
// of it is beyond spread, whatever its min and max columns say (the writer puts 0 there).
TEST(compare_results, figures_without_repetitions_span_their_value) {
    result_row a = row("kd_tree", 1000, 0.98, 0, 0), b = a;
    a.repetitions = b.repetitions = 0;
    a.metric = b.metric = "recall";
    EXPECT_EQ(verdict_between(a, b), verdict::within_spread);
    b.value = 0.97;
    EXPECT_EQ(verdict_between(a, b), verdict::lower);
    const auto& e = only_entry(compare_results({a}, {b}));
    EXPECT_EQ(e.a->min, 0.98);
    EXPECT_EQ(e.a->max, 0.98);
}

TEST(compare_results, keys_on_one_side_only_are_reported_as_such) {
    const comparison c = compare_results({row("kd_tree", 1000, 1, 1, 1), row("bvh", 1000, 1, 1, 1)},
                                         {row("kd_tree", 1000, 1, 1, 1), row("octree", 1000, 1, 1, 1)});
    ASSERT_EQ(c.entries.size(), 3u);  // in key order: bvh, kd_tree, octree
    EXPECT_EQ(c.entries[0].key.structure, "bvh");
    EXPECT_EQ(c.entries[0].outcome, verdict::only_in_a);
    EXPECT_FALSE(c.entries[0].b.has_value());
    EXPECT_TRUE(std::isnan(c.entries[0].ratio));
    EXPECT_EQ(c.entries[1].outcome, verdict::within_spread);
    EXPECT_EQ(c.entries[2].key.structure, "octree");
    EXPECT_EQ(c.entries[2].outcome, verdict::only_in_b);
    EXPECT_FALSE(c.entries[2].a.has_value());
}

TEST(compare_results, repeated_runs_of_a_key_are_pooled) {
    std::vector<result_row> a = {row("kd_tree", 1000, 3, 2.5, 3.5), row("kd_tree", 1000, 1, 0.8, 1.2),
                                 row("kd_tree", 1000, 2, 1.5, 2.5)};
    a[1].run_id = "run-b";
    a[2].run_id = "run-c";
    std::vector<result_row> b = {row("kd_tree", 1000, 4, 3.9, 4.1), row("kd_tree", 1000, 5, 4.8, 6)};
    const auto& e = only_entry(compare_results(a, b));
    EXPECT_EQ(e.a->value, 2);  // the median
    EXPECT_EQ(e.a->min, 0.8);
    EXPECT_EQ(e.a->max, 3.5);
    EXPECT_EQ(e.a->rows, 3u);
    EXPECT_EQ(e.b->value, 4.5);  // an even count: the mean of the middle two
    EXPECT_EQ(e.b->min, 3.9);
    EXPECT_EQ(e.b->max, 6);
    EXPECT_EQ(e.b->rows, 2u);
    EXPECT_EQ(e.outcome, verdict::higher);  // 3.9 > 3.5
    EXPECT_DOUBLE_EQ(e.ratio, 4.5 / 2);
}

TEST(compare_results, unvalidated_rows_are_counted_and_never_compared) {
    result_row unchecked_a = row("kd_tree", 1000, 100, 100, 100), unchecked_b = row("bvh", 1000, 1, 1, 1);
    unchecked_a.check = unchecked_b.check = "none";
    const comparison c = compare_results({row("kd_tree", 1000, 1, 1, 1), unchecked_a},
                                         {row("kd_tree", 1000, 1, 1, 1), unchecked_b, unchecked_b});
    EXPECT_EQ(c.unvalidated_a, 1u);
    EXPECT_EQ(c.unvalidated_b, 2u);
    const auto& e = only_entry(c);  // no entry for bvh, and A's unchecked 100 is not pooled
    EXPECT_EQ(e.outcome, verdict::within_spread);
    EXPECT_EQ(e.a->rows, 1u);
}

// A ratio of other figures (check "derived") is written once, without a spread of its own: a
// change of it is reported as no_spread, never flagged; equal values stay within_spread.
TEST(compare_results, a_single_derived_row_that_changed_has_no_spread) {
    auto ratio_row = [](double value) {
        result_row r = row("nanoflann", 1000, value, 0, 0);
        r.metric = "time_ratio", r.unit = "ratio", r.check = "derived", r.repetitions = 0;
        return r;
    };
    EXPECT_EQ(only_entry(compare_results({ratio_row(0.8)}, {ratio_row(0.9)})).outcome, verdict::no_spread);
    EXPECT_EQ(only_entry(compare_results({ratio_row(0.8)}, {ratio_row(0.8)})).outcome, verdict::within_spread);
    // Pooled over repeated runs, derived rows do have a spread and are judged by it.
    EXPECT_EQ(only_entry(compare_results({ratio_row(0.8), ratio_row(0.82)}, {ratio_row(0.9), ratio_row(0.95)})).outcome,
              verdict::higher);
}

TEST(compare_results, equal_values_have_ratio_one_even_at_zero) {
    EXPECT_EQ(only_entry(compare_results({row("kd_tree", 1000, 0, 0, 0)}, {row("kd_tree", 1000, 0, 0, 0)})).ratio, 1.0);
    EXPECT_TRUE(std::isinf(
        only_entry(compare_results({row("kd_tree", 1000, 0, 0, 0)}, {row("kd_tree", 1000, 1, 1, 1)})).ratio));
}

TEST(compare_results, a_unit_mismatch_is_an_error_naming_the_key) {
    result_row seconds = row("kd_tree", 1000, 1, 1, 1);
    seconds.unit = "s";
    for (const auto& [a, b] :
         {std::pair{std::vector{row("kd_tree", 1000, 1, 1, 1)}, std::vector{seconds}},
          std::pair{std::vector{row("kd_tree", 1000, 1, 1, 1), seconds}, std::vector<result_row>{}}}) {
        try {
            compare_results(a, b);
            ADD_FAILURE() << "no error";
        } catch (const std::runtime_error& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find("unit differs for key knn,kd_tree,,uniform,1000,3,double,knn,k=10,time_per_op"),
                      std::string::npos)
                << msg;
            EXPECT_NE(msg.find("'ns' in A"), std::string::npos) << msg;
            EXPECT_NE(msg.find("'s' in"), std::string::npos) << msg;
        }
    }
}

TEST_F(tables, folders_are_compared_table_by_table_by_file_name) {
    fs::create_directories(dir / "a" / "nested");
    fs::create_directories(dir / "b");
    write_csv_atomically(dir / "a" / "knn.csv", {row("kd_tree", 1000, 1, 1, 1)});
    write_csv_atomically(dir / "b" / "knn.csv", {row("kd_tree", 1000, 2, 2, 2)});
    write_csv_atomically(dir / "a" / "bv.csv", {row("kd_tree", 1000, 1, 1, 1)});
    write_csv_atomically(dir / "b" / "raycast.csv", {row("bvh", 1000, 1, 1, 1)});
    write_csv_atomically(dir / "a" / "nested" / "deep.csv", {row("bvh", 1000, 1, 1, 1)});  // not at the top level
    write_text_atomically(dir / "b" / "registry.json", "{}");                              // not a table

    const folder_comparison c = compare_result_paths(dir / "a", dir / "b");
    ASSERT_EQ(c.tables.size(), 1u);
    EXPECT_EQ(c.tables[0].table, "knn.csv");
    EXPECT_EQ(only_entry(c.tables[0].result).outcome, verdict::higher);
    EXPECT_EQ(c.only_in_a, std::vector<std::string>{"bv.csv"});
    EXPECT_EQ(c.only_in_b, std::vector<std::string>{"raycast.csv"});
}

TEST_F(tables, two_tables_are_one_comparison_named_by_a) {
    write_csv_atomically(dir / "before.csv", {row("kd_tree", 1000, 1, 1, 1)});
    write_csv_atomically(dir / "after.csv", {row("kd_tree", 1000, 1, 1, 1)});
    const folder_comparison c = compare_result_paths(dir / "before.csv", dir / "after.csv");
    ASSERT_EQ(c.tables.size(), 1u);
    EXPECT_EQ(c.tables[0].table, "before.csv");
    EXPECT_EQ(c.tables[0].result.count(verdict::within_spread), 1u);
    EXPECT_THROW(compare_result_paths(dir, dir / "after.csv"), std::runtime_error);
    EXPECT_THROW(compare_result_paths(dir / "before.csv", dir / "absent.csv"), table_error);
}

TEST_F(tables, the_comparison_csv_has_one_row_per_key_and_empty_fields_for_a_missing_side) {
    folder_comparison c;
    c.tables.push_back({"knn.csv", compare_results({row("kd_tree", 1000, 1.5, 1, 2), row("bvh", 10, 1, 1, 1)},
                                                   {row("kd_tree", 1000, 3, 2.5, 3.5)})});
    write_comparison_csv(dir / "out" / "compare.csv", c);
    std::ifstream in(dir / "out" / "compare.csv");
    std::stringstream text;
    text << in.rdbuf();
    EXPECT_EQ(text.str(),
              "table,suite,structure,bv,workload,n,dim,scalar,operation,params,metric,unit,verdict,ratio,"
              "a_value,a_min,a_max,a_rows,b_value,b_min,b_max,b_rows\n"
              "knn.csv,knn,bvh,,uniform,10,3,double,knn,k=10,time_per_op,ns,only_in_a,,1,1,1,1,,,,\n"
              "knn.csv,knn,kd_tree,,uniform,1000,3,double,knn,k=10,time_per_op,ns,higher,2,1.5,1,2,1,3,2.5,3.5,1\n");
    EXPECT_EQ(std::distance(fs::directory_iterator(dir / "out"), fs::directory_iterator{}), 1);  // no temporary left
}

TEST(comparison_summary, counts_verdicts_and_lists_the_largest_changes_first) {
    folder_comparison c;
    std::vector<result_row> a, b;
    for (std::size_t i = 1; i <= 30; ++i) {  // 30 keys, B slower by 1.1x ... 4x
        a.push_back(row("kd_tree", i, 1, 0.99, 1.01));
        b.push_back(row("kd_tree", i, 1 + 0.1 * static_cast<double>(i), 1.05, 5));
    }
    result_row unchecked = row("bvh", 1, 1, 1, 1);
    unchecked.check = "none";
    b.push_back(unchecked);
    c.tables.push_back({"knn.csv", compare_results(a, b)});
    c.only_in_b = {"raycast.csv"};
    const std::string s = comparison_summary(c);
    EXPECT_NE(s.find("1 table(s), 30 keys: within_spread 0, higher 30, lower 0, only_in_a 0, only_in_b 0, no_spread 0"),
              std::string::npos)
        << s;
    EXPECT_NE(s.find("0 rows of A, 1 rows of B"), std::string::npos) << s;
    EXPECT_NE(s.find("tables only in B: raycast.csv"), std::string::npos) << s;
    EXPECT_LT(s.find("higher x4 "), s.find("higher x3.9 ")) << s;  // n=30 first, then n=29
    EXPECT_NE(s.find("... and 18 more"), std::string::npos) << s;
    EXPECT_LE(std::count(s.begin(), s.end(), '\n'), 20);
}

TEST(comparison_summary, says_so_when_nothing_changed_beyond_spread) {
    folder_comparison c;
    c.tables.push_back({"knn.csv", compare_results({row("kd_tree", 1000, 1, 1, 1)}, {row("kd_tree", 1000, 1, 1, 1)})});
    EXPECT_NE(comparison_summary(c).find("no change beyond the runs' spread"), std::string::npos);
}

// ---- merging shards ----

TEST(merge_results, is_the_union_of_the_shards_sorted_by_key) {
    result_row build = row("kd_tree", 1000, 1, 1, 1);
    build.operation = "build";
    build.run_id = "shard-1";
    result_row big = row("kd_tree", 100000, 1, 1, 1);
    big.run_id = "shard-2";
    const std::vector<std::vector<result_row>> shards = {{row("kd_tree", 1000, 1, 1, 1), build},
                                                         {big, row("bvh", 10, 1, 1, 1)}};
    const auto merged = merge_results(shards);
    ASSERT_EQ(merged.size(), 4u);
    EXPECT_EQ(merged[0], shards[1][1]);  // bvh
    EXPECT_EQ(merged[1], build);         // kd_tree, n=1000: build before knn
    EXPECT_EQ(merged[2], shards[0][0]);
    EXPECT_EQ(merged[3], big);                                 // n=100000 after n=1000, its run_id kept
    EXPECT_EQ(merge_results({shards[1], shards[0]}), merged);  // the shards' order does not matter
}

TEST(merge_results, keeps_repeated_rows_of_a_key_within_one_shard_in_their_order) {
    result_row first = row("kd_tree", 1000, 1, 1, 1), second = first;
    second.run_id = "run-b";
    const auto merged = merge_results({{first, second}, {}});
    EXPECT_EQ(merged, (std::vector<result_row>{first, second}));
}

TEST(merge_results, a_key_in_two_shards_is_an_error_naming_it) {
    result_row again = row("kd_tree", 1000, 2, 2, 2);
    again.run_id = "run-b";
    try {
        merge_results({{row("bvh", 10, 1, 1, 1)}, {row("kd_tree", 1000, 1, 1, 1)}, {again}});
        FAIL() << "no error";
    } catch (const std::runtime_error& e) {
        EXPECT_STREQ(e.what(),
                     "key knn,kd_tree,,uniform,1000,3,double,knn,k=10,time_per_op is in shard 2 (run run-a) and in "
                     "shard 3 (run run-b): shards must hold disjoint cases");
    }
}

// Repeated runs of the same cases (issue 20): every run's rows of a key, in the inputs' order,
// sorted by key; the same run given twice is the error.
TEST(merge_results, repeated_runs_keep_every_runs_rows_of_a_key) {
    result_row first = row("kd_tree", 1000, 1, 1, 1), second = row("kd_tree", 1000, 2, 2, 2);
    second.run_id = "run-b";
    result_row other = row("bvh", 1000, 3, 3, 3);
    other.run_id = "run-b";
    const auto merged = merge_results({{first}, {second, other}}, {"a.csv", "b.csv"}, merge_kind::repeated_runs);
    EXPECT_EQ(merged, (std::vector<result_row>{other, first, second}));
    try {
        merge_results({{first}, {first}}, {"a.csv", "b.csv"}, merge_kind::repeated_runs);
        FAIL() << "no error";
    } catch (const std::runtime_error& e) {
        EXPECT_STREQ(e.what(),
                     "key knn,kd_tree,,uniform,1000,3,double,knn,k=10,time_per_op is in a.csv (run run-a) and in "
                     "b.csv (run run-a): one run given twice");
    }
    EXPECT_THROW(merge_results({{first}, {second}}, {"a.csv", "b.csv"}), std::runtime_error) << "shards by default";
}

TEST_F(tables, shard_folders_are_merged_table_by_table) {
    fs::create_directories(dir / "s1");
    fs::create_directories(dir / "s2");
    write_csv_atomically(dir / "s1" / "knn.csv", {row("kd_tree", 1000, 1, 1, 1)});
    write_csv_atomically(dir / "s2" / "knn.csv", {row("bvh", 1000, 1, 1, 1)});
    write_csv_atomically(dir / "s2" / "bv.csv", {row("bvh", 10, 1, 1, 1)});
    const auto merged = merge_result_folders({dir / "s1", dir / "s2"});
    ASSERT_EQ(merged.size(), 2u);
    EXPECT_EQ(merged.at("bv.csv"), std::vector<result_row>{row("bvh", 10, 1, 1, 1)});
    EXPECT_EQ(merged.at("knn.csv"),
              (std::vector<result_row>{row("bvh", 1000, 1, 1, 1), row("kd_tree", 1000, 1, 1, 1)}));

    write_csv_atomically(dir / "s2" / "knn.csv", {row("kd_tree", 1000, 2, 2, 2)});  // the same case twice
    try {
        merge_result_folders({dir / "s1", dir / "s2"});
        ADD_FAILURE() << "no error";
    } catch (const std::runtime_error& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("is in " + (dir / "s1" / "knn.csv").string() + " (run run-a) and in " +
                           (dir / "s2" / "knn.csv").string()),
                  std::string::npos)
            << msg;
    }
    EXPECT_THROW(merge_result_folders({dir / "s1", dir / "absent"}), std::runtime_error);
}
