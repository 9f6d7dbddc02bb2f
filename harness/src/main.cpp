// spatialbench — the benchmark harness CLI.
//   spatialbench run --suite SUITE [--preset smoke|quick|full] [--results DIR] [--real-data DIR] [--resume]
//                    [--workload W ...] [--structure S ...] [--n N ...] [--seed S] [--quiet]
//   spatialbench scene FILE... [--structure NAME|all] [--steps N] [--results DIR] [--output scenes.csv] [--quiet]
//   spatialbench list [--json] [--cases --suite SUITE [--shard i/N] ...]
//   spatialbench compare A B [--output FILE]      (two tables or two result folders)
//   spatialbench merge DIR... --results OUT        (the shards of a run, joined; --repeated-runs:
//                                                   runs of the same cases, one table)
// `run`, `list --cases` and `scene` take --shard i/N: a deterministic 1/N of the cases.
// The suites come from harness/suite_table.hpp, the structures from structure_registry.hpp and
// peer_registry.hpp: this file names none of them.
// Exit codes: 0 success, 1 bad usage or input, 2 validation failure (a wrong answer).

#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>

#include "datasets/generators.hpp"
#include "datasets/mesh_generators.hpp"
#include "datasets/shapes.hpp"
#include "datasets/scene.hpp"
#include "harness/peer_registry.hpp"
#include "harness/result_compare.hpp"
#include "harness/result_merge.hpp"
#include "harness/run_info.hpp"
#include "harness/scene_runner.hpp"
#include "harness/structure_registry.hpp"
#include "harness/suite_table.hpp"
#include "harness/timing.hpp"
#include "harness/validation.hpp"

namespace {

// Runs a command and maps its failures to the documented exit codes: 2 for a wrong answer
// (nothing was written), 1 for bad usage or input.
template <class F>
int guarded(F&& command) {
    try {
        command();
    } catch (const harness::validation_error& e) {
        std::fprintf(stderr, "spatialbench: VALIDATION FAILED, nothing written: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "spatialbench: error: %s\n", e.what());
        return 1;
    }
    return 0;
}

// The structure names of a suite part, for the help text and `list`.
std::string names_in(unsigned suite_bits) {
    std::string out;
    for (const auto* list : {&harness::registered_structures(), &harness::registered_peers()})
        for (const auto& s : *list)
            if (s.takes_part_in(suite_bits)) out += (out.empty() ? "" : " ") + s.name;
    return out;
}

void print_list() {
    std::cout << "suites:\n";
    for (const auto& s : harness::suite_table()) std::cout << "  " << s.name << ": " << s.description << '\n';
    std::cout << "workloads (collide): boxes moving_boxes triangles\nworkloads (knn, structures):";
    for (auto w : datasets::point_workload_names()) std::cout << ' ' << w;
    std::cout << "\nshapes (bv):";
    for (const auto& w : datasets::shape_names()) std::cout << ' ' << w;
    std::cout << "\nworkloads (raycast):";
    for (auto w : datasets::mesh_workload_names) std::cout << ' ' << w;
    std::cout << "\nstructures (in-house, harness/structure_registry.hpp):\n";
    for (const auto& s : harness::registered_structures())
        std::cout << "  " << s.name << " [" << s.kind << "]: " << s.description << '\n';
    std::cout << "peers (harness/peer_registry.hpp; built into this binary when their adapter is):\n";
    for (const auto& s : harness::registered_peers())
        std::cout << "  " << s.name << " [" << s.library << "]: " << s.description << '\n';
}

// `spatialbench run`: one suite of harness/suite_table.hpp.
struct run_command {
    CLI::App* app = nullptr;
    harness::suite_options opt;
    std::string suite = "knn";
    std::string output_name;
    std::string shard;
    bool no_dynamic = false;

    void add_to(CLI::App& parent, const std::vector<std::string>& runnable, const std::string& suite_help) {
        app = parent.add_subcommand("run", "run a benchmark suite and write results/<suite>.csv");
        app->add_option("--suite", suite, suite_help)->check(CLI::IsMember(runnable));
        app->add_option("--preset", opt.preset, "size preset: smoke (seconds), quick (up to 1e6; each run's wall time: results/provenance.md), full (1e7)")
            ->check(CLI::IsMember({"smoke", "quick", "full"}));
        app->add_option("--results", opt.results_dir, "directory for CSV tables and run sidecars");
        app->add_option("--output", output_name, "CSV file name inside --results (default <suite>.csv)");
        app->add_option("--real-data", opt.real_data_dir, "directory of real data to add as workloads: point sets (.xyz, .ply) for knn/bv, meshes (.off .ply .obj .stl) for raycast");
        app->add_option("--workload", opt.workloads, "restrict to these generated workloads (bv: shapes; raycast: sphere, soup)");
        app->add_option("--structure", opt.structures, "restrict to these structures (see `spatialbench list`)");
        app->add_option("--n", opt.sizes, "restrict to these sizes");
        app->add_option("--case", opt.cases, "run only these cases (ids from `spatialbench list --cases --suite S`)");
        app->add_option("--shard", shard, "run a deterministic 1/N of the cases: i/N takes those at positions i mod N (0 <= i < N) of `list --cases`");
        app->add_option("--seed", opt.seed, "seed of every generated workload (logged in the run sidecar)");
        app->add_flag("--quiet", opt.quiet, "no progress output");
        app->add_flag("--no-dynamic", no_dynamic, "skip the insert/erase workloads");
        app->add_flag("--resume", opt.resume, "finish an interrupted run: skip the cases its journal (<results>/<table>.journal/) holds");
    }

    int execute() {
        opt.dynamic = !no_dynamic;
        opt.suite_name = suite;
        const harness::suite_entry& entry = *harness::find_suite(suite);
        opt.output_name = output_name.empty() ? entry.table : output_name;
        return guarded([&] {
            if (!shard.empty()) harness::parse_shard(shard, opt);
            entry.run(opt);
            harness::write_registry_json(opt.results_dir);
        });
    }
};

// `spatialbench list`: the registries, as text or JSON, or one suite's case ids.
struct list_command {
    CLI::App* app = nullptr;
    bool json = false, cases = false;
    harness::suite_options opt;
    std::string suite, shard;

    void add_to(CLI::App& parent, const std::vector<std::string>& runnable) {
        app = parent.add_subcommand("list", "list suites, workloads, structures and peers");
        app->add_flag("--json", json, "print the registry as JSON (what results/registry.json holds)");
        app->add_flag("--cases", cases, "print the ids of the suite's independent cases (with --suite, --preset and the run filters)");
        app->add_option("--suite", suite, "the suite whose cases --cases lists")->check(CLI::IsMember(runnable));
        app->add_option("--preset", opt.preset, "size preset of the case list")->check(CLI::IsMember({"smoke", "quick", "full"}));
        app->add_option("--real-data", opt.real_data_dir, "real data directory, as for run");
        app->add_option("--workload", opt.workloads, "restrict to these workloads, as for run");
        app->add_option("--n", opt.sizes, "restrict to these sizes, as for run");
        app->add_option("--shard", shard, "only the cases of shard i/N, as for run");
    }

    int execute() {
        return guarded([&] {
            if (cases) {
                if (suite.empty()) throw std::invalid_argument("list --cases needs --suite");
                opt.suite_name = suite;
                if (!shard.empty()) harness::parse_shard(shard, opt);
                for (const auto& id : harness::find_suite(suite)->case_ids(opt)) std::cout << id << '\n';
            } else if (json) {
                std::cout << harness::registry_json();
            } else {
                print_list();
            }
        });
    }
};

// `spatialbench scene`: scene files, one table.
struct scene_command {
    CLI::App* app = nullptr;
    std::vector<std::string> files;
    harness::scene_run_options opt;
    std::filesystem::path results = "results";
    std::string output = "scenes.csv";
    std::string shard;

    void add_to(CLI::App& parent) {
        app = parent.add_subcommand("scene", "run scene files (datasets/scenes/*.toml) and write results/scenes.csv");
        app->add_option("files", files, "scene files (TOML)")->required()->check(CLI::ExistingFile);
        app->add_option("--structure", opt.structures, "structure(s) to run: " + names_in(harness::in::scenes) + ", or all (default bvh)");
        app->add_option("--steps", opt.steps, "override the scene's number of steps");
        app->add_option("--results", results, "directory for the CSV table and the run sidecar");
        app->add_option("--output", output, "CSV file name inside --results");
        app->add_option("--shard", shard, "run the files at positions i mod N of the list (i/N, 0 <= i < N)");
        app->add_flag("--quiet", opt.quiet, "no progress output");
    }

    int execute() {
        return guarded([&] {
            harness::suite_options sharding;
            if (!shard.empty()) harness::parse_shard(shard, sharding);
            std::vector<std::string> mine;
            for (std::size_t i = sharding.shard_index; i < files.size(); i += sharding.shard_count) mine.push_back(files[i]);
            files = std::move(mine);
            opt.run_id = harness::make_run_id("scenes", "scene", sharding.shard_label());
            const auto t0 = std::chrono::steady_clock::now();
            std::vector<harness::result_row> rows;
            harness::scene_counters counters;
            for (const auto& f : files) {
                auto r = harness::run_scene(datasets::load_scene(f), opt, counters);
                rows.insert(rows.end(), r.begin(), r.end());
            }
            harness::write_csv_atomically(results / output, rows);
            harness::write_registry_json(results);
            harness::run_info info{opt.run_id, "scenes", "scene", {}, {}};
            for (std::size_t i = 0; i < files.size(); ++i) info.extra["scene_" + std::to_string(i)] = files[i];
            if (!shard.empty()) info.extra["shard"] = shard;
            harness::write_run_sidecar(results, info, harness::seconds_since(t0));
            if (!opt.quiet) std::fprintf(stderr, "spatialbench: wrote %s (%zu rows)\n", (results / output).c_str(), rows.size());
        });
    }
};

// `spatialbench compare A B`: B against A, figure by figure (harness/result_compare.hpp).
struct compare_command {
    CLI::App* app = nullptr;
    std::filesystem::path a, b, output;

    void add_to(CLI::App& parent) {
        app = parent.add_subcommand("compare", "compare run B with run A (two tables or two result folders): ratio B/A per figure, flagged only beyond both runs' spread");
        app->add_option("A", a, "the reference: a results table (.csv) or folder")->required()->check(CLI::ExistingPath);
        app->add_option("B", b, "the run compared with it, of the same kind")->required()->check(CLI::ExistingPath);
        app->add_option("--output", output, "also write the comparison as a CSV table here");
    }

    int execute() {
        return guarded([&] {
            const auto result = harness::compare_result_paths(a, b);
            std::cout << harness::comparison_summary(result);
            if (!output.empty()) harness::write_comparison_csv(output, result);
        });
    }
};

// `spatialbench merge DIR... --results OUT`: the shards of one run joined into the tables a
// single run writes (harness/result_merge.hpp), with every shard's sidecar copied next to them.
struct merge_command {
    CLI::App* app = nullptr;
    std::vector<std::filesystem::path> shards;
    std::filesystem::path results;
    bool repeated_runs = false;
    bool quiet = false;

    void add_to(CLI::App& parent) {
        app = parent.add_subcommand("merge", "join the result folders of a sharded run (run --shard i/N) into one");
        app->add_option("DIR", shards, "the shards' result folders")->required()->check(CLI::ExistingDirectory);
        app->add_option("--results", results, "folder for the merged tables (tables there of the same names are replaced)")->required();
        app->add_flag("--repeated-runs", repeated_runs,
                      "the folders are runs of the same cases: keep every run's rows of a key (told apart by run_id)");
        app->add_flag("--quiet", quiet, "no summary");
    }

    int execute() {
        return guarded([&] {
            const auto tables = harness::merge_result_folders(
                shards, repeated_runs ? harness::merge_kind::repeated_runs : harness::merge_kind::shards);
            std::filesystem::create_directories(results / "runs");
            // Sidecars first: a merged table never names a run whose sidecar is missing.
            for (const auto& dir : shards)
                if (std::filesystem::is_directory(dir / "runs"))
                    for (const auto& sidecar : std::filesystem::directory_iterator(dir / "runs"))
                        std::filesystem::copy_file(sidecar.path(), results / "runs" / sidecar.path().filename(),
                                                   std::filesystem::copy_options::overwrite_existing);
            for (const auto& [name, rows] : tables) {
                harness::write_csv_atomically(results / name, rows);
                if (!quiet) std::fprintf(stderr, "spatialbench: merged %s (%zu rows)\n", (results / name).c_str(), rows.size());
            }
            harness::write_registry_json(results);
        });
    }
};

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"spatialbench: validated benchmarks of spatial data structures against CGAL, Embree and nanoflann"};
    app.require_subcommand(1);
    std::vector<std::string> runnable;
    std::string suite_help = "suite to run:";
    for (const auto& s : harness::suite_table())
        if (s.run) {
            runnable.push_back(s.name);
            suite_help += " " + s.name + " (" + s.description + ");";
        }
    run_command run;
    list_command list;
    scene_command scene;
    compare_command compare;
    merge_command merge;
    run.add_to(app, runnable, suite_help);
    list.add_to(app, runnable);
    scene.add_to(app);
    compare.add_to(app);
    merge.add_to(app);
    CLI11_PARSE(app, argc, argv);
    if (*list.app) return list.execute();
    if (*scene.app) return scene.execute();
    if (*compare.app) return compare.execute();
    if (*merge.app) return merge.execute();
    return run.execute();
}
