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
    // What verified the answers behind this figure, written by the code that ran the check
    // (docs/harness.md, "The check column"): e.g. "oracle:all+identity:all",
    // "oracle:sample=200+cross:all", "containment:all"; "none" when no check covers it.
    std::string check = "none";
    std::string run_id;
    // Extra columns (after the required ones).
    std::size_t repetitions = 0;
    double min_value = 0, max_value = 0;  // spread over repetitions, same unit as value

    // The `validated` column: derived from `check`, never set on its own.
    bool validated() const { return !check.empty() && check != "none"; }

    bool operator==(const result_row&) const = default;
};

std::string csv_header();
std::string csv_line(const result_row& r);
// One field as the tables write it: quoted (RFC 4180) when it holds a comma, quote or newline.
std::string csv_field(const std::string& s);
// One number as the tables write it: 9 significant digits.
std::string csv_number(double v);
// Writes header + rows to `file` atomically.
void write_csv_atomically(const std::filesystem::path& file, const std::vector<result_row>& rows);
// Writes text to `file` atomically.
void write_text_atomically(const std::filesystem::path& file, const std::string& text);

}  // namespace harness
