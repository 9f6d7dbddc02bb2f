#pragma once
// harness::suite_case — the unit a suite is made of: one independent case (a workload at one
// size, scalar and dimension; a mesh; a scene) with a stable id, say
// "knn/uniform/n=100000/3d/double". Each suite lists its cases declaratively; the same list
// serves `spatialbench list --cases --suite S` and `spatialbench run --case ID`, and is the
// unit that sharding, resuming and comparing runs build on. A case builds its participants,
// validates them and only then times them, adding its rows to the suite's table.
//
// finish_suite() is the suite's common end: the table written atomically (only after every
// case passed: a wrong answer throws before it), the run's sidecar, the closing message.

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "harness/csv_writer.hpp"
#include "harness/progress.hpp"
#include "harness/run_info.hpp"
#include "harness/run_journal.hpp"
#include "harness/suite_options.hpp"

namespace harness {

struct suite_case {
    std::string id;             // stable: <suite>/<workload>/n=<n>[/<dim>d/<scalar>]
    std::function<void()> run;  // runs the case, adding its rows to the suite's table
    // What it will hold in memory, checked for every selected case before any runs
    // (memory_budget.hpp): objects x about this many bytes each (0: not estimated).
    std::size_t objects = 0;
    std::size_t bytes_per_object = 0;
};

// The cases of `all` that --case selects (all of them when options.cases is empty). Throws
// std::invalid_argument naming a requested id that the suite does not have.
std::vector<const suite_case*> selected_cases(const std::vector<suite_case>& all, const suite_options& options);

// The ids of the cases of `cases` that `options` selects (--case, --shard), in order: what
// `spatialbench list --cases` prints.
std::vector<std::string> ids_of(const std::vector<suite_case>& cases, const suite_options& options);

// Runs the selected cases in order, each case's rows appended to `rows` and recorded in
// `journal` as it completes; a case the journal already holds (a resumed run) is not run
// again, its journaled rows are appended instead. Returns the wall time of each case run here
// (resumed cases are not listed), in order.
std::vector<case_time> run_cases(const std::vector<suite_case>& all, const suite_options& options,
                                 run_journal& journal, std::vector<result_row>& rows, const progress& prog);

// The end every suite shares: writes options.results_dir / options.output_name atomically,
// then the run's JSON sidecar (seeds, `extra` and the cases' wall times), and says so.
void finish_suite(const suite_options& options, const std::vector<result_row>& rows, const std::string& run_id,
                  const std::map<std::string, std::uint64_t>& seeds, const std::map<std::string, std::string>& extra,
                  const std::vector<case_time>& case_times, std::chrono::steady_clock::time_point started,
                  const progress& prog);

// "n=1000" style size label used in case ids.
std::string case_size(std::size_t n);

}  // namespace harness
