#include "harness/result_table.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <fstream>
#include <optional>
#include <sstream>
#include <string_view>
#include <system_error>
#include <utility>

#include "harness/check.hpp"

namespace harness {

namespace {

// The columns a table may have, by name. The first `required` must be there; the others came
// later (repetitions, min, max; check on 2026-11-26), so older tables lack them.
namespace col {
enum : std::size_t {
    suite,
    structure,
    bv,
    workload,
    n,
    dim,
    scalar,
    operation,
    params,
    metric,
    value,
    unit,
    validated,
    run_id,
    repetitions,
    min,
    max,
    check,
    count
};
constexpr std::size_t required = run_id + 1;
constexpr std::array<std::string_view, count> names = {
    "suite",  "structure", "bv",   "workload",  "n",      "dim",         "scalar", "operation", "params",
    "metric", "value",     "unit", "validated", "run_id", "repetitions", "min",    "max",       "check"};
}  // namespace col

// Where each known column stands in the records; empty where the table lacks it.
using column_positions = std::array<std::optional<std::size_t>, col::count>;

// One CSV record and the line it starts on (a quoted field may span lines).
struct record {
    std::size_t line = 0;
    std::vector<std::string> fields;
};

std::string read_whole_file(const std::filesystem::path& file) {
    std::error_code ec;
    if (!std::filesystem::exists(file, ec)) throw table_error(file, 0, "no such file");
    if (!std::filesystem::is_regular_file(file, ec)) throw table_error(file, 0, "not a regular file");
    std::ifstream in(file, std::ios::binary);
    if (!in) throw table_error(file, 0, "cannot open the file");
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

// RFC 4180 records of a whole file, one at a time: fields separated by commas, records by LF or
// CRLF; a field that starts with a quote runs to the closing quote, with "" standing for one
// quote and line breaks kept. A quote anywhere else is an error rather than a guess.
class record_splitter {
public:
    record_splitter(const std::string& text, const std::filesystem::path& file) : text_(text), file_(file) {}

    // The next record into `r`; false at the end of the text.
    bool next(record& r) {
        if (at_ >= text_.size()) return false;
        r = {line_, {}};
        for (;;) {
            const bool quoted = at_ < text_.size() && text_[at_] == '"';
            r.fields.push_back(quoted ? quoted_field(r.line) : plain_field());
            if (at_ == text_.size()) return true;
            if (text_[at_] == ',') {
                ++at_;
                continue;
            }
            at_ += text_[at_] == '\r' ? 2 : 1;  // the field stopped at LF or CRLF
            ++line_;
            return true;
        }
    }

private:
    bool at_record_end(std::size_t i) const {
        return i == text_.size() || text_[i] == '\n' ||
               (text_[i] == '\r' && i + 1 < text_.size() && text_[i + 1] == '\n');
    }

    std::string plain_field() {
        const std::size_t start = at_;
        while (!at_record_end(at_) && text_[at_] != ',') {
            if (text_[at_] == '"') throw table_error(file_, line_, "a quote inside an unquoted field");
            ++at_;
        }
        return text_.substr(start, at_ - start);
    }

    std::string quoted_field(std::size_t record_line) {
        std::string out;
        for (++at_;;) {
            const std::size_t quote = text_.find('"', at_);
            if (quote == std::string::npos) throw table_error(file_, record_line, "a quoted field is never closed");
            out.append(text_, at_, quote - at_);
            line_ += static_cast<std::size_t>(std::count(text_.begin() + static_cast<std::ptrdiff_t>(at_),
                                                         text_.begin() + static_cast<std::ptrdiff_t>(quote), '\n'));
            at_ = quote + 1;
            if (at_ < text_.size() && text_[at_] == '"') {  // "" stands for one quote
                out += '"';
                ++at_;
                continue;
            }
            if (!at_record_end(at_) && text_[at_] != ',') throw table_error(file_, line_, "text after a closing quote");
            return out;
        }
    }

    const std::string& text_;
    const std::filesystem::path& file_;
    std::size_t at_ = 0, line_ = 1;
};

column_positions map_header(const record& header, const std::filesystem::path& file) {
    column_positions at;
    for (std::size_t i = 0; i < header.fields.size(); ++i) {
        const std::string& name = header.fields[i];
        const auto known = std::find(col::names.begin(), col::names.end(), name);
        if (known == col::names.end()) throw table_error(file, header.line, "unknown column '" + name + "'");
        auto& slot = at[static_cast<std::size_t>(known - col::names.begin())];
        if (slot) throw table_error(file, header.line, "column '" + name + "' appears twice");
        slot = i;
    }
    for (std::size_t c = 0; c < col::required; ++c)
        if (!at[c]) throw table_error(file, header.line, "missing column '" + std::string(col::names[c]) + "'");
    return at;
}

// One record's fields by column, and the errors that name the record's line.
struct row_fields {
    const record& rec;
    const column_positions& at;
    const std::filesystem::path& file;

    bool has(std::size_t c) const { return at[c].has_value(); }
    const std::string& text(std::size_t c) const { return rec.fields[*at[c]]; }
    [[noreturn]] void fail(const std::string& what) const { throw table_error(file, rec.line, what); }

    template <class T>
    T parsed(std::size_t c, const char* kind) const {
        const std::string& s = text(c);
        T v{};
        const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
        if (s.empty() || ec != std::errc{} || end != s.data() + s.size())
            fail(std::string(col::names[c]) + " is not " + kind + ": '" + s + "'");
        return v;
    }
    std::size_t count(std::size_t c) const { return parsed<std::size_t>(c, "a non-negative integer"); }
    double number(std::size_t c) const { return parsed<double>(c, "a number"); }
};

// `validated` is derived from `check` (csv_writer.hpp): a table where they disagree was edited
// or written by something else, and which of the two to believe is not ours to guess.
void check_validated(const row_fields& f, const result_row& r) {
    const std::string& v = f.text(col::validated);
    if (v != "true" && v != "false") f.fail("validated is '" + v + "', neither true nor false");
    if (f.has(col::check) && (v == "true") != r.validated())
        f.fail("validated is " + v + " but check is '" + r.check + "'");
}

// The required columns taken as they stand.
constexpr std::array<std::pair<std::size_t, std::string result_row::*>, 10> text_columns = {{
    {col::suite, &result_row::suite},
    {col::structure, &result_row::structure},
    {col::bv, &result_row::bv},
    {col::workload, &result_row::workload},
    {col::scalar, &result_row::scalar},
    {col::operation, &result_row::operation},
    {col::params, &result_row::params},
    {col::metric, &result_row::metric},
    {col::unit, &result_row::unit},
    {col::run_id, &result_row::run_id},
}};

result_row parse_row(const row_fields& f) {
    result_row r;
    for (const auto& [c, member] : text_columns) r.*member = f.text(c);
    r.n = f.count(col::n);
    r.dim = f.count(col::dim);
    r.value = f.number(col::value);
    r.check = f.has(col::check) ? f.text(col::check) : check::none;
    r.repetitions = f.has(col::repetitions) ? f.count(col::repetitions) : 0;
    r.min_value = f.has(col::min) ? f.number(col::min) : r.value;
    r.max_value = f.has(col::max) ? f.number(col::max) : r.value;
    check_validated(f, r);
    return r;
}

}  // namespace

std::vector<result_row> read_results_csv(const std::filesystem::path& file) {
    const std::string text = read_whole_file(file);
    if (text.empty()) throw table_error(file, 1, "empty file: no header");
    record_splitter records(text, file);
    record header;
    records.next(header);
    const column_positions at = map_header(header, file);
    std::vector<result_row> rows;
    for (record rec; records.next(rec);) {
        if (rec.fields.size() == 1 && rec.fields[0].empty()) throw table_error(file, rec.line, "empty line");
        if (rec.fields.size() != header.fields.size())
            throw table_error(file, rec.line,
                              "expected " + std::to_string(header.fields.size()) + " fields (as the header), found " +
                                  std::to_string(rec.fields.size()));
        rows.push_back(parse_row({rec, at, file}));
    }
    return rows;
}

std::vector<std::string> result_table_names(const std::filesystem::path& dir) {
    if (!std::filesystem::is_directory(dir)) throw std::runtime_error(dir.string() + ": not a folder");
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(dir))
        if (entry.is_regular_file() && entry.path().extension() == ".csv")
            names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

}  // namespace harness
