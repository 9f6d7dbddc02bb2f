// Result tables read back (result_table.hpp): a reader that misreads a column would mislead
// without a sign, so every malformed table must stop with FILE:LINE.

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
