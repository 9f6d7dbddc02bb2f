// Fuzz target: the TOML scene reader (datasets/scene.hpp, datasets/src/scene_file.cpp).
//
// Input: the bytes are a scene file's text, given to parse_scene (load_scene reads a file
// into a string and calls it, so the file path adds nothing but I/O).
// Expected outcomes: a scene, or datasets::scene_error — the ONE error type scene.hpp and
// datasets/README.md ("Errors") document for every problem in a file. Anything else is a
// finding: a sanitizer report, a hang or timeout, or another exception type (it escapes, and
// libFuzzer reports the abort of std::terminate).
// Second oracle, for the files that parse: to_toml(scene) "reads back to the same text"
// (datasets/README.md), so writing, reading and writing again must give the same text, and
// what to_toml wrote must parse.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "../common/finding.hpp"
#include "datasets/scene.hpp"

namespace {

constexpr std::string_view target = "scene_file";
constexpr std::string_view file_name = "fuzz.toml";  // no directory: mesh paths stay relative

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    datasets::scene_description scene;
    try {
        scene = datasets::parse_scene(text, file_name);
    } catch (const datasets::scene_error&) {
        return 0;  // the documented answer to a malformed scene
    }
    const std::string written = datasets::to_toml(scene);
    std::string rewritten;
    try {
        rewritten = datasets::to_toml(datasets::parse_scene(written, file_name));
    } catch (const datasets::scene_error& e) {
        spatial_fuzz::finding(target, std::string("to_toml wrote a scene that parse_scene rejects: ") + e.what(), written);
    }
    if (rewritten != written)
        spatial_fuzz::finding(target, "to_toml(parse_scene(to_toml(scene))) differs from to_toml(scene)",
                              "first:\n" + written + "\nsecond:\n" + rewritten);
    return 0;
}
