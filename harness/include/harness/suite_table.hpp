#pragma once
// harness::suite_table — the ONE table of the harness's suites: name, CSV table, what it
// measures, the baseline its ratios are taken against, its targets, and how to run it.
// main.cpp loops over it for `run`, `list` and the help text; results/registry.json carries
// it (with the structure and peer registries) to the plots. Adding a suite: its source file,
// one entry in suite_table.cpp, its plots module, its test, docs.

#include <filesystem>
#include <string>
#include <vector>

#include "harness/suite_options.hpp"

namespace harness {

// A performance target drawn on the suite's figures (and checked in results/README.md).
struct suite_target {
    std::string metric;     // speedup | steps_per_second | ...
    std::string structure;  // the structure it applies to ("" = any)
    std::string workload;
    std::size_t n = 0;
    double value = 0;
    std::string label;
};

struct suite_entry {
    std::string name;         // --suite NAME, the CSV `suite` column
    std::string table;        // default CSV file name in the results directory
    std::string description;  // one line, for the help text, `list` and the plots
    std::string baseline;     // the structure its ratios and speed-ups are taken against ("" = none)
    std::vector<suite_target> targets;
    std::vector<std::string> series_params;  // params keys that make separate curves (bv: method)
    // Scenes: the per-step stages in stacking order, the whole step, and the once-per-scene ones.
    std::vector<std::string> stages;
    std::string total_stage;
    std::vector<std::string> once_stages;
    // Runs the suite with these options; nullptr for `scenes`, run by `spatialbench scene`.
    void (*run)(const suite_options&) = nullptr;
    // The ids of the independent cases a run with these options would run (suite_cases.hpp).
    std::vector<std::string> (*case_ids)(const suite_options&) = nullptr;
};

const std::vector<suite_entry>& suite_table();
// The suite called `name`, or nullptr.
const suite_entry* find_suite(const std::string& name);

// results/registry.json: the suites, the structures and the peers with their metadata
// (schema_version 1, documented in plots/README.md), for the plots and for readers of the
// tables. Written atomically into `results_dir` by every `run` and `scene`.
std::string registry_json();
void write_registry_json(const std::filesystem::path& results_dir);

}  // namespace harness
