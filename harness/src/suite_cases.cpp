// The case list's selection and the suites' common end (see suite_cases.hpp).

#include "harness/suite_cases.hpp"

#include <algorithm>
#include <stdexcept>

#include "harness/run_info.hpp"
#include "harness/timing.hpp"

namespace harness {

std::vector<const suite_case*> selected_cases(const std::vector<suite_case>& all, const suite_options& options) {
    std::vector<const suite_case*> out;
    for (const auto& c : all)
        if (options.cases.empty() || std::find(options.cases.begin(), options.cases.end(), c.id) != options.cases.end())
            out.push_back(&c);
    for (const auto& wanted : options.cases)
        if (std::none_of(all.begin(), all.end(), [&](const suite_case& c) { return c.id == wanted; }))
            throw std::invalid_argument("unknown case '" + wanted + "' in suite " + options.suite_name +
                                        " (spatialbench list --cases --suite " + options.suite_name + " lists them)");
    return out;
}

std::vector<std::string> ids_of(const std::vector<suite_case>& cases) {
    std::vector<std::string> ids;
    for (const auto& c : cases) ids.push_back(c.id);
    return ids;
}

void run_cases(const std::vector<suite_case>& all, const suite_options& options) {
    for (const suite_case* c : selected_cases(all, options)) c->run();
}

void finish_suite(const suite_options& options, const std::vector<result_row>& rows, const std::string& run_id,
                  const std::map<std::string, std::uint64_t>& seeds, const std::map<std::string, std::string>& extra,
                  std::chrono::steady_clock::time_point started, const progress& prog) {
    const auto table = options.results_dir / options.output_name;
    write_csv_atomically(table, rows);
    run_info info{run_id, options.suite_name, options.preset, seeds, extra};
    write_run_sidecar(options.results_dir, info, seconds_since(started));
    prog.say("wrote " + table.string() + " (" + std::to_string(rows.size()) + " rows), run " + run_id);
}

std::string case_size(std::size_t n) { return "n=" + std::to_string(n); }

}  // namespace harness
