// The PLY check (datasets/ply_check.hpp): the header parsed into elements and their properties
// as CGAL 5.5's PLY_reader::init parses it, then the rules CGAL's readers need; then the body
// walked for the sizes it declares.

#include "datasets/ply_check.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <ios>
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
    std::string count_type = {}, item_type = {};  // a list's
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

ply_check_result problem_at(std::size_t line, std::string what) { return {std::move(what), line, 0}; }

std::string type_list() {
    std::string s;
    for (auto t : scalar_types) s += (s.empty() ? "" : ", ") + std::string(t);
    return s;
}

// "property <type> <name>" or "property list <count type> <item type> <name>", after the keyword.
ply_check_result read_property(std::istringstream& words, std::size_t line, element& owner) {
    std::string type, name, count_type, item_type;
    if (!(words >> type >> name))
        return problem_at(line, "expected \"property <type> <name>\" or \"property list <count type> <type> <name>\"");
    if (type == "list") {
        count_type = name;
        if (!(words >> item_type >> name)) return problem_at(line, "expected \"property list <count type> <type> <name>\"");
        if (!one_of(count_type, std::span(scalar_types).first(integer_type_count)) || !one_of(item_type, scalar_types))
            return problem_at(line, "unknown list types \"" + count_type + " " + item_type +
                                        "\" (counts: an integer type; items: " + type_list() + ")");
    } else if (!one_of(type, scalar_types)) {
        return problem_at(line, "unknown property type \"" + type + "\" (PLY types: " + type_list() + ")");
    }
    owner.properties.push_back({name, type, line, count_type, item_type});
    return {};
}

struct parsed_header {
    std::string format;
    std::vector<element> elements;
    std::size_t end_line = 0;  // the line of end_header
};

// The elements of the header, up to end_header; a problem if it is malformed.
ply_check_result read_elements(std::istream& in, parsed_header& header) {
    auto& [format, elements, end_line] = header;
    std::string text, magic, tag, version;
    if (!std::getline(in, text) || !(std::istringstream(text) >> magic) || magic != "ply")
        return problem_at(1, "expected the PLY magic line \"ply\"");
    if (!std::getline(in, text) || !(std::istringstream(text) >> tag >> format >> version) || tag != "format" ||
        !(format == "ascii" || format == "binary_little_endian" || format == "binary_big_endian"))
        return problem_at(2, "expected \"format ascii|binary_little_endian|binary_big_endian <version>\"");
    for (std::size_t line = 3; line <= max_header_lines && std::getline(in, text); ++line) {
        std::istringstream words(text);
        std::string keyword;
        if (!(words >> keyword)) continue;
        if (keyword == "end_header") {
            end_line = line;
            return {};
        }
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
ply_check_result check_vertices(const std::vector<element>& elements) {
    ply_check_result result;
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
ply_check_result check_mesh_properties(const std::vector<element>& elements) {
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


ply_check_result check_header(std::istream& in, ply_use use, parsed_header& header) {
    if (auto r = read_elements(in, header); !r.problem.empty()) return r;
    ply_check_result result = check_vertices(header.elements);
    if (!result.problem.empty() || use == ply_use::points) return result;
    if (auto r = check_mesh_properties(header.elements); !r.problem.empty()) return r;
    return result;
}

// "row 3 of element face, property vertex_indices"
std::string place(const element& e, std::uint64_t row, const property& p) {
    return "row " + std::to_string(row) + " of element " + e.name + ", property " + p.name;
}

std::size_t byte_size(std::string_view type) {
    const auto at = static_cast<std::size_t>(std::find(scalar_types.begin(), scalar_types.end(), type) - scalar_types.begin());
    constexpr std::array<std::size_t, 16> sizes{1, 1, 1, 1, 2, 2, 2, 2, 4, 4, 4, 4, 4, 4, 8, 8};
    return sizes[at];  // the header check has rejected unknown types
}
bool is_signed(std::string_view type) {
    return type == "char" || type == "int8" || type == "short" || type == "int16" || type == "int" || type == "int32";
}

// At the end of the file: no line to name (the row says where).
ply_check_result file_ends_in(const element& e, std::uint64_t row, const property& p) {
    return problem_at(0, "the file ends in " + place(e, row, p) + " (element " + e.name + " declares " +
                             std::to_string(e.count) + " rows)");
}

// Every value of an element, row by row: `value(row, property)` reads one (binary or ASCII)
// and returns a problem or nothing.
template <class ReadValue>
ply_check_result each_value(const element& e, ReadValue&& value) {
    for (std::uint64_t row = 0; row < e.count; ++row)
        for (const auto& p : e.properties)
            if (auto r = value(row, p); !r.problem.empty()) return r;
    return {};
}

// A binary body: rows of fixed-size scalars and lists (a count, then that many items). Skipped
// with istream::ignore, so the stream's buffer serves it and nothing is stored.
class binary_body {
public:
    binary_body(std::istream& in, bool big_endian) : in_(in), big_endian_(big_endian) {
        const auto start = in_.tellg();
        in_.seekg(0, std::ios::end);
        const auto end = in_.tellg();
        in_.seekg(start);
        left_ = start >= 0 && end >= start ? static_cast<std::uint64_t>(end - start) : 0;
    }

    ply_check_result walk(const std::vector<element>& elements) {
        for (const auto& e : elements) {
            std::uint64_t row_bytes = 0;
            bool has_list = false;
            for (const auto& p : e.properties) {
                if (p.type == "list") has_list = true;
                else row_bytes += byte_size(p.type);
            }
            if (e.properties.empty() || e.count == 0) continue;
            if (!has_list) {  // fixed rows: one comparison, one skip
                if (e.count > left_ / row_bytes)
                    return problem_at(0, "element " + e.name + " declares " + std::to_string(e.count) + " rows of " +
                                             std::to_string(row_bytes) + " bytes but " + std::to_string(left_) +
                                             " bytes follow (truncated file or a wrong count, line " +
                                             std::to_string(e.line) + ")");
                skip(e.count * row_bytes);
                continue;
            }
            const auto value = [&](std::uint64_t row, const property& p) { return property_value(e, row, p); };
            if (auto r = each_value(e, value); !r.problem.empty()) return r;
        }
        return {};
    }

private:
    ply_check_result property_value(const element& e, std::uint64_t row, const property& p) {
        if (p.type != "list") {
            const std::size_t n = byte_size(p.type);
            if (n > left_) return file_ends_in(e, row, p);
            skip(n);
            return {};
        }
        const std::size_t count_bytes = byte_size(p.count_type), item_bytes = byte_size(p.item_type);
        if (count_bytes > left_) return file_ends_in(e, row, p);
        std::array<unsigned char, 4> raw{};
        in_.read(reinterpret_cast<char*>(raw.data()), static_cast<std::streamsize>(count_bytes));
        left_ -= count_bytes;
        std::uint64_t count = 0;
        for (std::size_t i = 0; i < count_bytes; ++i)
            count = (count << 8) | raw[big_endian_ ? i : count_bytes - 1 - i];
        const bool negative = is_signed(p.count_type) && (raw[big_endian_ ? 0 : count_bytes - 1] & 0x80u);
        if (negative) return problem_at(0, place(e, row, p) + ": a negative list count");
        if (count > left_ / item_bytes)
            return problem_at(0, place(e, row, p) + ": the list declares " + std::to_string(count) + " items of " +
                                     std::to_string(item_bytes) + " bytes but " + std::to_string(left_) +
                                     " bytes follow");
        skip(count * item_bytes);
        return {};
    }

    void skip(std::uint64_t bytes) {
        left_ -= bytes;
        constexpr auto chunk = static_cast<std::uint64_t>(std::numeric_limits<std::streamsize>::max());
        for (; bytes > chunk; bytes -= chunk) in_.ignore(std::numeric_limits<std::streamsize>::max());
        in_.ignore(static_cast<std::streamsize>(bytes));
    }

    std::istream& in_;
    bool big_endian_;
    std::uint64_t left_;  // bytes between the reading position and the end of the file
};

// An ASCII body: every value is a word; a list is its count, then that many words. Words are
// read one at a time, counting lines so that a problem names its line.
class ascii_body {
public:
    // `line`: the line of end_header (the body starts on the next).
    ascii_body(std::istream& in, std::size_t line) : in_(in), line_(line + 1) {}

    ply_check_result walk(const std::vector<element>& elements) {
        for (const auto& e : elements) {
            if (e.properties.empty()) continue;
            const auto value = [&](std::uint64_t row, const property& p) { return property_value(e, row, p); };
            if (auto r = each_value(e, value); !r.problem.empty()) return r;
        }
        return {};
    }

private:
    ply_check_result property_value(const element& e, std::uint64_t row, const property& p) {
        if (!next_word()) return file_ends_in(e, row, p);
        if (p.type != "list") return {};
        std::int64_t count = 0;
        const auto [end, ec] = std::from_chars(word_.data(), word_.data() + word_.size(), count);
        if (ec != std::errc{} || end != word_.data() + word_.size())
            return problem_at(line_, place(e, row, p) + ": expected a list count but found \"" + word_.substr(0, 40) + "\"");
        if (count < 0) return problem_at(line_, place(e, row, p) + ": a negative list count " + word_);
        const std::size_t count_line = line_;
        for (std::int64_t i = 0; i < count; ++i)
            if (!next_word())
                return problem_at(count_line, place(e, row, p) + ": the list declares " + std::to_string(count) +
                                                  " items but the file ends after " + std::to_string(i));
        return {};
    }

    // The next whitespace-separated word into word_ (kept to 64 characters: a value longer than
    // that is not a count, and a word of the whole file must not be stored); false at the end.
    bool next_word() {
        word_.clear();
        auto* buffer = in_.rdbuf();
        int c = buffer->sgetc();
        for (; c != std::char_traits<char>::eof() && std::isspace(c); c = buffer->snextc())
            if (c == '\n') ++line_;
        for (; c != std::char_traits<char>::eof() && !std::isspace(c); c = buffer->snextc())
            if (word_.size() < 64) word_ += static_cast<char>(c);
        return !word_.empty();
    }

    std::istream& in_;
    std::string word_;
    std::size_t line_;  // the line of the reading position
};

}  // namespace

ply_check_result check_ply_header(std::istream& in, ply_use use) {
    parsed_header header;
    return check_header(in, use, header);
}

ply_check_result check_ply(std::istream& in, ply_use use) {
    parsed_header header;
    ply_check_result result = check_header(in, use, header);
    if (!result.problem.empty()) return result;
    ply_check_result body = header.format == "ascii"
                                ? ascii_body(in, header.end_line).walk(header.elements)
                                : binary_body(in, header.format == "binary_big_endian").walk(header.elements);
    return body.problem.empty() ? result : body;
}

}  // namespace datasets
