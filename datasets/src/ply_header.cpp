// The PLY header check (datasets/ply_header.hpp): the header parsed into elements and their
// properties as CGAL 5.5's PLY_reader::init parses it, then the rules CGAL's readers need.

#include "datasets/ply_header.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <limits>
#include <span>
#include <sstream>
#include <string_view>
#include <system_error>
#include <vector>

namespace datasets {
namespace {

// The types CGAL's reader knows (TRY_TO_GENERATE_PROPERTY in CGAL/IO/PLY/PLY_reader.h); a list's
// count type must be one of the integer ones.
constexpr std::array<std::string_view, 16> scalar_types{"char",  "int8",   "uchar", "uint8",  "short",   "int16",
                                                        "ushort", "uint16", "int",   "int32",  "uint",    "uint32",
                                                        "float", "float32", "double", "float64"};
constexpr std::size_t integer_type_count = 12;  // the first 12 above
constexpr std::size_t max_header_lines = 10000;  // real headers are a few dozen lines

bool one_of(std::string_view word, std::span<const std::string_view> words) {
    return std::find(words.begin(), words.end(), word) != words.end();
}
bool is_coordinate_type(std::string_view t) { return t == "float" || t == "float32" || t == "double" || t == "float64"; }

struct property {
    std::string name;
    std::string type;  // "list" for a list
    std::size_t line;
    bool is(std::string_view scalar_a, std::string_view scalar_b) const { return type == scalar_a || type == scalar_b; }
};
struct element {
    std::string name;
    std::uint64_t count;
    std::size_t line;
    std::vector<property> properties;

    // CGAL looks a property up by name and takes the first one.
    const property* first(std::string_view property_name) const {
        for (const auto& p : properties)
            if (p.name == property_name) return &p;
        return nullptr;
    }
    bool named(std::string_view a, std::string_view b) const { return name == a || name == b; }
};

ply_header_check problem_at(std::size_t line, std::string what) { return {std::move(what), line, 0}; }

std::string type_list() {
    std::string s;
    for (auto t : scalar_types) s += (s.empty() ? "" : ", ") + std::string(t);
    return s;
}

// "property <type> <name>" or "property list <count type> <item type> <name>", after the keyword.
ply_header_check read_property(std::istringstream& words, std::size_t line, element& owner) {
    std::string type, name;
    if (!(words >> type >> name))
        return problem_at(line, "expected \"property <type> <name>\" or \"property list <count type> <type> <name>\"");
    if (type == "list") {
        const std::string count_type = name;
        std::string item_type;
        if (!(words >> item_type >> name)) return problem_at(line, "expected \"property list <count type> <type> <name>\"");
        if (!one_of(count_type, std::span(scalar_types).first(integer_type_count)) || !one_of(item_type, scalar_types))
            return problem_at(line, "unknown list types \"" + count_type + " " + item_type +
                                        "\" (counts: an integer type; items: " + type_list() + ")");
    } else if (!one_of(type, scalar_types)) {
        return problem_at(line, "unknown property type \"" + type + "\" (PLY types: " + type_list() + ")");
    }
    owner.properties.push_back({name, type, line});
    return {};
}

// The elements of the header, up to end_header; a problem if it is malformed.
ply_header_check read_elements(std::istream& in, std::vector<element>& elements) {
    std::string text, magic, tag, format, version;
    if (!std::getline(in, text) || !(std::istringstream(text) >> magic) || magic != "ply")
        return problem_at(1, "expected the PLY magic line \"ply\"");
    if (!std::getline(in, text) || !(std::istringstream(text) >> tag >> format >> version) || tag != "format" ||
        !(format == "ascii" || format == "binary_little_endian" || format == "binary_big_endian"))
        return problem_at(2, "expected \"format ascii|binary_little_endian|binary_big_endian <version>\"");
    for (std::size_t line = 3; line <= max_header_lines && std::getline(in, text); ++line) {
        std::istringstream words(text);
        std::string keyword;
        if (!(words >> keyword)) continue;
        if (keyword == "end_header") return {};
        if (keyword == "element") {
            std::string name, count;
            words >> name >> count;
            std::uint64_t n = 0;
            const auto [end, ec] = std::from_chars(count.data(), count.data() + count.size(), n);
            if (count.empty() || ec != std::errc{} || end != count.data() + count.size())
                return problem_at(line, "expected \"element <name> <count>\" but found \"" + text + "\"");
            elements.push_back({name, n, line, {}});
        } else if (keyword == "property") {
            if (elements.empty()) return problem_at(line, "a property line before any element line");
            if (auto p = read_property(words, line, elements.back()); !p.problem.empty()) return p;
        }  // comment, obj_info and unknown keywords: skipped, as CGAL does
    }
    return problem_at(0, "the PLY header has no end_header line");
}

// Every vertex element has x, y and z of type float or double; their counts summed.
ply_header_check check_vertices(const std::vector<element>& elements) {
    ply_header_check result;
    bool any = false;
    for (const auto& e : elements) {
        if (!e.named("vertex", "vertices")) continue;
        any = true;
        for (const char* axis : {"x", "y", "z"}) {
            const property* p = e.first(axis);
            if (!p)
                return problem_at(e.line, std::string("the PLY vertex element has no property ") + axis +
                                              " (x, y and z are required)");
            if (!is_coordinate_type(p->type))
                return problem_at(p->line, std::string("property ") + axis + " of the vertex element is " + p->type +
                                               "; CGAL's reader needs float or double coordinates");
        }
        result.vertex_count = std::min(result.vertex_count, std::numeric_limits<std::uint64_t>::max() - e.count) + e.count;
    }
    if (!any) return problem_at(0, "the PLY header declares no vertex element");
    return result;
}

// Meshes: the colours of vertices and faces as CGAL's polygon-soup reader picks them (red or r,
// green or g, blue or b, each uchar), and a halfedge element's source and target (uint).
ply_header_check check_mesh_properties(const std::vector<element>& elements) {
    for (const auto& e : elements) {
        if (e.name == "halfedge") {
            for (const char* name : {"source", "target"})
                if (const property* p = e.first(name); p && !p->is("uint", "uint32"))
                    return problem_at(p->line, std::string("property ") + name + " of the halfedge element is " + p->type +
                                                   "; CGAL's reader needs uint");
        }
        if (!e.named("vertex", "vertices") && !e.named("face", "faces")) continue;
        const auto uchar = [&](const char* name) {
            const property* p = e.first(name);
            return p && p->is("uchar", "uint8");
        };
        const bool has_colours = (uchar("red") || uchar("r")) && (uchar("green") || uchar("g")) && (uchar("blue") || uchar("b"));
        if (!has_colours) continue;  // CGAL reads no colour
        for (const char* name : uchar("red") ? std::array{"red", "green", "blue"} : std::array{"r", "g", "b"})
            if (const property* p = e.first(name); p && !p->is("uchar", "uint8"))
                return problem_at(p->line, std::string("colour property ") + name + " of the " + e.name + " element is " +
                                               p->type + " while the others are uchar; CGAL's reader needs all three uchar");
    }
    return {};
}

}  // namespace

ply_header_check check_ply_header(std::istream& in, ply_use use) {
    std::vector<element> elements;
    if (auto r = read_elements(in, elements); !r.problem.empty()) return r;
    ply_header_check result = check_vertices(elements);
    if (!result.problem.empty() || use == ply_use::points) return result;
    if (auto r = check_mesh_properties(elements); !r.problem.empty()) return r;
    return result;
}

}  // namespace datasets
