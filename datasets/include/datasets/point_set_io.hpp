#pragma once
// Loading real point sets (scans, mesh vertices) as 3D double points.
//
// Formats, chosen by the file extension (case-insensitive):
//   .xyz .xyzn .pwn  text, one point per line: x y z, then any extra columns (normals,
//                    colours) which are ignored; blank lines and lines starting with # skipped.
//   .off             the vertices of an ASCII OFF mesh ([ST][C][N]OFF); faces ignored.
//   .obj             the `v x y z` vertices of a Wavefront OBJ mesh; everything else ignored.
//   .ply             ASCII or binary PLY, through CGAL's reader; only in builds configured with
//                    -DSPATIAL_WITH_CGAL=ON (see can_load_ply()).
// The text formats are parsed here (locale-independent std::from_chars), so their errors can
// name the line. Every error, including a NaN or infinite coordinate and a file without
// points, throws datasets::load_error whose message names the file.

#include <filesystem>
#include <span>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "spatial/core/point.hpp"

namespace datasets {

class load_error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// The points of `file`; see the format list above. O(file size).
std::vector<spatial::point<double, 3>> load_point_set(const std::filesystem::path& file);

// Extensions load_point_set accepts in this build (lower case, with the dot).
std::span<const std::string_view> supported_point_set_extensions() noexcept;

// An OFF mesh checked before CGAL's OFF reader is given it (harness::load_triangle_mesh), so
// that every line CGAL 5.5's scanner reads is the line we checked, holding what it indexes
// without bounds checks (each rule was a fuzzing finding or found tracing one; docs/fuzzing.md):
// - the counts line is exactly "vertices faces edges" (CGAL reads them from the stream, so
//   anything more, or a missing edge count, shifts every later line), the first two below 2^31;
// - no line holds a comma (CGAL's reader stops a line there);
// - the vertices as load_point_set reads them, each line with the columns its [ST][C][N] header
//   names, finite numbers only;
// - each face's line: a non-negative vertex count and that many indices, each a whole number
//   below the vertex count (converted to std::size_t by CGAL: undefined for negative or huge);
// - with C, a vertex's and a face's colour: 0, 1, 3 or 4 numbers, as many as the first line of
//   its kind has, that CGAL can convert to bytes (an index from 0 to 2^31 - 1; red, green, blue
//   whole from 0 to 255 or all from 0 to 1).
// Throws load_error naming the file and line. O(file size).
void check_off_faces(const std::filesystem::path& file);

// True when this build reads .ply files (it was configured with SPATIAL_WITH_CGAL=ON).
bool can_load_ply() noexcept;

}  // namespace datasets
