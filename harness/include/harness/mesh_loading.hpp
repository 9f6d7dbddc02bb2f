#pragma once
// Loading triangle meshes from files: OFF, PLY (ASCII and binary), OBJ and STL (ASCII and
// binary), through CGAL's readers (CGAL::IO::read_OFF / read_PLY / read_OBJ / read_STL, the
// readers behind CGAL::IO::read_polygon_soup, CGAL 5.5). They live in the CGAL adapter
// library (harness/adapters/cgal/cgal_triangle_meshes.cpp), so CGAL's headers and its
// -frounding-math stay in that one translation unit; callers only see this header.
//
// Polygons with more than 3 vertices are fan-triangulated from their first vertex (exact for
// the convex faces mesh files hold). Every failure throws harness::mesh_load_error whose
// message starts with the file name: missing or unreadable file, unknown extension, CGAL's
// reader reporting a malformed file (CGAL does not tell the line, so neither can we),
// no faces (a point set), a face with fewer than 3 vertices or an out-of-range index (named
// by face number), a non-finite coordinate (named by vertex number).

#include <filesystem>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

#include "datasets/triangle_mesh.hpp"

namespace harness {

class mesh_load_error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Lower-case extensions (with the dot) that load_triangle_mesh reads in this build; empty
// without CGAL.
inline std::span<const std::string_view> supported_mesh_extensions() noexcept {
#if defined(SPATIAL_HAVE_CGAL) && SPATIAL_HAVE_CGAL
    static constexpr std::string_view extensions[] = {".off", ".ply", ".obj", ".stl"};
    return extensions;
#else
    return {};
#endif
}

#if defined(SPATIAL_HAVE_CGAL) && SPATIAL_HAVE_CGAL
// The mesh in `file`, chosen by its extension (case-insensitive). O(file size).
datasets::triangle_mesh load_triangle_mesh(const std::filesystem::path& file);
#else
inline datasets::triangle_mesh load_triangle_mesh(const std::filesystem::path& file) {
    throw mesh_load_error(file.string() + ": loading meshes needs CGAL: configure with -DSPATIAL_WITH_CGAL=ON");
}
#endif

}  // namespace harness
