// The spatialbench command line's options and checks (see command_line.hpp); the help texts
// are the CLI's documentation (`spatialbench SUBCOMMAND --help`).

#include "harness/command_line.hpp"

#include <ostream>
#include <stdexcept>

namespace harness {

namespace {

// run and scene take it alike (harness/allocator_policy.hpp).
constexpr const char* fresh_memory_help =
    "time with the allocator's defaults: large blocks freed to the system and mapped afresh (page faults in every round) instead of kept for reuse within a case";

std::vector<std::string> suite_names(const command_line_vocabulary& vocabulary) {
    std::vector<std::string> names;
    for (const auto& s : vocabulary.runnable_suites) names.push_back(s.name);
    return names;
}

void add_run(CLI::App& parent, run_arguments& a, const command_line_vocabulary& vocabulary) {
    std::string suite_help = "suite to run:";
    for (const auto& s : vocabulary.runnable_suites) suite_help += " " + s.name + " (" + s.description + ");";
    auto* app = a.app = parent.add_subcommand("run", "run a benchmark suite and write results/<suite>.csv");
    app->add_option("--suite", a.suite, suite_help)->check(CLI::IsMember(suite_names(vocabulary)));
    app->add_option("--preset", a.opt.preset, "size preset: smoke (seconds), quick (up to 1e6; each run's wall time: results/provenance.md), full (1e7)")
        ->check(CLI::IsMember({"smoke", "quick", "full"}));
    app->add_option("--results", a.opt.results_dir, "directory for CSV tables and run sidecars");
    app->add_option("--output", a.output_name, "CSV file name inside --results (default <suite>.csv)");
    app->add_option("--real-data", a.opt.real_data_dir, "directory of real data to add as workloads: point sets (.xyz, .ply) for knn/bv, meshes (.off .ply .obj .stl) for raycast");
    app->add_option("--workload", a.opt.workloads, "restrict to these generated workloads (bv: shapes; raycast: sphere, soup)");
    app->add_option("--structure", a.opt.structures, "restrict to these structures (see `spatialbench list`)");
    app->add_option("--n", a.opt.sizes, "restrict to these sizes");
    app->add_option("--case", a.opt.cases, "run only these cases (ids from `spatialbench list --cases --suite S`)");
    app->add_option("--shard", a.shard, "run a deterministic 1/N of the cases: i/N takes those at positions i mod N (0 <= i < N) of `list --cases`");
    app->add_option("--seed", a.opt.seed, "seed of every generated workload (logged in the run sidecar)");
    app->add_flag("--quiet", a.opt.quiet, "no progress output");
    app->add_flag("--no-dynamic", a.no_dynamic, "skip the insert/erase workloads");
    app->add_flag("--fresh-memory", a.fresh_memory, fresh_memory_help);
    app->add_flag("--resume", a.opt.resume, "finish an interrupted run: skip the cases its journal (<results>/<table>.journal/) holds");
}

void add_list(CLI::App& parent, list_arguments& a, const command_line_vocabulary& vocabulary) {
    auto* app = a.app = parent.add_subcommand("list", "list suites, workloads, structures and peers");
    app->add_flag("--json", a.json, "print the registry as JSON (what results/registry.json holds)");
    app->add_flag("--cases", a.cases, "print the ids of the suite's independent cases (with --suite, --preset and the run filters)");
    app->add_option("--suite", a.suite, "the suite whose cases --cases lists")->check(CLI::IsMember(suite_names(vocabulary)));
    app->add_option("--preset", a.opt.preset, "size preset of the case list")->check(CLI::IsMember({"smoke", "quick", "full"}));
    app->add_option("--real-data", a.opt.real_data_dir, "real data directory, as for run");
    app->add_option("--workload", a.opt.workloads, "restrict to these workloads, as for run");
    app->add_option("--n", a.opt.sizes, "restrict to these sizes, as for run");
    app->add_option("--shard", a.shard, "only the cases of shard i/N, as for run");
}

void add_scene(CLI::App& parent, scene_arguments& a, const command_line_vocabulary& vocabulary) {
    auto* app = a.app = parent.add_subcommand("scene", "run scene files (datasets/scenes/*.toml) and write results/scenes.csv");
    app->add_option("files", a.files, "scene files (TOML)")->required()->check(CLI::ExistingFile);
    app->add_option("--structure", a.opt.structures, "structure(s) to run: " + vocabulary.scene_structures + ", or all (default bvh)");
    app->add_option("--steps", a.opt.steps, "override the scene's number of steps");
    app->add_option("--results", a.results, "directory for the CSV table and the run sidecar");
    app->add_option("--output", a.output, "CSV file name inside --results");
    app->add_option("--shard", a.shard, "run the files at positions i mod N of the list (i/N, 0 <= i < N)");
    app->add_flag("--fresh-memory", a.fresh_memory, fresh_memory_help);
    app->add_flag("--quiet", a.opt.quiet, "no progress output");
}

void add_compare(CLI::App& parent, compare_arguments& a) {
    auto* app = a.app = parent.add_subcommand("compare", "compare run B with run A (two tables or two result folders): ratio B/A per figure, flagged only beyond both runs' spread");
    app->add_option("A", a.a, "the reference: a results table (.csv) or folder")->required()->check(CLI::ExistingPath);
    app->add_option("B", a.b, "the run compared with it, of the same kind")->required()->check(CLI::ExistingPath);
    app->add_option("--output", a.output, "also write the comparison as a CSV table here");
}

void add_merge(CLI::App& parent, merge_arguments& a) {
    auto* app = a.app = parent.add_subcommand("merge", "join the result folders of a sharded run (run --shard i/N) into one");
    app->add_option("DIR", a.shards, "the shards' result folders")->required()->check(CLI::ExistingDirectory);
    app->add_option("--results", a.results, "folder for the merged tables (tables there of the same names are replaced)")->required();
    app->add_flag("--repeated-runs", a.repeated_runs,
                  "the folders are runs of the same cases: keep every run's rows of a key (told apart by run_id)");
    app->add_flag("--quiet", a.quiet, "no summary");
}

}  // namespace

command_line::command_line(const command_line_vocabulary& vocabulary)
    : app_("spatialbench: validated benchmarks of spatial data structures against CGAL, Embree and nanoflann") {
    app_.require_subcommand(1);
    add_run(app_, run, vocabulary);
    add_list(app_, list, vocabulary);
    add_scene(app_, scene, vocabulary);
    add_compare(app_, compare);
    add_merge(app_, merge);
}

void command_line::parse(int argc, const char* const* argv) {
    app_.parse(argc, argv);
    check_after_parsing();
}

command_line::command command_line::chosen() const {
    if (*list.app) return command::list;
    if (*scene.app) return command::scene;
    if (*compare.app) return command::compare;
    if (*merge.app) return command::merge;
    return command::run;
}

int command_line::exit(const CLI::Error& error, std::ostream& out, std::ostream& err) const {
    return app_.exit(error, out, err);
}

void command_line::check_after_parsing() {
    switch (chosen()) {
        case command::run:
            run.opt.dynamic = !run.no_dynamic;
            run.opt.suite_name = run.suite;
            if (!run.shard.empty()) parse_shard(run.shard, run.opt);
            return;
        case command::list:
            if (!list.cases) return;  // the suite and the shard only select case ids
            if (list.suite.empty()) throw std::invalid_argument("list --cases needs --suite");
            list.opt.suite_name = list.suite;
            if (!list.shard.empty()) parse_shard(list.shard, list.opt);
            return;
        case command::scene:
            if (!scene.shard.empty()) parse_shard(scene.shard, scene.sharding);
            return;
        case command::compare:
        case command::merge: return;
    }
}

}  // namespace harness
