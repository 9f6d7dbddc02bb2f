#pragma once
// datasets::scene_description — a collision/query scene as read from a TOML scene file: the
// object sets (seeded generator or mesh), their motion, the number of steps, and the effects
// the scene asks for (collide, raycast, nearest, range, churn). Plain data with every default
// filled in and every name resolved; the runner (harness/) composes exactly the pipeline the
// present effects need, so an absent effect (std::nullopt) must cost nothing.
//
// The file format, every key, its default and its unit are documented in datasets/README.md
// ("Scene files"). Parsing lives in src/scene_file.cpp so that toml++ stays out of every other
// translation unit. Object generation: scene_objects.hpp; motion: scene_motion.hpp; rays and
// query points: scene_queries.hpp.
//
// Units: lengths in the scene's domain units; time in seconds of simulated time (time_step);
// speeds in domain units per second; angular speeds in radians per second.

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "datasets/generators.hpp"  // point_workload: the placement generators

namespace datasets {

// Every scene error: a syntax error, an unknown key, a wrong type, an out-of-range value, a
// reference to an unknown set. what() is "FILE:LINE:COLUMN: message", like a compiler's, e.g.
//   falling.toml:12:1: [effects.collide] unknown key 'filtr' (expected one of: between, filter, strategy)
class scene_error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Where a table or key starts in the scene file (1-based). line == 0: not from a file (a
// default, or a description built in code). Kept so the runner can point its own errors (a
// mesh file that fails to load, say) at the line that asked for it.
struct source_position {
    std::uint32_t line = 0;
    std::uint32_t column = 0;
};

// Coordinates of a point or direction; only the first `dimension` entries are used (the
// third is 0 in 2D scenes). Kept in double whatever the scene's scalar, so that a scene means
// the same thing in float and double runs.
using scene_vector = std::array<double, 3>;

enum class scalar_kind { float32, float64 };  // TOML: "float", "double"
enum class object_kind { point, box, sphere, triangle };
enum class size_distribution { fixed, uniform, heavy_tailed };
enum class motion_kind { static_, linear, random_walk, rigid_rotation };  // TOML: "static", ...
enum class collide_filter { candidates, exact };
enum class update_strategy { automatic, refit, rebuild, reinsert };
enum class ray_kind { random, camera };
enum class mesh_split { triangles };  // one triangle object per mesh triangle (the only split so far)

// The TOML spelling of each enumerator (what the parser accepts and to_toml writes).
std::string_view to_string(scalar_kind) noexcept;
std::string_view to_string(object_kind) noexcept;
std::string_view to_string(size_distribution) noexcept;
std::string_view to_string(motion_kind) noexcept;
std::string_view to_string(collide_filter) noexcept;
std::string_view to_string(update_strategy) noexcept;
std::string_view to_string(ray_kind) noexcept;
std::string_view to_string(mesh_split) noexcept;

// How the objects of a set move between steps. One body or many: a MESH set moves as one rigid
// body (its triangles share one velocity / one random displacement, and it bounces when the
// box of the whole mesh leaves the domain); a GENERATOR set's objects move independently, except
// under rigid_rotation, which turns the whole set about `centre`.
struct motion_description {
    motion_kind kind = motion_kind::static_;
    // linear: |velocity|; random_walk: the per-axis RMS speed (each step moves each axis by
    // N(0, (speed * dt)^2)). Domain units per second, >= 0.
    double speed = 0;
    // linear only: the common direction of every object (as written, non-zero; scene_motion
    // normalises it). nullopt: each object (or the mesh body) draws its own random direction.
    std::optional<scene_vector> direction;
    // rigid_rotation: the rotation axis (3D only, as written, non-zero; 2D turns in the plane),
    // the angular speed (rad/s, counter-clockwise about the axis by the right-hand rule, any
    // sign) and the centre (default: the domain's).
    scene_vector axis{0, 0, 1};
    double angular_speed = 0;
    scene_vector centre{};
    source_position position;  // the motion table (or the set's table when motion is omitted)
};

// Objects drawn by a seeded generator: centres from a point workload mapped into the domain,
// sizes from a size distribution.
struct generator_source {
    point_workload placement = point_workload::uniform;
    std::size_t count = 0;  // >= 1
    // box: edge length; sphere: radius; triangle: circumradius; points: unused (0).
    double size = 0;
    size_distribution sizes = size_distribution::fixed;
    double size_max = 0;  // heavy_tailed: the cap (default 10 * size); 0 for the others
};

// Triangles from a mesh, one object per triangle. Vertices are mapped x -> offset + scale * n(x)
// where n normalises the mesh into the unit cube (largest extent 1, centred at 0.5) when
// `normalize` is set, and is the identity otherwise.
struct mesh_source {
    enum class origin { file, generated };
    origin from = origin::generated;
    std::string reference;       // as written in the scene file: "bunny.off", "generated:sphere"
    std::filesystem::path file;  // origin::file: resolved against the scene file's directory
    std::string generator;       // origin::generated: "sphere" or "soup" (mesh_generators.hpp)
    std::size_t triangles = 0;   // origin::generated: about this many triangles (exact for soup)
    double scale = 1;
    scene_vector offset{};
    bool normalize = true;
    mesh_split split = mesh_split::triangles;
};

struct object_set {
    std::string name;  // unique within the scene
    object_kind kind = object_kind::box;
    // Exactly one of the two is set.
    std::optional<generator_source> generator;
    std::optional<mesh_source> mesh;  // only with kind == triangle, only in 3D
    motion_description motion;
    source_position position;  // the [[objects]] header

    bool is_mesh() const noexcept { return mesh.has_value(); }
    bool moves() const noexcept { return motion.kind != motion_kind::static_; }
};

// Sets are referred to by their index in scene_description::objects.
struct collide_effect {
    // The pairs of sets to test; (i, i) asks for the self pairs of set i. Each unordered pair at
    // most once.
    std::vector<std::pair<std::size_t, std::size_t>> between;
    collide_filter filter = collide_filter::exact;  // candidates: broad phase only (boxes overlap)
    update_strategy strategy = update_strategy::automatic;  // how indexes follow moving objects
    source_position position;
};

struct raycast_effect {
    std::vector<std::size_t> targets;  // default: every set, in file order
    std::size_t rays_per_step = 0;     // >= 1
    ray_kind kind = ray_kind::random;
    double thickness = 0;  // capsule radius of the rays; > 0 needed when a point set is a target
    // camera only (see scene_queries.hpp for how rays are laid out):
    scene_vector eye{};      // default: look_at - (0, 2 * largest domain extent[, 0])
    scene_vector look_at{};  // default: the domain centre
    double field_of_view = 45;  // degrees, full angle, in (0, 180)
    source_position position;
};

struct nearest_effect {
    std::size_t target = 0;
    std::size_t queries_per_step = 0;  // >= 1
    std::size_t k = 10;                // >= 1
    source_position position;
};

struct range_effect {
    std::size_t target = 0;
    std::size_t queries_per_step = 0;  // >= 1
    double half_extent = 0;            // query boxes are centre -/+ half_extent on every axis, > 0
    source_position position;
};

// Objects inserted into / erased from a generator set at every step.
struct churn_effect {
    std::size_t target = 0;  // a generator set (inserted objects are drawn like its initial ones)
    std::size_t inserts_per_step = 0;
    std::size_t erases_per_step = 0;  // at most the current size is erased
    source_position position;
};

struct scene_description {
    std::string file;  // the file name given to the parser (used in messages)
    std::string name;  // default: the file name's stem
    std::string description;
    std::size_t dimension = 3;  // 2 or 3
    scalar_kind scalar = scalar_kind::float64;
    std::size_t steps = 1;    // >= 1; each step: move, churn, then the effects
    double time_step = 0.01;  // seconds of simulated time per step, > 0
    std::uint64_t seed = 42;
    scene_vector domain_lo{0, 0, 0};  // objects start inside; linear and random-walk motion
    scene_vector domain_hi{1, 1, 1};  // bounce off its walls; lo < hi on every used axis
    std::vector<object_set> objects;  // at least one

    std::optional<collide_effect> collide;
    std::optional<raycast_effect> raycast;
    std::optional<nearest_effect> nearest;
    std::optional<range_effect> range;
    std::optional<churn_effect> churn;

    source_position position;  // the [scene] table (1:1 when the file has none)

    // The index of the set called `set_name`, or nullopt.
    std::optional<std::size_t> find_set(std::string_view set_name) const noexcept {
        for (std::size_t i = 0; i < objects.size(); ++i)
            if (objects[i].name == set_name) return i;
        return std::nullopt;
    }
    // True when some set moves: a scene where this is false needs no index updates.
    bool moves() const noexcept {
        for (const auto& s : objects)
            if (s.moves()) return true;
        return false;
    }
    scene_vector domain_centre() const noexcept {
        scene_vector c{};
        for (std::size_t d = 0; d < 3; ++d) c[d] = domain_lo[d] + (domain_hi[d] - domain_lo[d]) / 2;
        return c;
    }
};

// Reads and validates a scene file. Relative mesh paths are resolved against the file's
// directory. Throws scene_error ("FILE:LINE:COLUMN: ...") for any problem in the file, and
// scene_error ("FILE: cannot open ...") when it cannot be read. Does not open mesh files: the
// runner loads them (mesh_source::file) and can cite mesh's object_set::position.
scene_description load_scene(const std::filesystem::path& file);

// The same from text; `file_name` names the file in messages, and its directory resolves
// relative mesh paths (an empty directory: relative to the working directory).
scene_description parse_scene(std::string_view toml_text, std::string_view file_name);

// The scene as a TOML scene file that parse_scene reads back to the same description, with
// every default written out (for logs and run sidecars). Mesh files are written as referenced.
std::string to_toml(const scene_description& scene);

}  // namespace datasets
