// Fuzz target: the spatialbench command line (harness/command_line.hpp), parsed and checked,
// nothing run. The bytes are the arguments after the program's name, separated by NUL bytes
// (fuzz/dict/command_line.dict holds the subcommands, options and the values they take).
// Expected: the options parsed (and valid: a known subcommand, suite and preset, a shard
// i/N with i < N, scene files given), or a usage error with a message: CLI::ParseError
// (printed by command_line::exit, as the CLI does; --help prints the help and exits 0) or
// std::invalid_argument. A finding: a crash, a sanitizer report, a hang, another exception
// type (it escapes and libFuzzer reports it), an error without a message, options that are
// not valid.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "../common/finding.hpp"
#include "harness/command_line.hpp"
#include "vocabulary.hpp"

namespace {

void require(bool ok, std::string_view what) {
    if (!ok) spatial_fuzz::finding("command_line", what);
}

std::vector<std::string> arguments(const std::uint8_t* data, std::size_t size) {
    std::vector<std::string> args{"spatialbench"};
    std::string current;
    for (std::size_t i = 0; i < size; ++i) {
        if (data[i] == 0) {
            args.push_back(current);
            current.clear();
        } else {
            current += static_cast<char>(data[i]);
        }
    }
    if (size > 0) args.push_back(current);
    return args;
}

bool is_preset(const std::string& p) { return p == "smoke" || p == "quick" || p == "full"; }
bool is_runnable(const std::string& suite) {
    const auto& suites = spatial_fuzz::command_line_vocabulary().runnable_suites;
    return std::any_of(suites.begin(), suites.end(), [&](const auto& s) { return s.name == suite; });
}
bool valid_shard(const harness::suite_options& o) { return o.shard_count >= 1 && o.shard_index < o.shard_count; }

// What a parsed command line must hold (what main.cpp relies on when it runs it).
void check_parsed(const harness::command_line& cli) {
    switch (cli.chosen()) {
        case harness::command_line::command::run:
            require(is_runnable(cli.run.suite), "run: a suite that is not runnable was accepted");
            require(is_preset(cli.run.opt.preset), "run: an unknown preset was accepted");
            require(valid_shard(cli.run.opt), "run: an invalid shard was accepted");
            require(cli.run.opt.dynamic == !cli.run.no_dynamic, "run: --no-dynamic not applied");
            return;
        case harness::command_line::command::list:
            if (!cli.list.cases) return;
            require(is_runnable(cli.list.suite), "list --cases: a suite that is not runnable was accepted");
            require(is_preset(cli.list.opt.preset), "list: an unknown preset was accepted");
            require(valid_shard(cli.list.opt), "list: an invalid shard was accepted");
            return;
        case harness::command_line::command::scene:
            require(!cli.scene.files.empty(), "scene: no file, accepted");
            require(valid_shard(cli.scene.sharding), "scene: an invalid shard was accepted");
            return;
        case harness::command_line::command::compare:
            require(!cli.compare.a.empty() && !cli.compare.b.empty(), "compare: A or B missing, accepted");
            return;
        case harness::command_line::command::merge:
            require(!cli.merge.shards.empty() && !cli.merge.results.empty(), "merge: no folder or no --results, accepted");
            return;
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::vector<std::string> args = arguments(data, size);
    std::vector<const char*> argv;
    for (const auto& a : args) argv.push_back(a.c_str());
    harness::command_line cli(spatial_fuzz::command_line_vocabulary());
    try {
        cli.parse(static_cast<int>(argv.size()), argv.data());
    } catch (const CLI::ParseError& e) {
        std::ostringstream out, err;
        const int code = cli.exit(e, out, err);  // formats the message, or the help
        if (code == 0) require(!out.str().empty(), "a usage error that exits 0 printed no help");
        else require(!err.str().empty() && !std::string_view(e.what()).empty(), "a usage error without a message");
        return 0;
    } catch (const std::invalid_argument& e) {
        require(!std::string_view(e.what()).empty(), "std::invalid_argument without a message");
        return 0;
    }
    check_parsed(cli);
    return 0;
}
