#pragma once
// The spatialbench command line, parsed and checked without running anything: every
// subcommand's options bound to CLI11, the values CLI11 cannot check (--shard i/N; list --cases
// needs --suite) checked after it. main.cpp runs what was asked; the command-line fuzz target
// (fuzz/command_line/) parses argument vectors built from its bytes and runs nothing.
//
// A command line is either parsed, or refused with a usage error that has a message:
//   * CLI::ParseError, CLI11's own (an unknown option, a missing or malformed value, a value
//     outside a set, no subcommand, --help: CLI::CallForHelp, exit code 0); print it with
//     command_line::exit, which is what CLI11_PARSE does;
//   * std::invalid_argument, for the checks after CLI11's (main prints "spatialbench: error:").
// Exit code of both: 1 (0 for --help).
//
// The names the command line accepts that come from the suites (suite_table.hpp) and the
// structure registry are passed in (command_line_vocabulary), so this library links neither:
// parsing needs no suite, no structure and no peer.

#include <CLI/CLI.hpp>
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include "harness/scene_runner.hpp"
#include "harness/suite_options.hpp"

namespace harness {

struct command_line_vocabulary {
    struct suite {
        std::string name, description;
    };
    std::vector<suite> runnable_suites;  // what run --suite and list --suite accept
    std::string scene_structures;        // the scene command's --structure help: the names, space-separated
};

// `spatialbench run`: one suite of harness/suite_table.hpp.
struct run_arguments {
    CLI::App* app = nullptr;
    suite_options opt;  // with shard_index and shard_count from --shard, dynamic from --no-dynamic
    std::string suite = "knn";
    std::string output_name;  // empty: the suite's table
    std::string shard;
    bool no_dynamic = false;
    bool fresh_memory = false;  // glibc's defaults instead of keeping freed memory (allocator_policy.hpp)
};

// `spatialbench list`: the registries, as text or JSON, or one suite's case ids.
struct list_arguments {
    CLI::App* app = nullptr;
    bool json = false, cases = false;
    suite_options opt;  // with suite_name, and the shard from --shard
    std::string suite, shard;
};

// `spatialbench scene FILE...`: scene files, one table.
struct scene_arguments {
    CLI::App* app = nullptr;
    std::vector<std::string> files;
    scene_run_options opt;
    std::filesystem::path results = "results";
    std::string output = "scenes.csv";
    std::string shard;
    suite_options sharding;  // shard_index and shard_count from --shard
    bool fresh_memory = false;
};

// `spatialbench compare A B`.
struct compare_arguments {
    CLI::App* app = nullptr;
    std::filesystem::path a, b, output;
};

// `spatialbench merge DIR... --results OUT`.
struct merge_arguments {
    CLI::App* app = nullptr;
    std::vector<std::filesystem::path> shards;
    std::filesystem::path results;
    bool repeated_runs = false;
    bool quiet = false;
};

class command_line {
public:
    enum class command { run, list, scene, compare, merge };

    explicit command_line(const command_line_vocabulary& vocabulary);
    command_line(const command_line&) = delete;  // the subcommands point into app_
    command_line& operator=(const command_line&) = delete;

    // Parses argv (argv[0] is the program's name); throws the usage errors above.
    void parse(int argc, const char* const* argv);
    // The subcommand parse() found.
    command chosen() const;
    // Prints a CLI11 usage error as CLI11_PARSE does (help to `out`, the message to `err`) and
    // returns the exit code.
    int exit(const CLI::Error& error, std::ostream& out, std::ostream& err) const;

    run_arguments run;
    list_arguments list;
    scene_arguments scene;
    compare_arguments compare;
    merge_arguments merge;

private:
    void check_after_parsing();

    CLI::App app_;
};

}  // namespace harness
