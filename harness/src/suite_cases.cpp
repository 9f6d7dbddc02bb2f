// The case list's selection and the suites' common end (see suite_cases.hpp).

#include "harness/suite_cases.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <string_view>

#include "harness/allocator_policy.hpp"
#include "harness/fault_injection.hpp"
#include "harness/memory_budget.hpp"
#include "harness/run_info.hpp"
#include "harness/validation.hpp"
#include "harness/timing.hpp"

namespace harness {

std::vector<const suite_case*> selected_cases(const std::vector<suite_case>& all, const suite_options& options) {
    std::vector<const suite_case*> out;
    for (std::size_t position = 0; position < all.size(); ++position) {
        const suite_case& c = all[position];
        const bool wanted = options.cases.empty() || std::find(options.cases.begin(), options.cases.end(), c.id) != options.cases.end();
        if (wanted && position % options.shard_count == options.shard_index) out.push_back(&c);
    }
    for (const auto& wanted : options.cases)
        if (std::none_of(all.begin(), all.end(), [&](const suite_case& c) { return c.id == wanted; }))
            throw std::invalid_argument("unknown case '" + wanted + "' in suite " + options.suite_name +
                                        " (spatialbench list --cases --suite " + options.suite_name + " lists them)");
    return out;
}

std::vector<std::string> ids_of(const std::vector<suite_case>& cases, const suite_options& options) {
    std::vector<std::string> ids;
    for (const suite_case* c : selected_cases(cases, options)) ids.push_back(c->id);
    return ids;
}

std::vector<case_time> run_cases(const std::vector<suite_case>& all, const suite_options& options,
                                 run_journal& journal, std::vector<result_row>& rows, const progress& prog) {
    const auto selected = selected_cases(all, options);
    // Before anything runs: a case that cannot fit is refused now, not killed hours later.
    for (const suite_case* c : selected) require_memory("case " + c->id, c->objects, c->bytes_per_object);
    std::size_t completed_here = 0;
    std::vector<case_time> times;
    for (const suite_case* c : selected) {
        const auto position = static_cast<std::size_t>(c - all.data());
        if (journal.completed(position)) {
            const auto& kept = journal.rows_of(position);
            rows.insert(rows.end(), kept.begin(), kept.end());
            prog.say("resumed: " + c->id + " from " + journal.dir().string() + " (" + std::to_string(kept.size()) + " rows)");
            continue;
        }
        const std::size_t before = rows.size();
        const auto case_started = std::chrono::steady_clock::now();
        try {
            c->run();
        } catch (const validation_error&) {
            journal.finish();  // a run that met a wrong answer keeps nothing
            throw;
        }
        times.push_back({c->id, seconds_since(case_started)});
        return_freed_memory();  // allocator_policy.hpp: kept within a case, not across cases
        journal.record(position, std::vector<result_row>(rows.begin() + static_cast<std::ptrdiff_t>(before), rows.end()));
        char took[32];
        std::snprintf(took, sizeof took, "%.1f s", times.back().seconds);
        prog.say("finished " + c->id + " in " + took);
        injected_interrupt(++completed_here);
    }
    return times;
}

void finish_suite(const suite_options& options, const std::vector<result_row>& rows, const std::string& run_id,
                  const std::map<std::string, std::uint64_t>& seeds, const std::map<std::string, std::string>& extra,
                  const std::vector<case_time>& case_times, std::chrono::steady_clock::time_point started,
                  const progress& prog) {
    const auto table = options.results_dir / options.output_name;
    write_csv_atomically(table, rows);
    run_info info{run_id, options.suite_name, options.preset, seeds, extra, case_times};
    if (options.shard_count > 1) info.extra["shard"] = std::to_string(options.shard_index) + "/" + std::to_string(options.shard_count);
    write_run_sidecar(options.results_dir, info, seconds_since(started));
    prog.say("wrote " + table.string() + " (" + std::to_string(rows.size()) + " rows), run " + run_id);
}

std::string case_size(std::size_t n) { return "n=" + std::to_string(n); }

}  // namespace harness
