// harness::parse_shard (see suite_options.hpp): apart from the suites, so the command line
// (command_line.cpp) parses --shard without linking them.

#include "harness/suite_options.hpp"

#include <charconv>
#include <stdexcept>
#include <string_view>

namespace harness {

void parse_shard(const std::string& text, suite_options& options) {
    const auto bad = [&](const std::string& why) {
        return std::invalid_argument("--shard '" + text + "': " + why + " (expected i/N with 0 <= i < N, e.g. 0/3)");
    };
    const auto slash = text.find('/');
    if (slash == std::string::npos) throw bad("no '/'");
    std::size_t index = 0, count = 0;
    const auto parse = [&](std::string_view part, std::size_t& value) {
        const auto [end, ec] = std::from_chars(part.data(), part.data() + part.size(), value);
        if (part.empty() || ec != std::errc() || end != part.data() + part.size()) throw bad("'" + std::string(part) + "' is not a count");
    };
    parse(std::string_view(text).substr(0, slash), index);
    parse(std::string_view(text).substr(slash + 1), count);
    if (count == 0) throw bad("N must be at least 1");
    if (index >= count) throw bad("i must be less than N");
    options.shard_index = index;
    options.shard_count = count;
}

}  // namespace harness
