// CGAL for triangle meshes: loading mesh files (harness/mesh_loading.hpp) and the
// AABB_tree ray caster (harness/ray_adapters.hpp). One translation unit for both, because
// every CGAL header costs seconds of compile time and brings -frounding-math with it.

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "datasets/ply_check.hpp"
#include "datasets/point_set_io.hpp"
#include "harness/mesh_loading.hpp"
#include "harness/ray_adapters.hpp"

namespace harness {
namespace {

using kernel = CGAL::Simple_cartesian<double>;  // reading files: plain coordinates suffice
// The AABB tree: exact predicates make CGAL's ray/triangle test watertight (with
// Simple_cartesian<double>, rays aimed at shared vertices of a closed mesh slipped through).
using aabb_kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

// ---------------------------------------------------------------------------------------
// Mesh files

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& what) {
    throw mesh_load_error(file.string() + ": " + what);
}

// CGAL's readers explain a failure only on std::cerr / std::cout (with the verbose
// parameter; they also chat there on success). Both are captured for the exception message
// instead of being printed. Not thread-safe (the streams are global); the harness does not
// load concurrently.
class capture_console {
public:
    capture_console() : old_err_(std::cerr.rdbuf(buffer_.rdbuf())), old_out_(std::cout.rdbuf(buffer_.rdbuf())) {}
    ~capture_console() {
        std::cerr.rdbuf(old_err_);
        std::cout.rdbuf(old_out_);
    }
    capture_console(const capture_console&) = delete;
    capture_console& operator=(const capture_console&) = delete;
    std::string text() const {
        std::string s = buffer_.str();
        while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
        for (char& c : s)
            if (c == '\n') c = ';';
        return s;
    }

private:
    std::ostringstream buffer_;
    std::streambuf* old_err_;
    std::streambuf* old_out_;
};

std::string lower_extension(const std::filesystem::path& file) {
    std::string ext = file.extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

}  // namespace

datasets::triangle_mesh load_triangle_mesh(const std::filesystem::path& file) {
    std::error_code ec;
    if (std::filesystem::is_directory(file, ec)) fail(file, "is a directory, not a mesh file");
    if (!std::ifstream(file, std::ios::binary)) fail(file, "cannot open the file (missing or unreadable)");
    const std::string ext = lower_extension(file);
    if (ext == ".ply") {  // CGAL's PLY reader crashes on some headers, trusts list counts (datasets/ply_check.hpp)
        std::ifstream in(file, std::ios::binary);
        const auto checked = datasets::check_ply(in, datasets::ply_use::mesh);
        if (!checked.problem.empty())
            fail(file, (checked.line ? "line " + std::to_string(checked.line) + ": " : std::string()) + checked.problem);
    }
    if (ext == ".off") {  // CGAL's OFF scanner takes a negative face size for a huge one (point_set_io.hpp)
        try {
            datasets::check_off_faces(file);
        } catch (const datasets::load_error& e) {
            throw mesh_load_error(e.what());  // it names the file already
        }
    }

    std::vector<kernel::Point_3> points;
    std::vector<std::vector<std::size_t>> polygons;
    bool ok = false;
    std::string diagnostics;
    {
        capture_console capture;
        const auto np = CGAL::parameters::verbose(true);
        const std::string name = file.string();
        try {
            // The readers CGAL::IO::read_polygon_soup dispatches to; dispatched here so that
            // upper-case extensions work too.
            if (ext == ".off") ok = CGAL::IO::read_OFF(name, points, polygons, np);
            else if (ext == ".ply") ok = CGAL::IO::read_PLY(name, points, polygons, np);
            else if (ext == ".obj") ok = CGAL::IO::read_OBJ(name, points, polygons, np);
            else if (ext == ".stl") ok = CGAL::IO::read_STL(name, points, polygons, np);
            else {
                std::string message = "unknown mesh extension \"" + file.extension().string() + "\"; supported:";
                for (auto e : supported_mesh_extensions()) message += " " + std::string(e);
                fail(file, message);
            }
        } catch (const mesh_load_error&) {
            throw;
        } catch (const std::exception& e) {
            ok = false;
            diagnostics = e.what();
        }
        if (diagnostics.empty()) diagnostics = capture.text();
        if (diagnostics.size() > 400) diagnostics = diagnostics.substr(0, 400) + "...";
    }
    if (!ok)
        fail(file, "CGAL's " + ext.substr(1) + " reader failed (malformed or truncated file)" +
                       (diagnostics.empty() ? std::string() : ": " + diagnostics));

    datasets::triangle_mesh mesh;
    mesh.vertices.reserve(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        const auto& p = points[i];
        if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z()))
            fail(file, "vertex " + std::to_string(i) + " has a non-finite coordinate");
        mesh.vertices.push_back({{p.x(), p.y(), p.z()}});
    }
    if (points.size() > std::numeric_limits<std::uint32_t>::max())
        fail(file, "more than 2^32 - 1 vertices are not supported");
    for (std::size_t f = 0; f < polygons.size(); ++f) {
        const auto& poly = polygons[f];
        if (poly.size() < 3)
            fail(file, "face " + std::to_string(f) + " has " + std::to_string(poly.size()) +
                           " vertices; a face needs at least 3");
        for (std::size_t v : poly)
            if (v >= points.size())
                fail(file, "face " + std::to_string(f) + " uses vertex " + std::to_string(v) + " but the file has " +
                               std::to_string(points.size()) + " vertices");
        // Fan triangulation from the first vertex: exact for convex polygons.
        for (std::size_t k = 1; k + 1 < poly.size(); ++k)
            mesh.triangles.push_back({static_cast<std::uint32_t>(poly[0]), static_cast<std::uint32_t>(poly[k]),
                                      static_cast<std::uint32_t>(poly[k + 1])});
    }
    if (mesh.triangles.empty()) fail(file, "has no faces (a point set, not a mesh?)");
    return mesh;
}

// ---------------------------------------------------------------------------------------
// AABB_tree ray caster (Epick: exact predicates, so the ray/triangle test is watertight)

namespace {

template <class T>
class cgal_aabb_tree_ray_index final : public ray_index<T> {
    using triangle_list = std::vector<aabb_kernel::Triangle_3>;
    using primitive = CGAL::AABB_triangle_primitive<aabb_kernel, typename triangle_list::const_iterator>;
    using traits = CGAL::AABB_traits<aabb_kernel, primitive>;
    using tree_type = CGAL::AABB_tree<traits>;

public:
    using typename ray_index<T>::point_type;
    using typename ray_index<T>::triangle_type;

    std::string name() const override { return "cgal_aabb_tree"; }

    void build(const datasets::triangle_mesh&, std::span<const triangle_type> triangles) override {
        tree_.clear();
        triangles_.clear();
        original_index_.clear();
        triangles_.reserve(triangles.size());
        for (std::size_t i = 0; i < triangles.size(); ++i) {
            const auto& t = triangles[i];
            aabb_kernel::Triangle_3 k(point(t.vertex(0)), point(t.vertex(1)), point(t.vertex(2)));
            // A zero-area triangle is never hit by the watertight test the other structures
            // use (its determinant is 0), and CGAL's predicates assume non-degenerate input.
            if (k.is_degenerate()) continue;
            triangles_.push_back(k);
            original_index_.push_back(static_cast<std::uint32_t>(i));
        }
        size_ = triangles.size();
        if (triangles_.empty()) return;
        tree_.insert(triangles_.cbegin(), triangles_.cend());
        tree_.build();
    }
    std::size_t size() const override { return size_; }
    std::size_t memory_bytes() const override {
        const std::size_t n = triangles_.size();
        const std::size_t node_bytes = sizeof(CGAL::Bbox_3) + 2 * sizeof(void*);
        return sizeof(*this) + triangles_.capacity() * sizeof(aabb_kernel::Triangle_3) +
               original_index_.capacity() * sizeof(std::uint32_t) + n * sizeof(primitive) +
               (n > 0 ? n - 1 : 0) * node_bytes;
    }

    bool intersect(const point_type& origin, const point_type& direction, T t_max, ray_hit<T>& hit) override {
        if (triangles_.empty()) return false;
        const aabb_kernel::Point_3 o = point(origin);
        const aabb_kernel::Vector_3 d(static_cast<double>(direction[0]), static_cast<double>(direction[1]),
                                 static_cast<double>(direction[2]));
        const auto result = tree_.first_intersection(aabb_kernel::Ray_3(o, d));
        if (!result) return false;
        aabb_kernel::Point_3 p;
        if (const auto* q = boost::get<aabb_kernel::Point_3>(&result->first)) {
            p = *q;
        } else if (const auto* s = boost::get<aabb_kernel::Segment_3>(&result->first)) {
            // The ray lies in the triangle's plane: its first point on the triangle.
            p = CGAL::squared_distance(o, s->source()) <= CGAL::squared_distance(o, s->target()) ? s->source()
                                                                                                 : s->target();
        } else {
            return false;
        }
        const double t = ((p - o) * d) / d.squared_length();
        if (!(static_cast<T>(t) < t_max)) return false;
        hit.t = static_cast<T>(t);
        hit.triangle = original_index_[static_cast<std::size_t>(result->second - triangles_.cbegin())];
        return true;
    }

    bool occluded(const point_type& origin, const point_type& direction, T t_max) override {
        if (triangles_.empty()) return false;
        const aabb_kernel::Point_3 o = point(origin);
        const aabb_kernel::Vector_3 d(static_cast<double>(direction[0]), static_cast<double>(direction[1]),
                                 static_cast<double>(direction[2]));
        if (std::isinf(t_max)) return tree_.do_intersect(aabb_kernel::Ray_3(o, d));
        return tree_.do_intersect(aabb_kernel::Segment_3(o, o + static_cast<double>(t_max) * d));
    }

private:
    static aabb_kernel::Point_3 point(const point_type& p) {
        return {static_cast<double>(p[0]), static_cast<double>(p[1]), static_cast<double>(p[2])};
    }

    triangle_list triangles_;
    std::vector<std::uint32_t> original_index_;  // tree triangle -> mesh triangle
    tree_type tree_;
    std::size_t size_ = 0;
};

}  // namespace

template <class T>
std::unique_ptr<ray_index<T>> make_cgal_aabb_tree_ray_index() {
    return std::make_unique<cgal_aabb_tree_ray_index<T>>();
}

template std::unique_ptr<ray_index<float>> make_cgal_aabb_tree_ray_index<float>();
template std::unique_ptr<ray_index<double>> make_cgal_aabb_tree_ray_index<double>();

}  // namespace harness
