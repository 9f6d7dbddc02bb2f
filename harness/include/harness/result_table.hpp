#pragma once
// harness::read_results_csv — a result table (csv_writer.hpp, results/README.md) read back into
// rows, for the tools that work on finished runs (compare, merge). The reader trusts nothing:
// a table may come from another commit, another machine or an editor, and a comparison built
// on a misread column would be wrong without a sign. So every malformed input stops with a
// table_error naming FILE:LINE and what is wrong there.
//
// Columns are found by name in the header, in any order. Required: suite, structure, bv,
// workload, n, dim, scalar, operation, params, metric, value, unit, validated, run_id.
// Optional: repetitions (absent: 0), min and max (absent: the value), and check (absent in
// tables written before 2026-11-26: "none"). Where check is present, validated must agree
// with it (validated is derived from check, csv_writer.hpp); an unknown or repeated column is
// an error. Fields are RFC 4180, as the writer quotes them: a quoted field may hold commas,
// doubled quotes and line breaks; CRLF line ends are accepted.

#include <cstddef>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "harness/csv_writer.hpp"
#include "harness/result_key.hpp"  // what the readers of tables pair rows by

namespace harness {

// A malformed table. what() is "FILE:LINE: <what is wrong>"; LINE is the line the offending
// record starts on (1 = the header), 0 when the file itself cannot be read.
class table_error : public std::runtime_error {
public:
    table_error(const std::filesystem::path& file, std::size_t line, const std::string& what)
        : std::runtime_error(file.string() + ':' + std::to_string(line) + ": " + what), file_(file), line_(line) {}
    const std::filesystem::path& file() const { return file_; }
    std::size_t line() const { return line_; }

private:
    std::filesystem::path file_;
    std::size_t line_;
};

// The rows of `file`, in file order. Throws table_error.
std::vector<result_row> read_results_csv(const std::filesystem::path& file);

// The tables of a result folder, the ones compare and merge pair by name: the file names of
// the *.csv files at its top level (not runs/, not the sidecars), sorted. Throws
// std::runtime_error when `dir` is not a folder.
std::vector<std::string> result_table_names(const std::filesystem::path& dir);

}  // namespace harness
