#pragma once
// Tidy CSV results: one figure per row, the columns documented in results/README.md.
// Files are written atomically (temporary file in the same directory, then rename), so a
// reader never sees a half-written table and an aborted run leaves the old table intact.

#include <filesystem>
#include <string>
#include <vector>

namespace harness {

struct result_row {
    std::string suite, structure, bv, workload;
    std::size_t n = 0;
    std::size_t dim = 0;
    std::string scalar, operation, params, metric;
    double value = 0;
    std::string unit;
    bool validated = false;
    std::string run_id;
    // Extra columns (after the required ones).
    std::size_t repetitions = 0;
    double min_value = 0, max_value = 0;  // spread over repetitions, same unit as value
};

std::string csv_header();
std::string csv_line(const result_row& r);
// Writes header + rows to `file` atomically.
void write_csv_atomically(const std::filesystem::path& file, const std::vector<result_row>& rows);
// Writes text to `file` atomically.
void write_text_atomically(const std::filesystem::path& file, const std::string& text);

}  // namespace harness
