// Point-set loaders. The only translation unit of the project that includes CGAL (for PLY):
// CGAL headers compile slowly and its target adds -frounding-math, so they stay here, behind
// SPATIAL_DATASETS_HAVE_CGAL, and never reach a public header.

#include "datasets/point_set_io.hpp"
#include "datasets/ply_check.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <limits>
#include <optional>
#include <span>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#if defined(SPATIAL_DATASETS_HAVE_CGAL)
#include <CGAL/IO/read_ply_points.h>
#include <CGAL/Simple_cartesian.h>
#endif

namespace datasets {
namespace {

namespace fs = std::filesystem;
using point3 = spatial::point<double, 3>;

[[noreturn]] void fail(const fs::path& file, std::string_view what) {
    throw load_error(file.string() + ": " + std::string(what));
}

[[noreturn]] void fail_at(const fs::path& file, std::size_t line, std::string_view what) {
    throw load_error(file.string() + ": line " + std::to_string(line) + ": " + std::string(what));
}

// The whole file as bytes: one read is faster than line-by-line stream extraction, and the
// parsers below work on string_views into it.
std::string read_whole_file(const fs::path& file) {
    std::error_code ec;
    if (fs::is_directory(file, ec)) fail(file, "is a directory, not a point-set file");
    std::ifstream in(file, std::ios::binary);
    if (!in) fail(file, "cannot open the file (missing or unreadable)");
    std::ostringstream buffer;
    buffer << in.rdbuf();
    if (in.bad()) fail(file, "read error");
    return std::move(buffer).str();
}

// Yields the lines of a text one by one, numbered from 1, without their "\n" or "\r\n".
class line_reader {
public:
    explicit line_reader(std::string_view text) : text_(text) {}

    bool next(std::string_view& line) {
        if (pos_ >= text_.size()) return false;
        const std::size_t end = std::min(text_.find('\n', pos_), text_.size());
        line = text_.substr(pos_, end - pos_);
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        pos_ = end + 1;
        ++number_;
        return true;
    }
    std::size_t number() const { return number_; }

private:
    std::string_view text_;
    std::size_t pos_ = 0;
    std::size_t number_ = 0;
};

bool is_separator(char c) {
    // Commas are accepted too: some tools write "x, y, z".
    return c == ' ' || c == '\t' || c == ',' || c == '\v' || c == '\f';
}

// Whitespace/comma separated tokens of one line.
class token_reader {
public:
    explicit token_reader(std::string_view line) : rest_(line) {}

    bool next(std::string_view& token) {
        std::size_t i = 0;
        while (i < rest_.size() && is_separator(rest_[i])) ++i;
        if (i == rest_.size()) return false;
        std::size_t j = i;
        while (j < rest_.size() && !is_separator(rest_[j])) ++j;
        token = rest_.substr(i, j - i);
        rest_.remove_prefix(j);
        return true;
    }

private:
    std::string_view rest_;
};

std::string_view strip_comment(std::string_view line) {
    const std::size_t hash = line.find('#');
    return hash == std::string_view::npos ? line : line.substr(0, hash);
}

bool is_blank(std::string_view line) {
    return std::all_of(line.begin(), line.end(),
                       [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; });
}

std::string quote_token(std::string_view token) {
    constexpr std::size_t max_shown = 40;
    std::string s = "\"" + std::string(token.substr(0, max_shown));
    return s + (token.size() > max_shown ? "...\"" : "\"");
}

// Locale-independent: std::from_chars ignores the C locale's decimal separator.
std::optional<double> parse_double(std::string_view token) {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    double value = 0.0;
    const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (ec != std::errc{} || ptr != token.data() + token.size()) return std::nullopt;
    return value;
}

std::optional<std::uint64_t> parse_count(std::string_view token) {
    std::uint64_t value = 0;
    const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (ec != std::errc{} || ptr != token.data() + token.size()) return std::nullopt;
    return value;
}

// Reads x, y, z from the next three tokens of `tokens`; what follows on the line is ignored.
point3 parse_xyz(token_reader& tokens, const fs::path& file, std::size_t line_number,
                 std::string_view line_kind) {
    static constexpr std::array<const char*, 3> axis_name{"x", "y", "z"};
    point3 p;
    for (std::size_t d = 0; d < 3; ++d) {
        std::string_view token;
        if (!tokens.next(token)) {
            fail_at(file, line_number,
                    "expected at least 3 numbers (x y z) on " + std::string(line_kind) +
                        " but found " + std::to_string(d));
        }
        const std::optional<double> value = parse_double(token);
        if (!value) {
            fail_at(file, line_number,
                    "expected a number for " + std::string(axis_name[d]) + " on " +
                        std::string(line_kind) + " but found " + quote_token(token));
        }
        if (!std::isfinite(*value)) {
            fail_at(file, line_number,
                    std::string(axis_name[d]) + " = " + std::string(token) +
                        " is not finite (NaN and infinite coordinates are rejected)");
        }
        p[d] = *value;
    }
    return p;
}

// .xyz/.xyzn/.pwn: "x y z [extra columns]" per line. A first data line holding a single
// integer is taken as a point-count header (some tools write one) and skipped.
std::vector<point3> parse_xyz_text(std::string_view text, const fs::path& file) {
    std::vector<point3> points;
    line_reader lines(text);
    std::string_view line;
    bool first_data_line = true;
    while (lines.next(line)) {
        if (is_blank(line)) continue;
        const std::size_t start = line.find_first_not_of(" \t");
        if (line[start] == '#') continue;
        if (first_data_line) {
            first_data_line = false;
            token_reader probe(line);
            std::string_view first, second;
            if (probe.next(first) && !probe.next(second) && parse_count(first)) continue;
        }
        token_reader tokens(line);
        points.push_back(parse_xyz(tokens, file, lines.number(), "a point line"));
    }
    return points;
}

// .off: our own reader rather than CGAL's, because we only want the vertices and (1) it
// reports the line of a bad vertex, (2) it works in builds without CGAL, (3) it does not
// reject meshes that are non-manifold or have broken faces, which CGAL's Surface_mesh
// reader refuses although their vertices are a perfectly good point set.
// Accepts the ASCII header keywords [ST][C][N]OFF (extra per-vertex columns ignored) and
// headerless files that start with the counts; rejects 4OFF, nOFF and binary OFF by name.
enum class off_faces { ignore, check };

// A mesh's colour (COFF), a vertex's or a face's: CGAL's OFF scanner converts it to bytes
// without range checks. One number is an index into its colour map, converted to int and
// clamped above only (a negative index read before its table). Three or four are red, green,
// blue (alpha ignored): whole numbers are converted to unsigned char as they are, otherwise each
// is multiplied by 255 first; a value outside the byte is undefined behaviour either way.
void check_off_colour(std::span<const double> colour, const std::string& what, const fs::path& file,
                      std::size_t line_number) {
    if (colour.empty()) return;
    if (colour.size() == 1) {
        if (!(colour[0] >= 0.0 && colour[0] < 2147483648.0))
            fail_at(file, line_number, what + " has colour map index " + std::to_string(colour[0]) +
                                           "; an index is a number from 0 to 2^31 - 1");
        return;
    }
    const auto rgb = colour.first(3);
    const bool bytes = std::all_of(rgb.begin(), rgb.end(), [](double c) { return c == std::floor(c) && c >= 0.0 && c <= 255.0; });
    const bool fractions = std::all_of(rgb.begin(), rgb.end(), [](double c) { return c >= 0.0 && c <= 1.0; });
    if (!bytes && !fractions)
        fail_at(file, line_number, what + " has colour (" + std::to_string(rgb[0]) + ", " + std::to_string(rgb[1]) + ", " +
                                       std::to_string(rgb[2]) + "): red, green and blue are whole numbers from 0 to 255, "
                                       "or all three from 0 to 1");
}

// The finite numbers of a line's tokens from `tokens` on, or a named failure.
std::vector<double> finite_columns(token_reader tokens, const std::string& what, const fs::path& file, std::size_t line_number) {
    std::vector<double> columns;
    std::string_view column;
    while (tokens.next(column)) {
        const std::optional<double> value = parse_double(column);
        if (!value || !std::isfinite(*value))
            fail_at(file, line_number, what + " has a column that is not a finite number: " + quote_token(column));
        columns.push_back(*value);
    }
    return columns;
}

// 0, 1 (a colour map index), 3 or 4 colour numbers, as many as on the first line of their kind
// (the scanner keeps a line's "has colours" for the lines after it), in range.
void check_off_colour_columns(std::span<const double> colour, std::optional<std::size_t>& first_colours,
                              const std::string& what, const fs::path& file, std::size_t line_number) {
    const std::size_t n = colour.size();
    if (n != 0 && n != 1 && n != 3 && n != 4)
        fail_at(file, line_number, what + " has " + std::to_string(n) + " colour numbers; expected 0, 1 (a colour map index), 3 or 4");
    if (!first_colours) first_colours = n;
    if (n != *first_colours)
        fail_at(file, line_number, what + " has " + std::to_string(n) + " colour numbers but the first has " +
                                       std::to_string(*first_colours));
    check_off_colour(colour, what, file, line_number);
}

// A mesh's vertex line, for CGAL's OFF scanner (File_scanner_OFF.h), which counts the line's
// leading numbers and indexes them without bounds checks: after the 3 coordinates, 3 normal
// components (N), 2 texture coordinates (ST) and, with C, 0, 1 (a colour map index), 3 or 4
// colour components. Any other count made it read past its vector ("STCOFF" with a
// three-number vertex line: found by fuzzing, docs/fuzzing.md). It keeps a line's "has
// colours" for the lines after it, so every line must have the same colour count
// (`first_colours`: the first line's). Every column must be a finite number, so that its
// count and ours agree (it stops at the first one it cannot read).
void check_off_vertex_columns(std::string_view vertex_line, std::string_view variant, const fs::path& file,
                              std::size_t line_number, std::optional<std::size_t>& first_colours) {
    const std::vector<double> columns = finite_columns(token_reader(vertex_line), "a vertex line", file, line_number);
    const std::size_t count = columns.size();
    const bool normals = variant.find('N') != std::string_view::npos, colours = variant.find('C') != std::string_view::npos,
               textures = variant.starts_with("ST");
    const std::size_t fixed = 3 + (normals ? 3 : 0) + (textures ? 2 : 0);
    const std::string keyword = std::string(variant) + "OFF";
    if (count < fixed)
        fail_at(file, line_number, "a vertex line of " + keyword + " needs " + std::to_string(fixed) +
                                       " numbers (coordinates" + (normals ? ", normal" : "") +
                                       (textures ? ", texture" : "") + ") but has " + std::to_string(count));
    if (!colours) return;
    // The colour columns follow the coordinates and the normal; the texture coordinates come last.
    const std::size_t first_colour = 3 + (normals ? 3 : 0);
    check_off_colour_columns(std::span(columns).subspan(first_colour, count - fixed), first_colours,
                             "a vertex line of " + keyword, file, line_number);
}

// A mesh's counts line, after its vertex and face counts: the edge count, then nothing. CGAL's
// OFF header reader takes "vertices faces edges" as three numbers of a stream, not a line: with
// the edge count missing it takes the first vertex's first number for it, and whatever follows
// the edge count on its line becomes the first vertex line. Either way every line after it is
// read one line off from ours, and a line we checked as a vertex reached its face scanner as a
// face ("-1 0 0": a negative face size converted to std::size_t, UBSan; found by fuzzing,
// docs/fuzzing.md). It reads the counts as int, so the vertex and face counts must fit one.
void check_mesh_counts(std::uint64_t vertex_count, std::uint64_t face_count, token_reader rest, const fs::path& file,
                       std::size_t line_number) {
    constexpr auto int_max = static_cast<std::uint64_t>(std::numeric_limits<int>::max());
    if (vertex_count > int_max || face_count > int_max)
        fail_at(file, line_number, "a mesh's OFF vertex and face counts must be below 2^31 (CGAL's OFF reader reads them as int)");
    std::string_view edges, extra;
    if (!rest.next(edges))
        fail_at(file, line_number, "a mesh's OFF counts line needs three numbers, \"vertices faces edges\", "
                                   "on one line; the edge count is missing");
    const std::optional<std::uint64_t> edge_count = parse_count(edges);
    if (!edge_count || *edge_count > int_max)
        fail_at(file, line_number, "expected the edge count (a whole number below 2^31) after the face count but found " +
                                       quote_token(edges));
    if (rest.next(extra))
        fail_at(file, line_number, "a mesh's OFF counts line holds \"vertices faces edges\" and nothing else, but " +
                                       quote_token(extra) + " follows the edge count");
}

// Faces (when asked): each face's line starts with its vertex count, a non-negative integer
// followed by at least that many indices, none negative, on the same line, as CGAL's OFF scanner (which reads a
// face and skips the rest of its line, colours included) needs them: it converts a negative
// count to std::size_t (undefined behaviour) and reserves a count's worth of indices.
std::vector<point3> parse_off_text(std::string_view text, const fs::path& file, off_faces faces = off_faces::ignore) {
    line_reader lines(text);
    std::string_view raw;
    // Next line with content, comments removed; false at end of file. A mesh's numbers are
    // separated by white space only: CGAL's OFF reader stops a line at a comma, and its
    // scanner then indexed colour columns past the numbers it had read (a COFF vertex
    // line "0,0,0": ASan heap-buffer-overflow in scan_color; docs/fuzzing.md).
    const auto next_content_line = [&](std::string_view& content) {
        while (lines.next(raw)) {
            content = strip_comment(raw);
            if (is_blank(content)) continue;
            if (faces == off_faces::check && content.find(',') != std::string_view::npos)
                fail_at(file, lines.number(), "a mesh's OFF numbers are separated by spaces, not commas "
                                              "(CGAL's OFF reader does not read a comma)");
            return true;
        }
        return false;
    };

    std::string_view header;
    if (!next_content_line(header)) fail(file, "contains no points (empty OFF file)");
    token_reader header_tokens(header);
    std::string_view token;
    header_tokens.next(token);
    std::optional<std::uint64_t> vertex_count;
    std::string_view face_count_token;  // the word after the vertex count
    std::string_view variant;           // the header keyword's prefix: "", "N", "C", ..., "STCN"
    token_reader counts_rest{{}};       // the counts line after the face count
    if (parse_count(token)) {
        vertex_count = parse_count(token);  // headerless: the counts come first
        header_tokens.next(face_count_token);
    } else {
        const bool ends_with_off = token.size() >= 3 && token.substr(token.size() - 3) == "OFF";
        const std::string_view prefix = ends_with_off ? token.substr(0, token.size() - 3) : token;
        static constexpr std::array<std::string_view, 8> supported_prefixes{
            "", "N", "C", "CN", "ST", "STN", "STC", "STCN"};
        if (!ends_with_off) {
            fail_at(file, lines.number(), "expected the OFF header keyword but found " + quote_token(token));
        }
        if (std::find(supported_prefixes.begin(), supported_prefixes.end(), prefix) ==
            supported_prefixes.end()) {
            fail_at(file, lines.number(),
                    "unsupported OFF variant " + quote_token(token) +
                        " (supported: [ST][C][N]OFF with 3D vertices)");
        }
        variant = prefix;
        std::string_view counts_token;
        if (header_tokens.next(counts_token)) {
            if (counts_token == "BINARY") {
                fail_at(file, lines.number(), "binary OFF is not supported; convert it to ASCII");
            }
            vertex_count = parse_count(counts_token);
            if (!vertex_count) {
                fail_at(file, lines.number(),
                        "expected the vertex count after " + quote_token(token) + " but found " +
                            quote_token(counts_token));
            }
            header_tokens.next(face_count_token);
            counts_rest = header_tokens;
        }
    }
    if (!vertex_count) {
        std::string_view counts;
        if (!next_content_line(counts)) {
            fail(file, "ends after the OFF keyword; expected the line \"vertices faces edges\"");
        }
        token_reader count_tokens(counts);
        count_tokens.next(token);
        vertex_count = parse_count(token);
        if (!vertex_count) {
            fail_at(file, lines.number(),
                    "expected the vertex count (\"vertices faces edges\") but found " + quote_token(token));
        }
        count_tokens.next(face_count_token);
        counts_rest = count_tokens;
    }
    const std::size_t counts_line = lines.number();
    if (*vertex_count == 0) fail(file, "contains no points (the OFF header declares 0 vertices)");
    const std::optional<std::uint64_t> face_count = parse_count(face_count_token);
    if (faces == off_faces::check) {
        if (!face_count)
            fail_at(file, counts_line, "expected the face count after the vertex count but found " + quote_token(face_count_token));
        check_mesh_counts(*vertex_count, *face_count, counts_rest, file, counts_line);
    }

    std::vector<point3> points;
    // A lying header must not allocate terabytes: a vertex line needs at least 6 bytes.
    points.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(*vertex_count, text.size() / 6)));
    // A mesh's texture coordinates without colours: CGAL's scanner reads them at a column index
    // it only sets for colour files (uninitialised otherwise).
    if (faces == off_faces::check && variant.starts_with("ST") && variant.find('C') == std::string_view::npos)
        fail(file, std::string(variant) + "OFF (texture coordinates without colours) is not supported for meshes: "
                   "CGAL's OFF reader cannot read it; drop the texture columns and the ST, or add colours (STCOFF)");
    std::optional<std::size_t> first_colours;  // a mesh's colour columns per vertex line (COFF)
    std::string_view vertex_line;
    while (points.size() < *vertex_count) {
        if (!next_content_line(vertex_line)) {
            fail(file, "the OFF header declares " + std::to_string(*vertex_count) +
                           " vertices but the file ends after " + std::to_string(points.size()) +
                           " (at line " + std::to_string(lines.number()) + ")");
        }
        token_reader tokens(vertex_line);
        points.push_back(parse_xyz(tokens, file, lines.number(), "a vertex line"));
        if (faces == off_faces::check) check_off_vertex_columns(vertex_line, variant, file, lines.number(), first_colours);
    }
    if (faces == off_faces::ignore) return points;

    const bool colours = variant.find('C') != std::string_view::npos;
    std::optional<std::size_t> first_face_colours;  // a mesh's colour columns per face line (COFF)
    std::string_view face_line;
    for (std::uint64_t f = 0; f < *face_count; ++f) {
        if (!next_content_line(face_line))
            fail(file, "the OFF header declares " + std::to_string(*face_count) + " faces but the file ends after " +
                           std::to_string(f) + " (at line " + std::to_string(lines.number()) + ")");
        token_reader tokens(face_line);
        std::string_view size_token, index;
        tokens.next(size_token);
        const std::string face = "face " + std::to_string(f);
        if (!size_token.empty() && size_token.front() == '-')
            fail_at(file, lines.number(), face + " has a negative vertex count " + quote_token(size_token));
        const std::optional<std::uint64_t> size = parse_count(size_token);
        if (!size)
            fail_at(file, lines.number(), "expected the vertex count of " + face + " but found " + quote_token(size_token));
        std::uint64_t indices = 0;
        while (indices < *size && tokens.next(index)) {
            // CGAL's scanner converts a negative index to std::size_t too (undefined behaviour).
            if (!index.empty() && index.front() == '-')
                fail_at(file, lines.number(), face + " has a negative vertex index " + quote_token(index));
            // It reads every index as a double and converts it: an index beyond std::size_t
            // ("3 3555...5", 65 digits: found by fuzzing) is undefined behaviour as well. An
            // index is a whole number naming one of the vertices.
            if (!std::all_of(index.begin(), index.end(), [](char c) { return c >= '0' && c <= '9'; }))
                fail_at(file, lines.number(), face + " has a vertex index that is not a whole number: " + quote_token(index));
            const std::optional<std::uint64_t> vertex = parse_count(index);  // none: beyond 2^64 - 1
            if (!vertex || *vertex >= *vertex_count)
                fail_at(file, lines.number(), face + " has vertex index " + quote_token(index) + " but the file has " +
                                                  std::to_string(*vertex_count) + " vertices (0 to " +
                                                  std::to_string(*vertex_count - 1) + ")");
            ++indices;
        }
        if (indices < *size)
            fail_at(file, lines.number(), face + " declares " + std::to_string(*size) + " vertices but its line has " +
                                              std::to_string(indices) + " indices (a face is one line)");
        // With C in the header the scanner reads what follows the indices as the face's colour,
        // by the same rules as a vertex's (it reads past its numbers otherwise).
        if (colours)
            check_off_colour_columns(finite_columns(tokens, face, file, lines.number()), first_face_colours, face, file,
                                     lines.number());
    }
    return points;
}

// .obj: the geometric vertices "v x y z [w] [r g b]"; every other statement is ignored.
std::vector<point3> parse_obj_text(std::string_view text, const fs::path& file) {
    std::vector<point3> points;
    line_reader lines(text);
    std::string_view line;
    while (lines.next(line)) {
        token_reader tokens(strip_comment(line));
        std::string_view keyword;
        if (!tokens.next(keyword) || keyword != "v") continue;
        points.push_back(parse_xyz(tokens, file, lines.number(), "a \"v\" line"));
    }
    return points;
}

std::vector<point3> load_ply(const fs::path& file) {
#if defined(SPATIAL_DATASETS_HAVE_CGAL)
    using kernel = CGAL::Simple_cartesian<double>;
    std::error_code ec;
    if (!fs::is_regular_file(file, ec)) fail(file, "cannot open the file (missing or not a file)");
    // Our own check first: CGAL's reader silently yields (0, 0, 0) points when x, y or z is
    // missing, gives no reason for a failure, crashes on some headers, and allocates a list's
    // declared count before reading it (ply_check.hpp).
    std::ifstream in(file, std::ios::binary);
    if (!in) fail(file, "cannot open the file (missing or unreadable)");
    const ply_check_result checked = check_ply(in, ply_use::points);
    if (!checked.problem.empty()) {
        if (checked.line == 0) fail(file, checked.problem);
        fail_at(file, checked.line, checked.problem);
    }
    const std::uint64_t declared = checked.vertex_count;
    std::vector<kernel::Point_3> read;
    bool ok = false;
    try {
        ok = CGAL::IO::read_PLY(file.string(), std::back_inserter(read));
    } catch (const std::exception& e) {
        fail(file, std::string("CGAL's PLY reader failed: ") + e.what());
    }
    if (!ok) {
        fail(file, "CGAL's PLY reader could not read the vertices (truncated, or a value that is "
                   "not a number, such as nan in ASCII PLY)");
    }
    if (read.size() != declared) {
        fail(file, "the PLY header declares " + std::to_string(declared) + " vertices but " +
                       std::to_string(read.size()) + " were read");
    }
    std::vector<point3> points;
    points.reserve(read.size());
    for (std::size_t i = 0; i < read.size(); ++i) {
        const point3 p{{read[i].x(), read[i].y(), read[i].z()}};
        for (std::size_t d = 0; d < 3; ++d) {
            if (!std::isfinite(p[d])) {
                fail(file, "vertex " + std::to_string(i) + " has a non-finite coordinate " +
                               std::to_string(p[d]) + " (NaN and infinite coordinates are rejected)");
            }
        }
        points.push_back(p);
    }
    return points;
#else
    fail(file, "reading PLY needs CGAL: configure with -DSPATIAL_WITH_CGAL=ON");
#endif
}

std::string lower_case(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

#if defined(SPATIAL_DATASETS_HAVE_CGAL)
constexpr std::array<std::string_view, 6> extensions{".xyz", ".xyzn", ".pwn", ".off", ".obj", ".ply"};
#else
constexpr std::array<std::string_view, 5> extensions{".xyz", ".xyzn", ".pwn", ".off", ".obj"};
#endif

}  // namespace

std::span<const std::string_view> supported_point_set_extensions() noexcept { return extensions; }

bool can_load_ply() noexcept {
#if defined(SPATIAL_DATASETS_HAVE_CGAL)
    return true;
#else
    return false;
#endif
}

void check_off_faces(const std::filesystem::path& file) {
    parse_off_text(read_whole_file(file), file, off_faces::check);
}

std::vector<spatial::point<double, 3>> load_point_set(const std::filesystem::path& file) {
    const std::string ext = lower_case(file.extension().string());
    std::vector<point3> points;
    if (ext == ".xyz" || ext == ".xyzn" || ext == ".pwn") {
        points = parse_xyz_text(read_whole_file(file), file);
    } else if (ext == ".off") {
        points = parse_off_text(read_whole_file(file), file);
    } else if (ext == ".obj") {
        points = parse_obj_text(read_whole_file(file), file);
    } else if (ext == ".ply") {
        points = load_ply(file);
    } else {
        std::string message = "unsupported extension " + quote_token(ext.empty() ? "(none)" : ext) +
                              "; supported: ";
        for (std::size_t i = 0; i < extensions.size(); ++i) {
            message += (i ? ", " : "");
            message += extensions[i];
        }
        if (!can_load_ply()) message += " (.ply needs a build with -DSPATIAL_WITH_CGAL=ON)";
        fail(file, message);
    }
    if (points.empty()) fail(file, "contains no points");
    return points;
}

}  // namespace datasets
