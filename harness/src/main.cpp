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

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"spatialbench: validated benchmarks of spatial data structures against CGAL, Embree and nanoflann"};
    app.require_subcommand(1);

    harness::suite_options opt;
    std::string suite = "knn";
    std::vector<std::string> runnable;
    std::string suite_help = "suite to run:";
    for (const auto& s : harness::suite_table())
        if (s.run) {
            runnable.push_back(s.name);
            suite_help += " " + s.name + " (" + s.description + ");";
        }
    auto* run = app.add_subcommand("run", "run a benchmark suite and write results/<suite>.csv");
    run->add_option("--suite", suite, suite_help)->check(CLI::IsMember(runnable));
    run->add_option("--preset", opt.preset, "size preset: smoke (seconds), quick (<15 min), full (1e7)")
        ->check(CLI::IsMember({"smoke", "quick", "full"}));
    run->add_option("--results", opt.results_dir, "directory for CSV tables and run sidecars");
    std::string output_name;
    run->add_option("--output", output_name, "CSV file name inside --results (default <suite>.csv)");
    run->add_option("--real-data", opt.real_data_dir, "directory of real data to add as workloads: point sets (.xyz, .ply) for knn/bv, meshes (.off .ply .obj .stl) for raycast");
    run->add_option("--workload", opt.workloads, "restrict to these generated workloads (bv: shapes; raycast: sphere, soup)");
    run->add_option("--structure", opt.structures, "restrict to these structures (see `spatialbench list`)");
    run->add_option("--n", opt.sizes, "restrict to these sizes");
    run->add_option("--case", opt.cases, "run only these cases (ids from `spatialbench list --cases --suite S`)");
    run->add_option("--seed", opt.seed, "seed of every generated workload (logged in the run sidecar)");
    run->add_flag("--quiet", opt.quiet, "no progress output");
    bool no_dynamic = false;
    run->add_flag("--no-dynamic", no_dynamic, "skip the insert/erase workloads");

    auto* list = app.add_subcommand("list", "list suites, workloads, structures and peers");
    bool list_json = false, list_cases = false;
    list->add_flag("--json", list_json, "print the registry as JSON (what results/registry.json holds)");
    list->add_flag("--cases", list_cases, "print the ids of the suite's independent cases (with --suite, --preset and the run filters)");
    harness::suite_options list_opt;
    std::string list_suite;
    list->add_option("--suite", list_suite, "the suite whose cases --cases lists")->check(CLI::IsMember(runnable));
    list->add_option("--preset", list_opt.preset, "size preset of the case list")->check(CLI::IsMember({"smoke", "quick", "full"}));
    list->add_option("--real-data", list_opt.real_data_dir, "real data directory, as for run");
    list->add_option("--workload", list_opt.workloads, "restrict to these workloads, as for run");
    list->add_option("--n", list_opt.sizes, "restrict to these sizes, as for run");

    std::vector<std::string> scene_files;
    harness::scene_run_options scene_opt;
    std::filesystem::path scene_results = "results";
    std::string scene_output = "scenes.csv";
    auto* scene = app.add_subcommand("scene", "run scene files (datasets/scenes/*.toml) and write results/scenes.csv");
    scene->add_option("files", scene_files, "scene files (TOML)")->required()->check(CLI::ExistingFile);
    scene->add_option("--structure", scene_opt.structures,
                      "structure(s) to run: " + names_in(harness::in::scenes) + ", or all (default bvh)");
    scene->add_option("--steps", scene_opt.steps, "override the scene's number of steps");
    scene->add_option("--results", scene_results, "directory for the CSV table and the run sidecar");
    scene->add_option("--output", scene_output, "CSV file name inside --results");
    scene->add_flag("--quiet", scene_opt.quiet, "no progress output");

    CLI11_PARSE(app, argc, argv);

    if (*list)
        return guarded([&] {
            if (list_cases) {
                if (list_suite.empty()) throw std::invalid_argument("list --cases needs --suite");
                list_opt.suite_name = list_suite;
                for (const auto& id : harness::find_suite(list_suite)->case_ids(list_opt)) std::cout << id << '\n';
            } else if (list_json) {
                std::cout << harness::registry_json();
            } else {
                print_list();
            }
        });
    if (*scene)
        return guarded([&] {
            scene_opt.run_id = harness::make_run_id("scenes", "scene");
            const auto t0 = std::chrono::steady_clock::now();
            std::vector<harness::result_row> rows;
            harness::scene_counters counters;
            for (const auto& f : scene_files) {
                const auto description = datasets::load_scene(f);
                auto r = harness::run_scene(description, scene_opt, counters);
                rows.insert(rows.end(), r.begin(), r.end());
            }
            harness::write_csv_atomically(scene_results / scene_output, rows);
            harness::write_registry_json(scene_results);
            harness::run_info info{scene_opt.run_id, "scenes", "scene", {}, {}};
            for (std::size_t i = 0; i < scene_files.size(); ++i) info.extra["scene_" + std::to_string(i)] = scene_files[i];
            harness::write_run_sidecar(scene_results, info, harness::seconds_since(t0));
            if (!scene_opt.quiet)
                std::fprintf(stderr, "spatialbench: wrote %s (%zu rows)\n", (scene_results / scene_output).c_str(), rows.size());
        });
    opt.dynamic = !no_dynamic;
    opt.suite_name = suite;
    const harness::suite_entry& entry = *harness::find_suite(suite);
    opt.output_name = output_name.empty() ? entry.table : output_name;
    return guarded([&] {
        entry.run(opt);
        harness::write_registry_json(opt.results_dir);
    });
}
