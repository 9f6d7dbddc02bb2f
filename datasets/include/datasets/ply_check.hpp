#pragma once
// datasets::check_ply — a PLY file checked for what CGAL 5.5's PLY reader
// (CGAL::IO::internal::PLY_reader, behind CGAL::IO::read_PLY for point sets and for polygon
// soups) needs, before the file is handed to it: its header (check_ply_header), then the sizes
// its body declares. The point-set loader (point_set_io.hpp) and the mesh loader
// (harness/mesh_loading.hpp) both call it.
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
//
// The body: CGAL resizes a list to its declared count before reading the items
// (PLY_read_typed_list_with_typed_size::get), so a file of a few hundred bytes whose list
// declares 2^31 - 1 items made it allocate 8 GB (found by fuzzing). check_ply walks the body
// without storing it — binary: the byte size of each row, each list count against the bytes
// left; ASCII: each value a word, each list count a non-negative integer followed by that many
// words — and names the element, row and property (and the line, in ASCII) where the file is
// too short or a count is negative.

#include <cstddef>
#include <cstdint>
#include <istream>
#include <string>

namespace datasets {

enum class ply_use {
    points,  // read_PLY into points: the vertex elements only
    mesh,    // read_PLY into a polygon soup: also the colours of vertices and faces
};

struct ply_check_result {
    std::string problem;             // empty when the file is fit for CGAL's reader
    std::size_t line = 0;            // the line of the problem; 0 when it concerns the whole header or a binary body
    std::uint64_t vertex_count = 0;  // declared vertices: the sum over the "vertex" / "vertices" elements
};

// Reads the header from `in` (from its first line to end_header). O(header size).
ply_check_result check_ply_header(std::istream& in, ply_use use);

// The header, then the body up to the last declared element; `in` at the start of the file.
// O(file size) time, O(1) memory beyond the header. Data after the last element is ignored.
ply_check_result check_ply(std::istream& in, ply_use use);

}  // namespace datasets
