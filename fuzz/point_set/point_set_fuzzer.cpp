// Fuzz target: the point-set readers (datasets/point_set_io.hpp): XYZ, OFF and OBJ (our own
// text parsers) and PLY, ASCII and binary (CGAL's reader after our header check).
//
// Input: the first byte chooses the format (its extension; ASCII or binary PLY is decided by
// the header, as in a real file), the rest is the file's content, written to a scratch file
// because load_point_set takes a path.
// Expected outcomes: the points, or datasets::load_error (the one documented error type).
// Findings: a sanitizer report, a hang, another exception type (it escapes and aborts), or an
// answer that breaks the documented promises: at least one point, every coordinate finite.

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "../common/finding.hpp"
#include "../common/quiet_console.hpp"
#include "../common/scratch_file.hpp"
#include "datasets/point_set_io.hpp"

namespace {

constexpr std::string_view target = "point_set";
// .xyzn and .pwn are read by the .xyz parser; listing them would only dilute the choice.
constexpr std::array<std::string_view, 4> extensions{".xyz", ".off", ".obj", ".ply"};

void check_points(const std::vector<spatial::point<double, 3>>& points) {
    if (points.empty()) spatial_fuzz::finding(target, "load_point_set returned no points without an error");
    for (const auto& p : points)
        for (std::size_t d = 0; d < 3; ++d)
            if (!std::isfinite(p[d])) spatial_fuzz::finding(target, "load_point_set returned a non-finite coordinate");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    const std::string_view extension = extensions[data[0] % extensions.size()];
    const auto file = spatial_fuzz::scratch().write(extension, std::span(data + 1, size - 1));
    const spatial_fuzz::quiet_console quiet;  // CGAL's PLY reader explains every rejection on std::cerr
    try {
        check_points(datasets::load_point_set(file));
    } catch (const datasets::load_error&) {
        // the documented answer to a malformed file
    }
    return 0;
}
