#include "harness/result_compare.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include "harness/result_table.hpp"

namespace harness {

namespace {

constexpr std::array<verdict, 6> all_verdicts = {verdict::within_spread, verdict::higher, verdict::lower,
                                                 verdict::only_in_a, verdict::only_in_b, verdict::no_spread};
constexpr std::array<const char*, 2> side_names = {"A", "B"};

// The validated rows of one key: [0] from A, [1] from B.
using key_rows = std::array<std::vector<const result_row*>, 2>;

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t mid = v.size() / 2;
    return v.size() % 2 == 1 ? v[mid] : (v[mid - 1] + v[mid]) / 2;
}

// A timed row spans [min, max] over its repetitions; a figure taken once spans its value.
pooled_figure pool(const std::vector<const result_row*>& rows) {
    pooled_figure f{.value = 0,
                    .min = std::numeric_limits<double>::infinity(),
                    .max = -std::numeric_limits<double>::infinity(),
                    .rows = rows.size()};
    std::vector<double> values;
    for (const result_row* r : rows) {
        values.push_back(r->value);
        f.min = std::min(f.min, r->repetitions == 0 ? r->value : r->min_value);
        f.max = std::max(f.max, r->repetitions == 0 ? r->value : r->max_value);
        f.derived = f.derived && r->check == "derived";
    }
    f.value = median(std::move(values));
    return f;
}

// A ratio across units would be meaningless (and a unit change is a change of the metric).
std::string common_unit(const result_key& key, const key_rows& rows) {
    const result_row* first = nullptr;
    std::size_t first_side = 0;
    for (std::size_t s = 0; s < rows.size(); ++s)
        for (const result_row* r : rows[s]) {
            if (!first) {
                first = r;
                first_side = s;
            } else if (r->unit != first->unit) {
                throw std::runtime_error("unit differs for key " + to_string(key) + ": '" + first->unit + "' in " +
                                         side_names[first_side] + ", '" + r->unit + "' in " + side_names[s]);
            }
        }
    return first->unit;
}

verdict verdict_of(const comparison_entry& e) {
    if (!e.a) return verdict::only_in_b;
    if (!e.b) return verdict::only_in_a;
    if (e.a->value == e.b->value) return verdict::within_spread;
    // A ratio of other figures written once has no spread of its own: its components say
    // whether it moved.
    const auto single_derived = [](const pooled_figure& f) { return f.derived && f.rows == 1; };
    if (single_derived(*e.a) || single_derived(*e.b)) return verdict::no_spread;
    if (e.b->min > e.a->max) return verdict::higher;
    if (e.b->max < e.a->min) return verdict::lower;
    return verdict::within_spread;
}

comparison_entry entry_of(const result_key& key, const key_rows& rows) {
    comparison_entry e;
    e.key = key;
    e.unit = common_unit(key, rows);
    if (!rows[0].empty()) e.a = pool(rows[0]);
    if (!rows[1].empty()) e.b = pool(rows[1]);
    e.ratio = !e.a || !e.b               ? std::numeric_limits<double>::quiet_NaN()
              : e.a->value == e.b->value ? 1.0
                                         : e.b->value / e.a->value;
    e.outcome = verdict_of(e);
    return e;
}

}  // namespace

std::string_view to_string(verdict v) {
    switch (v) {
        case verdict::within_spread:
            return "within_spread";
        case verdict::higher:
            return "higher";
        case verdict::lower:
            return "lower";
        case verdict::only_in_a:
            return "only_in_a";
        case verdict::only_in_b:
            return "only_in_b";
        case verdict::no_spread:
            return "no_spread";
    }
    return "?";
}

std::size_t comparison::count(verdict v) const {
    return static_cast<std::size_t>(
        std::count_if(entries.begin(), entries.end(), [v](const comparison_entry& e) { return e.outcome == v; }));
}

comparison compare_results(const std::vector<result_row>& a, const std::vector<result_row>& b) {
    comparison out;
    std::map<result_key, key_rows> keys;
    const std::array<const std::vector<result_row>*, 2> sides = {&a, &b};
    const std::array<std::size_t*, 2> unvalidated = {&out.unvalidated_a, &out.unvalidated_b};
    for (std::size_t s = 0; s < sides.size(); ++s)
        for (const result_row& r : *sides[s]) {
            if (r.validated())
                keys[key_of(r)][s].push_back(&r);
            else
                ++*unvalidated[s];
        }
    for (const auto& [key, rows] : keys) out.entries.push_back(entry_of(key, rows));
    return out;
}

folder_comparison compare_result_folders(const std::filesystem::path& a, const std::filesystem::path& b) {
    const std::vector<std::string> in_a = result_table_names(a), in_b = result_table_names(b);
    folder_comparison out;
    std::set_difference(in_a.begin(), in_a.end(), in_b.begin(), in_b.end(), std::back_inserter(out.only_in_a));
    std::set_difference(in_b.begin(), in_b.end(), in_a.begin(), in_a.end(), std::back_inserter(out.only_in_b));
    std::vector<std::string> both;
    std::set_intersection(in_a.begin(), in_a.end(), in_b.begin(), in_b.end(), std::back_inserter(both));
    for (const std::string& name : both)
        out.tables.push_back({name, compare_results(read_results_csv(a / name), read_results_csv(b / name))});
    return out;
}

folder_comparison compare_result_paths(const std::filesystem::path& a, const std::filesystem::path& b) {
    const bool folder_a = std::filesystem::is_directory(a), folder_b = std::filesystem::is_directory(b);
    if (folder_a && folder_b) return compare_result_folders(a, b);
    if (folder_a || folder_b)
        throw std::runtime_error("compare takes two tables or two folders, not one of each: " +
                                 (folder_a ? a : b).string() + " is a folder");
    folder_comparison out;
    out.tables.push_back({a.filename().string(), compare_results(read_results_csv(a), read_results_csv(b))});
    return out;
}

namespace {

std::string figure_fields(const std::optional<pooled_figure>& f) {
    if (!f) return ",,,";
    return csv_number(f->value) + ',' + csv_number(f->min) + ',' + csv_number(f->max) + ',' + std::to_string(f->rows);
}

// How far a change went, for ranking: |log ratio|, and infinite when a sign flipped or a zero
// became something.
double change_size(double ratio) {
    return ratio > 0 && std::isfinite(ratio) ? std::abs(std::log(ratio)) : std::numeric_limits<double>::infinity();
}

std::string short_number(double v, int digits) {
    std::ostringstream os;
    os.precision(digits);
    os << v;
    return os.str();
}

std::string verdict_counts(const folder_comparison& c) {
    std::size_t keys = 0, unvalidated_a = 0, unvalidated_b = 0;
    std::array<std::size_t, all_verdicts.size()> n{};
    for (const auto& t : c.tables) {
        keys += t.result.entries.size();
        unvalidated_a += t.result.unvalidated_a;
        unvalidated_b += t.result.unvalidated_b;
        for (std::size_t i = 0; i < all_verdicts.size(); ++i) n[i] += t.result.count(all_verdicts[i]);
    }
    std::string out = std::to_string(c.tables.size()) + " table(s), " + std::to_string(keys) + " keys:";
    for (std::size_t i = 0; i < all_verdicts.size(); ++i)
        out += std::string(i == 0 ? " " : ", ") + std::string(to_string(all_verdicts[i])) + ' ' + std::to_string(n[i]);
    out += '\n';
    if (unvalidated_a + unvalidated_b > 0)
        out += "not compared (check none: nothing verified them): " + std::to_string(unvalidated_a) + " rows of A, " +
               std::to_string(unvalidated_b) + " rows of B\n";
    return out;
}

std::string joined(const std::vector<std::string>& names) {
    std::string out;
    for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
    return out;
}

std::string largest_changes(const folder_comparison& c, std::size_t most) {
    std::vector<std::pair<const std::string*, const comparison_entry*>> changes;
    for (const auto& t : c.tables)
        for (const auto& e : t.result.entries)
            if (e.outcome == verdict::higher || e.outcome == verdict::lower) changes.emplace_back(&t.table, &e);
    if (changes.empty()) return "no change beyond the runs' spread\n";
    std::stable_sort(changes.begin(), changes.end(), [](const auto& x, const auto& y) {
        return change_size(x.second->ratio) > change_size(y.second->ratio);
    });
    std::string out = "largest changes beyond the runs' spread (B / A):\n";
    for (std::size_t i = 0; i < std::min(most, changes.size()); ++i) {
        const auto& [table, e] = changes[i];
        out += "  " + std::string(to_string(e->outcome)) + " x" + short_number(e->ratio, 3) + "  " +
               short_number(e->a->value, 4) + " -> " + short_number(e->b->value, 4) + ' ' + e->unit + "  " + *table +
               "  " + to_string(e->key) + '\n';
    }
    if (changes.size() > most) out += "  ... and " + std::to_string(changes.size() - most) + " more (see the CSV)\n";
    return out;
}

}  // namespace

void write_comparison_csv(const std::filesystem::path& file, const folder_comparison& c) {
    std::string text =
        "table,suite,structure,bv,workload,n,dim,scalar,operation,params,metric,unit,verdict,ratio,"
        "a_value,a_min,a_max,a_rows,b_value,b_min,b_max,b_rows\n";
    for (const auto& t : c.tables)
        for (const auto& e : t.result.entries)
            text += csv_field(t.table) + ',' + to_string(e.key) + ',' + csv_field(e.unit) + ',' +
                    std::string(to_string(e.outcome)) + ',' + (std::isnan(e.ratio) ? "" : csv_number(e.ratio)) + ',' +
                    figure_fields(e.a) + ',' + figure_fields(e.b) + '\n';
    write_text_atomically(file, text);
}

std::string comparison_summary(const folder_comparison& c, std::size_t most) {
    std::string out = verdict_counts(c);
    if (!c.only_in_a.empty()) out += "tables only in A: " + joined(c.only_in_a) + '\n';
    if (!c.only_in_b.empty()) out += "tables only in B: " + joined(c.only_in_b) + '\n';
    return out + largest_changes(c, most);
}

}  // namespace harness
