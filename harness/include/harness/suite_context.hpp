#pragma once
// harness::suite_context — the state one suite run shares across its cases: the options, the
// preset's settings, the run id, progress output, the rows measured so far (written only when
// every case has passed: suite_cases.hpp's finish_suite) and the seeds the sidecar records.

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "harness/csv_writer.hpp"
#include "harness/progress.hpp"
#include "harness/row_scope.hpp"
#include "harness/run_info.hpp"
#include "harness/suite_cases.hpp"
#include "harness/suite_options.hpp"

namespace harness {

template <class Preset>
struct suite_context {
    std::string suite;  // the CSV suite column
    suite_options opt;
    Preset cfg;
    std::string run_id;
    progress prog;
    std::vector<result_row> rows;
    std::map<std::string, std::uint64_t> seeds;
    std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();
    std::unique_ptr<run_journal> journal = nullptr;  // while the cases run (run_journal.hpp)
    std::vector<case_time> case_times{};             // of the cases run here (the sidecar's)

    // Whether --structure (empty: every structure) selects `structure`.
    bool wants(const std::string& structure) const {
        return opt.structures.empty() ||
               std::find(opt.structures.begin(), opt.structures.end(), structure) != opt.structures.end();
    }

    // The rows of one case: this suite and run, on `workload` at n, dim, scalar.
    row_scope scope(const std::string& workload, std::size_t n, std::size_t dim = 3,
                    const std::string& scalar = "double") const {
        return {suite, run_id, workload, n, dim, scalar};
    }

    // Runs the selected cases of `cases` (the suite's whole list, in order), journaled: a
    // resumed run takes the interrupted run's id and its completed cases.
    void run(const std::vector<suite_case>& cases) {
        journal = std::make_unique<run_journal>(opt, run_id, ids_of(cases, suite_options{}));
        run_id = journal->run_id();
        case_times = run_cases(cases, opt, *journal, rows, prog);
    }

    // The suite's end (finish_suite): the table, the sidecar with the seeds, `extra` and the
    // cases' wall times; then the journal goes (the table holds every case now).
    void finish(const std::map<std::string, std::string>& extra = {}) {
        finish_suite(opt, rows, run_id, seeds, extra, case_times, started, prog);
        if (journal) journal->finish();
    }
};

// A suite's context from its options and preset: run id "<suite>-<preset>-...", the data seed
// recorded.
template <class Preset>
suite_context<Preset> make_suite_context(const std::string& suite, const suite_options& options, Preset cfg) {
    suite_context<Preset> ctx{suite, options, std::move(cfg), make_run_id(suite, options.preset, options.shard_label()), progress(options.quiet),
                              {}, {}};
    ctx.seeds["data"] = options.seed;
    return ctx;
}

}  // namespace harness
