#pragma once
// datasets::check_ply_header — a PLY header checked for what CGAL 5.5's PLY reader
// (CGAL::IO::internal::PLY_reader, behind CGAL::IO::read_PLY for point sets and for polygon
// soups) needs, before the file is handed to it. The point-set loader (point_set_io.hpp) and
// the mesh loader (harness/mesh_loading.hpp) both call it.
//
// Why: CGAL's reader accepts some headers and then dereferences a null pointer (caught by its
// assertions in debug builds; undefined behaviour, in practice a crash, in release builds,
// where the assertions are off). Found by fuzzing (docs/fuzzing.md):
//   * a property line before any element line: it is added to the last element of an empty list;
//   * a vertex coordinate x, y or z that is neither float nor double (an integer type, a list):
//     it is read through a dynamic_cast to float that fails;
//   * (meshes) colours where red (or r) is uchar but green or blue (g, b) has another type: the
//     colour is then read as uchar through a failed dynamic_cast.
// It also rejects what CGAL would read silently wrong: a vertex element without x, y or z
// (CGAL yields 0 for it), a property type CGAL does not know (CGAL skips the property, so
// every following value is read from the wrong column or byte offset).
// Lines are split into words as CGAL splits them (std::getline, then >> on the line), so both
// see the same keywords.

#include <cstddef>
#include <cstdint>
#include <istream>
#include <string>

namespace datasets {

enum class ply_use {
    points,  // read_PLY into points: the vertex elements only
    mesh,    // read_PLY into a polygon soup: also the colours of vertices and faces
};

struct ply_header_check {
    std::string problem;             // empty when the header is fit for CGAL's reader
    std::size_t line = 0;            // the line of the problem; 0 when it concerns the whole header
    std::uint64_t vertex_count = 0;  // declared vertices: the sum over the "vertex" / "vertices" elements
};

// Reads the header from `in` (from its first line to end_header). O(header size).
ply_header_check check_ply_header(std::istream& in, ply_use use);

}  // namespace datasets
