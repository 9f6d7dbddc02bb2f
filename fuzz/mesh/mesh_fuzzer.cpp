// Fuzz target: the mesh readers (harness/mesh_loading.hpp): OFF, PLY (ASCII and binary), OBJ
// and STL (ASCII and binary), CGAL's readers behind load_triangle_mesh, in the CGAL adapter's
// mesh library (spatial_adapter_cgal_meshes: one CGAL translation unit).
//
// Input: the first byte chooses the format (its extension; ASCII or binary is decided by the
// content, as in a real file), the rest is the file's content, written to a scratch file.
// Expected outcomes: a mesh, or harness::mesh_load_error (the one documented error type).
// Findings: a sanitizer report, a hang, another exception type (it escapes and aborts), or a
// mesh that breaks the documented promises: at least one triangle, every vertex finite, every
// triangle's indices inside the vertex list.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

#include "../common/finding.hpp"
#include "../common/scratch_file.hpp"
#include "harness/mesh_loading.hpp"

namespace {

constexpr std::string_view target = "mesh";
constexpr std::array<std::string_view, 4> extensions{".off", ".ply", ".obj", ".stl"};

void check_mesh(const datasets::triangle_mesh& mesh) {
    if (mesh.triangles.empty()) spatial_fuzz::finding(target, "load_triangle_mesh returned no triangle without an error");
    try {
        datasets::require_valid_mesh(mesh, "the loaded mesh");  // finite vertices, indices in range
    } catch (const std::invalid_argument& e) {
        spatial_fuzz::finding(target, std::string("load_triangle_mesh returned an invalid mesh: ") + e.what());
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    const std::string_view extension = extensions[data[0] % extensions.size()];
    const auto file = spatial_fuzz::scratch().write(extension, std::span(data + 1, size - 1));
    try {
        check_mesh(harness::load_triangle_mesh(file));
    } catch (const harness::mesh_load_error&) {
        // the documented answer to a malformed file
    }
    return 0;
}
