// spatialbench — the benchmark harness CLI.
//   spatialbench run --suite SUITE [--preset smoke|quick|full] [--results DIR] [--real-data DIR] [--resume]
//                    [--workload W ...] [--structure S ...] [--n N ...] [--seed S] [--fresh-memory] [--quiet]
//   spatialbench scene FILE... [--structure NAME|all] [--steps N] [--results DIR] [--output scenes.csv] [--fresh-memory] [--quiet]
//   spatialbench list [--json] [--cases --suite SUITE [--shard i/N] ...]
//   spatialbench compare A B [--output FILE]      (two tables or two result folders)
//   spatialbench merge DIR... --results OUT        (the shards of a run, joined; --repeated-runs:
//                                                   runs of the same cases, one table)
// `run`, `list --cases` and `scene` take --shard i/N: a deterministic 1/N of the cases.
// The suites come from harness/suite_table.hpp, the structures from structure_registry.hpp and
// peer_registry.hpp: this file names none of them. The options and their checks are
// harness/command_line.hpp (parsed without running anything); this file runs what they ask.
// Exit codes: 0 success, 1 bad usage or input, 2 validation failure (a wrong answer).

#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>
#include <stdexcept>

#include "datasets/generators.hpp"
#include "datasets/mesh_generators.hpp"
#include "datasets/shapes.hpp"
#include "datasets/scene.hpp"
#include "harness/allocator_policy.hpp"
#include "harness/command_line.hpp"
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
int execute(harness::run_arguments& a) {
    harness::set_freed_memory_policy(a.fresh_memory ? harness::freed_memory::returned : harness::freed_memory::kept);
    const harness::suite_entry& entry = *harness::find_suite(a.suite);
    a.opt.output_name = a.output_name.empty() ? entry.table : a.output_name;
    return guarded([&] {
        entry.run(a.opt);
        harness::write_registry_json(a.opt.results_dir);
    });
}

// `spatialbench list`: the registries, as text or JSON, or one suite's case ids.
int execute(const harness::list_arguments& a) {
    return guarded([&] {
        if (a.cases) {
            for (const auto& id : harness::find_suite(a.suite)->case_ids(a.opt)) std::cout << id << '\n';
        } else if (a.json) {
            std::cout << harness::registry_json();
        } else {
            print_list();
        }
    });
}

// `spatialbench scene`: scene files, one table.
int execute(harness::scene_arguments& a) {
    harness::set_freed_memory_policy(a.fresh_memory ? harness::freed_memory::returned : harness::freed_memory::kept);
    return guarded([&] {
        const harness::suite_options& sharding = a.sharding;
        std::vector<std::string> mine;
        for (std::size_t i = sharding.shard_index; i < a.files.size(); i += sharding.shard_count) mine.push_back(a.files[i]);
        a.files = std::move(mine);
        a.opt.run_id = harness::make_run_id("scenes", "scene", sharding.shard_label());
        const auto t0 = std::chrono::steady_clock::now();
        std::vector<harness::result_row> rows;
        harness::scene_counters counters;
        std::vector<harness::case_time> scene_seconds;
        for (const auto& f : a.files) {
            const auto scene_started = std::chrono::steady_clock::now();
            auto r = harness::run_scene(datasets::load_scene(f), a.opt, counters);
            rows.insert(rows.end(), r.begin(), r.end());
            scene_seconds.push_back({f, harness::seconds_since(scene_started)});
            harness::return_freed_memory();
        }
        harness::write_csv_atomically(a.results / a.output, rows);
        harness::write_registry_json(a.results);
        harness::run_info info{a.opt.run_id, "scenes", "scene", {}, {}, std::move(scene_seconds)};
        for (std::size_t i = 0; i < a.files.size(); ++i) info.extra["scene_" + std::to_string(i)] = a.files[i];
        if (!a.shard.empty()) info.extra["shard"] = a.shard;
        harness::write_run_sidecar(a.results, info, harness::seconds_since(t0));
        if (!a.opt.quiet) std::fprintf(stderr, "spatialbench: wrote %s (%zu rows)\n", (a.results / a.output).c_str(), rows.size());
    });
}

// `spatialbench compare A B`: B against A, figure by figure (harness/result_compare.hpp).
int execute(const harness::compare_arguments& a) {
    return guarded([&] {
        const auto result = harness::compare_result_paths(a.a, a.b);
        std::cout << harness::comparison_summary(result);
        if (!a.output.empty()) harness::write_comparison_csv(a.output, result);
    });
}

// `spatialbench merge DIR... --results OUT`: the shards of one run joined into the tables a
// single run writes (harness/result_merge.hpp), with every shard's sidecar copied next to them.
int execute(const harness::merge_arguments& a) {
    return guarded([&] {
        const auto tables = harness::merge_result_folders(
            a.shards, a.repeated_runs ? harness::merge_kind::repeated_runs : harness::merge_kind::shards);
        std::filesystem::create_directories(a.results / "runs");
        // Sidecars first: a merged table never names a run whose sidecar is missing.
        for (const auto& dir : a.shards)
            if (std::filesystem::is_directory(dir / "runs"))
                for (const auto& sidecar : std::filesystem::directory_iterator(dir / "runs"))
                    std::filesystem::copy_file(sidecar.path(), a.results / "runs" / sidecar.path().filename(),
                                               std::filesystem::copy_options::overwrite_existing);
        for (const auto& [name, rows] : tables) {
            harness::write_csv_atomically(a.results / name, rows);
            if (!a.quiet) std::fprintf(stderr, "spatialbench: merged %s (%zu rows)\n", (a.results / name).c_str(), rows.size());
        }
        harness::write_registry_json(a.results);
    });
}

// What the command line accepts from the suite table and the structure registry.
harness::command_line_vocabulary vocabulary() {
    harness::command_line_vocabulary v;
    for (const auto& s : harness::suite_table())
        if (s.run) v.runnable_suites.push_back({s.name, s.description});
    v.scene_structures = names_in(harness::in::scenes);
    return v;
}

}  // namespace

int main(int argc, char** argv) {
    harness::command_line cli(vocabulary());
    try {
        cli.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return cli.exit(e, std::cout, std::cerr);  // what CLI11_PARSE does
    } catch (const std::invalid_argument& e) {
        std::fprintf(stderr, "spatialbench: error: %s\n", e.what());
        return 1;
    }
    switch (cli.chosen()) {
        case harness::command_line::command::list: return execute(cli.list);
        case harness::command_line::command::scene: return execute(cli.scene);
        case harness::command_line::command::compare: return execute(cli.compare);
        case harness::command_line::command::merge: return execute(cli.merge);
        case harness::command_line::command::run: break;
    }
    return execute(cli.run);
}
