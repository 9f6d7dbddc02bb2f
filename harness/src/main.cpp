// spatialbench — the benchmark harness CLI.
//   spatialbench run --suite SUITE [--preset smoke|quick|full] [--results DIR] [--real-data DIR]
//                    [--workload W ...] [--structure S ...] [--n N ...] [--seed S] [--quiet]
//   spatialbench scene FILE... [--structure NAME|all] [--steps N] [--results DIR] [--output scenes.csv] [--quiet]
//   spatialbench list [--json]
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
    bool no_dynamic = false;

    void add_to(CLI::App& parent, const std::vector<std::string>& runnable, const std::string& suite_help) {
        app = parent.add_subcommand("run", "run a benchmark suite and write results/<suite>.csv");
        app->add_option("--suite", suite, suite_help)->check(CLI::IsMember(runnable));
        app->add_option("--preset", opt.preset, "size preset: smoke (seconds), quick (<15 min), full (1e7)")
            ->check(CLI::IsMember({"smoke", "quick", "full"}));
        app->add_option("--results", opt.results_dir, "directory for CSV tables and run sidecars");
        app->add_option("--output", output_name, "CSV file name inside --results (default <suite>.csv)");
        app->add_option("--real-data", opt.real_data_dir, "directory of real data to add as workloads: point sets (.xyz, .ply) for knn/bv, meshes (.off .ply .obj .stl) for raycast");
        app->add_option("--workload", opt.workloads, "restrict to these generated workloads (bv: shapes; raycast: sphere, soup)");
        app->add_option("--structure", opt.structures, "restrict to these structures (see `spatialbench list`)");
        app->add_option("--n", opt.sizes, "restrict to these sizes");
        app->add_option("--case", opt.cases, "run only these cases (ids from `spatialbench list --cases --suite S`)");
        app->add_option("--seed", opt.seed, "seed of every generated workload (logged in the run sidecar)");
        app->add_flag("--quiet", opt.quiet, "no progress output");
        app->add_flag("--no-dynamic", no_dynamic, "skip the insert/erase workloads");
    }

    int execute() {
        opt.dynamic = !no_dynamic;
        opt.suite_name = suite;
        const harness::suite_entry& entry = *harness::find_suite(suite);
        opt.output_name = output_name.empty() ? entry.table : output_name;
        return guarded([&] {
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
    std::string suite;

    void add_to(CLI::App& parent, const std::vector<std::string>& runnable) {
        app = parent.add_subcommand("list", "list suites, workloads, structures and peers");
        app->add_flag("--json", json, "print the registry as JSON (what results/registry.json holds)");
        app->add_flag("--cases", cases, "print the ids of the suite's independent cases (with --suite, --preset and the run filters)");
        app->add_option("--suite", suite, "the suite whose cases --cases lists")->check(CLI::IsMember(runnable));
        app->add_option("--preset", opt.preset, "size preset of the case list")->check(CLI::IsMember({"smoke", "quick", "full"}));
        app->add_option("--real-data", opt.real_data_dir, "real data directory, as for run");
        app->add_option("--workload", opt.workloads, "restrict to these workloads, as for run");
        app->add_option("--n", opt.sizes, "restrict to these sizes, as for run");
    }

    int execute() {
        return guarded([&] {
            if (cases) {
                if (suite.empty()) throw std::invalid_argument("list --cases needs --suite");
                opt.suite_name = suite;
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

    void add_to(CLI::App& parent) {
        app = parent.add_subcommand("scene", "run scene files (datasets/scenes/*.toml) and write results/scenes.csv");
        app->add_option("files", files, "scene files (TOML)")->required()->check(CLI::ExistingFile);
        app->add_option("--structure", opt.structures, "structure(s) to run: " + names_in(harness::in::scenes) + ", or all (default bvh)");
        app->add_option("--steps", opt.steps, "override the scene's number of steps");
        app->add_option("--results", results, "directory for the CSV table and the run sidecar");
        app->add_option("--output", output, "CSV file name inside --results");
        app->add_flag("--quiet", opt.quiet, "no progress output");
    }

    int execute() {
        return guarded([&] {
            opt.run_id = harness::make_run_id("scenes", "scene");
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
            harness::write_run_sidecar(results, info, harness::seconds_since(t0));
            if (!opt.quiet) std::fprintf(stderr, "spatialbench: wrote %s (%zu rows)\n", (results / output).c_str(), rows.size());
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
    run.add_to(app, runnable, suite_help);
    list.add_to(app, runnable);
    scene.add_to(app);
    CLI11_PARSE(app, argc, argv);
    if (*list.app) return list.execute();
    if (*scene.app) return scene.execute();
    return run.execute();
}
