// Scene files: TOML text -> datasets::scene_description (and back, for logs).
//
// The only translation unit that includes toml++. The parser is strict on purpose: a benchmark
// scene with a misspelt key that is silently ignored measures something other than what its
// author believes, so every unknown key, wrong type, out-of-range value and dangling set name is
// an error that cites the file, line and column of the offending key (or array element).

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include <toml++/toml.h>

#include "datasets/mesh_generators.hpp"
#include "datasets/scene.hpp"

namespace datasets {

// ---- enum spellings --------------------------------------------------------------------------

namespace {

template <class E, std::size_t N>
struct enum_names {
    std::array<std::string_view, N> names;
    std::string_view operator[](E e) const noexcept { return names[static_cast<std::size_t>(e)]; }
};

constexpr enum_names<scalar_kind, 2> scalar_names{{"float", "double"}};
constexpr enum_names<object_kind, 4> object_kind_names{{"point", "box", "sphere", "triangle"}};
constexpr enum_names<size_distribution, 3> size_distribution_names{{"fixed", "uniform", "heavy_tailed"}};
constexpr enum_names<motion_kind, 4> motion_kind_names{{"static", "linear", "random_walk", "rigid_rotation"}};
constexpr enum_names<collide_filter, 2> collide_filter_names{{"candidates", "exact"}};
constexpr enum_names<update_strategy, 4> update_strategy_names{{"automatic", "refit", "rebuild", "reinsert"}};
constexpr enum_names<ray_kind, 2> ray_kind_names{{"random", "camera"}};
constexpr enum_names<mesh_split, 1> mesh_split_names{{"triangles"}};

}  // namespace

std::string_view to_string(scalar_kind e) noexcept { return scalar_names[e]; }
std::string_view to_string(object_kind e) noexcept { return object_kind_names[e]; }
std::string_view to_string(size_distribution e) noexcept { return size_distribution_names[e]; }
std::string_view to_string(motion_kind e) noexcept { return motion_kind_names[e]; }
std::string_view to_string(collide_filter e) noexcept { return collide_filter_names[e]; }
std::string_view to_string(update_strategy e) noexcept { return update_strategy_names[e]; }
std::string_view to_string(ray_kind e) noexcept { return ray_kind_names[e]; }
std::string_view to_string(mesh_split e) noexcept { return mesh_split_names[e]; }

// ---- parsing ---------------------------------------------------------------------------------

namespace {

// Counts (object counts, steps, per-step numbers) fit in 32 bits: the runner identifies objects
// by std::uint32_t (harness::index_pair), and larger scenes would not fit in memory anyway.
constexpr std::int64_t max_count = std::numeric_limits<std::uint32_t>::max();

std::string join(std::initializer_list<std::string_view> words) {
    std::string out;
    for (auto w : words) {
        if (!out.empty()) out += ", ";
        out += w;
    }
    return out;
}

template <class E, std::size_t N>
std::string join(const enum_names<E, N>& table) {
    std::string out;
    for (auto w : table.names) {
        if (!out.empty()) out += ", ";
        out += w;
    }
    return out;
}

// Shortest text that reads back to the same double (std::to_chars), always a TOML float.
std::string format_number(double v) {
    char buffer[64];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, v);
    std::string s(buffer, result.ptr);
    if (s.find_first_of(".en") == std::string::npos) s += ".0";
    return s;
}

source_position position_of(const toml::source_region& region) {
    return {static_cast<std::uint32_t>(region.begin.line), static_cast<std::uint32_t>(region.begin.column)};
}

std::string_view type_name(const toml::node& node) {
    switch (node.type()) {
        case toml::node_type::table: return "a table";
        case toml::node_type::array: return "an array";
        case toml::node_type::string: return "a string";
        case toml::node_type::integer: return "an integer";
        case toml::node_type::floating_point: return "a float";
        case toml::node_type::boolean: return "a boolean";
        case toml::node_type::date: return "a date";
        case toml::node_type::time: return "a time";
        case toml::node_type::date_time: return "a date-time";
        default: return "nothing";
    }
}

class scene_parser {
public:
    scene_parser(std::string_view file_name) : file_(file_name) {
        directory_ = std::filesystem::path(std::string(file_name)).parent_path();
    }

    [[noreturn]] void fail(source_position at, std::string_view context, std::string_view message) const {
        std::string what = file_ + ":" + std::to_string(at.line) + ":" + std::to_string(at.column) + ": ";
        if (!context.empty()) {
            what += context;
            what += ' ';
        }
        what += message;
        throw scene_error(what);
    }

    // One TOML table being read: lookups by key, each failure citing the key's position.
    class table_reader {
    public:
        table_reader(const scene_parser& parser, const toml::table& table, std::string context)
            : parser_(parser), table_(table), context_(std::move(context)) {}

        const std::string& context() const { return context_; }
        void rename(std::string context) { context_ = std::move(context); }
        source_position position() const { return position_of(table_.source()); }
        bool has(std::string_view key) const { return table_.contains(key); }

        [[noreturn]] void fail(source_position at, std::string_view message) const {
            parser_.fail(at, context_, message);
        }
        [[noreturn]] void fail_key(std::string_view key, std::string_view message) const {
            fail(key_position(key), "'" + std::string(key) + "' " + std::string(message));
        }

        source_position key_position(std::string_view key) const {
            const auto it = table_.find(key);
            return it == table_.end() ? position() : position_of(it->first.source());
        }

        // Every key must be one of `allowed`; the first unknown key in file order is reported.
        void allow_only(std::initializer_list<std::string_view> allowed) const {
            const toml::key* first_unknown = nullptr;
            for (auto&& [key, node] : table_) {
                if (std::find(allowed.begin(), allowed.end(), key.str()) != allowed.end()) continue;
                if (!first_unknown || earlier(key.source(), first_unknown->source())) first_unknown = &key;
            }
            if (first_unknown)
                fail(position_of(first_unknown->source()),
                     "unknown key '" + std::string(first_unknown->str()) + "' (expected one of: " + join(allowed) + ")");
        }

        // `key` must be absent: it does not apply here (`why` says why).
        void forbid(std::string_view key, std::string_view why) const {
            if (has(key)) fail_key(key, std::string(why));
        }

        const toml::node* node(std::string_view key) const { return table_.get(key); }

        std::optional<std::string> string(std::string_view key) const {
            const auto* n = node(key);
            if (!n) return std::nullopt;
            if (!n->is_string()) fail_key(key, "must be a string, not " + std::string(type_name(*n)));
            return std::string(n->as_string()->get());
        }
        std::string required_string(std::string_view key) const {
            auto s = string(key);
            if (!s) fail(position(), "needs the key '" + std::string(key) + "'");
            return *s;
        }

        std::optional<bool> boolean(std::string_view key) const {
            const auto* n = node(key);
            if (!n) return std::nullopt;
            if (!n->is_boolean()) fail_key(key, "must be true or false, not " + std::string(type_name(*n)));
            return n->as_boolean()->get();
        }

        std::optional<std::int64_t> integer(std::string_view key, std::int64_t lo, std::int64_t hi) const {
            const auto* n = node(key);
            if (!n) return std::nullopt;
            if (!n->is_integer()) fail_key(key, "must be an integer, not " + std::string(type_name(*n)));
            const std::int64_t v = n->as_integer()->get();
            if (v < lo || v > hi)
                fail_key(key, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "] (got " +
                                  std::to_string(v) + ")");
            return v;
        }
        std::size_t required_count(std::string_view key, std::int64_t lo) const {
            const auto v = integer(key, lo, max_count);
            if (!v) fail(position(), "needs the key '" + std::string(key) + "'");
            return static_cast<std::size_t>(*v);
        }
        std::size_t count(std::string_view key, std::int64_t lo, std::size_t fallback) const {
            const auto v = integer(key, lo, max_count);
            return v ? static_cast<std::size_t>(*v) : fallback;
        }

        std::optional<double> number(std::string_view key) const {
            const auto* n = node(key);
            if (!n) return std::nullopt;
            std::string problem;
            const auto v = finite_number(*n, problem);
            if (!v) fail_key(key, problem);
            return v;
        }
        double required_number(std::string_view key) const {
            const auto v = number(key);
            if (!v) fail(position(), "needs the key '" + std::string(key) + "'");
            return *v;
        }

        // An array of exactly `size` finite numbers (the scene's dimension, usually).
        std::optional<scene_vector> vector(std::string_view key, std::size_t size) const {
            const auto* n = node(key);
            if (!n) return std::nullopt;
            const auto* elements = n->as_array();
            const std::string expected = "must be an array of " + std::to_string(size) + " numbers";
            if (!elements) fail_key(key, expected + ", not " + std::string(type_name(*n)));
            if (elements->size() != size)
                fail_key(key, expected + " (one per axis), not of " + std::to_string(elements->size()));
            scene_vector v{};
            for (std::size_t i = 0; i < size; ++i) {
                const toml::node& element = *elements->get(i);
                std::string problem;
                const auto x = finite_number(element, problem);
                if (!x)
                    fail(position_of(element.source()),
                         "'" + std::string(key) + "' element " + std::to_string(i + 1) + " " + problem);
                v[i] = *x;
            }
            return v;
        }

        template <class E, std::size_t N>
        std::optional<E> choice(std::string_view key, const enum_names<E, N>& names) const {
            const auto s = string(key);
            if (!s) return std::nullopt;
            for (std::size_t i = 0; i < N; ++i)
                if (names.names[i] == *s) return static_cast<E>(i);
            fail_key(key, "has no value '" + *s + "' (expected one of: " + join(names) + ")");
        }

        const toml::table* table(std::string_view key) const {
            const auto* n = node(key);
            if (!n) return nullptr;
            if (!n->is_table()) fail_key(key, "must be a table, not " + std::string(type_name(*n)));
            return n->as_table();
        }

        const toml::array* array(std::string_view key) const {
            const auto* n = node(key);
            if (!n) return nullptr;
            if (!n->is_array()) fail_key(key, "must be an array, not " + std::string(type_name(*n)));
            return n->as_array();
        }

    private:
        static bool earlier(const toml::source_region& a, const toml::source_region& b) {
            return a.begin.line != b.begin.line ? a.begin.line < b.begin.line : a.begin.column < b.begin.column;
        }

        const scene_parser& parser_;
        const toml::table& table_;
        std::string context_;
    };

    // A finite number; TOML integers are accepted where a float is expected (speed = 1).
    // nullopt, with `problem` set, otherwise.
    static std::optional<double> finite_number(const toml::node& n, std::string& problem) {
        double v = 0;
        if (n.is_integer()) {
            v = static_cast<double>(n.as_integer()->get());
        } else if (n.is_floating_point()) {
            v = n.as_floating_point()->get();
        } else {
            problem = "must be a number, not " + std::string(type_name(n));
            return std::nullopt;
        }
        if (!std::isfinite(v)) {
            problem = "must be finite (got " + std::string(std::isnan(v) ? "nan" : "inf") + ")";
            return std::nullopt;
        }
        return v;
    }

    scene_description parse(const toml::table& root) {
        scene_description scene;
        scene.file = file_;
        scene.name = std::filesystem::path(file_).stem().string();
        scene.position = {1, 1};

        const table_reader top(*this, root, "");
        top.allow_only({"scene", "objects", "effects"});

        if (const auto* t = top.table("scene")) parse_scene_table(table_reader(*this, *t, "[scene]"), scene);

        const auto* objects = top.node("objects");
        if (!objects) fail({1, 1}, "", "the scene has no object set: add at least one [[objects]] table");
        if (!objects->is_array_of_tables())
            top.fail_key("objects", "must be an array of tables: write each set as [[objects]] (double brackets)");
        for (const auto& element : *objects->as_array()) parse_object_set(*element.as_table(), scene);

        const auto* effects = top.table("effects");
        if (!effects)
            fail({1, 1}, "", "the scene asks for no effect: add at least one of [effects.collide], "
                             "[effects.raycast], [effects.nearest], [effects.range], [effects.churn]");
        parse_effects(table_reader(*this, *effects, "[effects]"), scene);
        return scene;
    }

private:
    void parse_scene_table(const table_reader& t, scene_description& scene) const {
        t.allow_only({"name", "description", "dimension", "scalar", "steps", "time_step", "seed", "domain"});
        scene.position = t.position();
        if (auto s = t.string("name")) {
            if (s->empty()) t.fail_key("name", "must not be empty");
            scene.name = *s;
        }
        if (auto s = t.string("description")) scene.description = *s;
        if (auto d = t.node("dimension")) {
            if (!d->is_integer()) t.fail_key("dimension", "must be the integer 2 or 3, not " + std::string(type_name(*d)));
            const auto v = d->as_integer()->get();
            if (v != 2 && v != 3) t.fail_key("dimension", "must be 2 or 3 (got " + std::to_string(v) + ")");
            scene.dimension = static_cast<std::size_t>(v);
        }
        if (auto s = t.choice("scalar", scalar_names)) scene.scalar = *s;
        scene.steps = t.count("steps", 1, scene.steps);
        if (auto v = t.number("time_step")) {
            if (!(*v > 0)) t.fail_key("time_step", "must be > 0 seconds");
            scene.time_step = *v;
        }
        if (auto v = t.integer("seed", 0, std::numeric_limits<std::int64_t>::max()))
            scene.seed = static_cast<std::uint64_t>(*v);
        if (const auto* d = t.table("domain")) {
            const table_reader domain(*this, *d, "[scene.domain]");
            domain.allow_only({"lo", "hi"});
            scene.domain_lo = {0, 0, 0};
            scene.domain_hi = {1, 1, 1};
            if (auto v = domain.vector("lo", scene.dimension)) scene.domain_lo = *v;
            if (auto v = domain.vector("hi", scene.dimension)) scene.domain_hi = *v;
            for (std::size_t i = 0; i < scene.dimension; ++i)
                if (!(scene.domain_lo[i] < scene.domain_hi[i]))
                    domain.fail(domain.position(), "needs lo < hi on every axis (axis " + std::to_string(i) +
                                                       ": lo = " + format_number(scene.domain_lo[i]) +
                                                       ", hi = " + format_number(scene.domain_hi[i]) + ")");
        }
        if (scene.dimension == 2) scene.domain_lo[2] = scene.domain_hi[2] = 0;
    }

    void parse_object_set(const toml::table& table, scene_description& scene) const {
        table_reader t(*this, table, "[[objects]]");
        t.allow_only({"name", "kind", "placement", "count", "size", "size_distribution", "size_max", "mesh",
                      "triangles", "scale", "offset", "normalize", "split", "motion"});
        object_set set;
        set.position = t.position();
        set.name = t.required_string("name");
        if (set.name.empty()) t.fail_key("name", "must not be empty");
        if (auto earlier_set = scene.find_set(set.name))
            t.fail_key("name", "'" + set.name + "' is already the name of the set at line " +
                                   std::to_string(scene.objects[*earlier_set].position.line));
        t.rename("[[objects]] '" + set.name + "'");
        const auto kind = t.choice("kind", object_kind_names);
        if (!kind) t.fail(t.position(), "needs the key 'kind' (one of: " + join(object_kind_names) + ")");
        set.kind = *kind;

        if (t.has("mesh")) {
            set.mesh = parse_mesh_source(t, scene, set.kind);
        } else {
            set.generator = parse_generator_source(t, set.kind);
        }

        set.motion.position = set.position;
        set.motion.centre = scene.domain_centre();
        if (const auto* m = t.table("motion"))
            set.motion = parse_motion(table_reader(*this, *m, t.context() + " motion"), scene);
        scene.objects.push_back(std::move(set));
    }

    mesh_source parse_mesh_source(const table_reader& t, const scene_description& scene, object_kind kind) const {
        for (auto key : {"placement", "count", "size", "size_distribution", "size_max"})
            t.forbid(key, "does not apply to a mesh set (its objects are the mesh's triangles)");
        if (scene.dimension != 3) t.fail_key("mesh", "needs a 3D scene (meshes are 3D; this scene has dimension = 2)");
        if (kind != object_kind::triangle)
            t.fail_key("mesh", "needs kind = \"triangle\" (a mesh set holds one triangle object per mesh triangle)");
        mesh_source m;
        m.reference = *t.string("mesh");
        if (m.reference.empty()) t.fail_key("mesh", "must not be empty: a file path or \"generated:sphere\"");
        constexpr std::string_view generated_prefix = "generated:";
        if (m.reference.starts_with(generated_prefix)) {
            m.from = mesh_source::origin::generated;
            m.generator = m.reference.substr(generated_prefix.size());
            if (std::find(mesh_workload_names.begin(), mesh_workload_names.end(), m.generator) ==
                mesh_workload_names.end())
                t.fail_key("mesh", "names no mesh generator '" + m.generator + "' (expected generated:sphere or generated:soup)");
            m.triangles = t.required_count("triangles", 1);
        } else {
            m.from = mesh_source::origin::file;
            t.forbid("triangles", "applies only to generated meshes (a mesh file has the triangles it has)");
            const std::filesystem::path p(m.reference);
            m.file = p.is_absolute() ? p : (directory_ / p).lexically_normal();
        }
        if (auto v = t.number("scale")) {
            if (!(*v > 0)) t.fail_key("scale", "must be > 0");
            m.scale = *v;
        }
        if (auto v = t.vector("offset", 3)) m.offset = *v;
        if (auto v = t.boolean("normalize")) m.normalize = *v;
        if (auto v = t.choice("split", mesh_split_names)) m.split = *v;
        return m;
    }

    generator_source parse_generator_source(const table_reader& t, object_kind kind) const {
        for (auto key : {"triangles", "scale", "offset", "normalize", "split"})
            t.forbid(key, "applies only to mesh sets (with mesh = \"...\")");
        generator_source g;
        g.count = t.required_count("count", 1);
        if (auto s = t.string("placement")) {
            try {
                g.placement = parse_point_workload(*s);
            } catch (const std::invalid_argument&) {
                std::string names;
                for (auto n : point_workload_names()) names += (names.empty() ? "" : ", ") + std::string(n);
                t.fail_key("placement", "has no value '" + *s + "' (expected one of: " + names + ")");
            }
        }
        if (kind == object_kind::point) {
            for (auto key : {"size", "size_distribution", "size_max"}) t.forbid(key, "does not apply to points");
            return g;
        }
        g.size = t.required_number("size");
        if (!(g.size > 0)) t.fail_key("size", "must be > 0 (got " + format_number(g.size) + ")");
        if (auto d = t.choice("size_distribution", size_distribution_names)) g.sizes = *d;
        if (g.sizes == size_distribution::heavy_tailed) {
            g.size_max = 10 * g.size;
            if (auto v = t.number("size_max")) {
                if (!(*v >= g.size)) t.fail_key("size_max", "must be >= size (" + format_number(g.size) + ")");
                g.size_max = *v;
            }
        } else {
            t.forbid("size_max", "applies only to size_distribution = \"heavy_tailed\"");
        }
        return g;
    }

    motion_description parse_motion(const table_reader& t, const scene_description& scene) const {
        t.allow_only({"kind", "speed", "direction", "axis", "angular_speed", "centre"});
        motion_description m;
        m.position = t.position();
        m.centre = scene.domain_centre();
        const auto kind = t.choice("kind", motion_kind_names);
        if (!kind) t.fail(t.position(), "needs the key 'kind' (one of: " + join(motion_kind_names) + ")");
        m.kind = *kind;
        const std::string kind_name(to_string(m.kind));
        auto only_for = [&](std::string_view key, std::string_view kinds) {
            t.forbid(key, "does not apply to motion kind '" + kind_name + "' (only to " + std::string(kinds) + ")");
        };
        if (m.kind == motion_kind::linear || m.kind == motion_kind::random_walk) {
            m.speed = t.required_number("speed");
            if (!(m.speed >= 0)) t.fail_key("speed", "must be >= 0 (got " + format_number(m.speed) + ")");
        } else {
            only_for("speed", "linear and random_walk");
        }
        if (m.kind == motion_kind::linear) {
            if (auto v = t.vector("direction", scene.dimension)) m.direction = nonzero(t, "direction", *v);
        } else {
            only_for("direction", "linear");
        }
        if (m.kind == motion_kind::rigid_rotation) {
            m.angular_speed = t.required_number("angular_speed");
            if (scene.dimension == 2) {
                t.forbid("axis", "is not used in a 2D scene (rotations turn in the plane; the sign of "
                                 "angular_speed gives the sense)");
                m.axis = {0, 0, 1};
            } else if (auto v = t.vector("axis", 3)) {
                m.axis = nonzero(t, "axis", *v);
            }
            if (auto v = t.vector("centre", scene.dimension)) m.centre = *v;
        } else {
            for (auto key : {"axis", "angular_speed", "centre"}) only_for(key, "rigid_rotation");
        }
        return m;
    }

    // Directions are kept as written (so that to_toml writes them back bit for bit; the motion
    // normalises them), but must have a direction.
    static scene_vector nonzero(const table_reader& t, std::string_view key, const scene_vector& v) {
        const double length = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if (!(length > 0) || !std::isfinite(length)) t.fail_key(key, "must be a non-zero vector");
        return v;
    }

    // A set referred to by name from an effect; `at` is where the name is written.
    std::size_t set_index(const table_reader& t, const toml::node& name_node, std::string_view what,
                          const scene_description& scene) const {
        const auto at = position_of(name_node.source());
        if (!name_node.is_string())
            t.fail(at, std::string(what) + " must name an object set (a string), not " + std::string(type_name(name_node)));
        const std::string name(name_node.as_string()->get());
        if (auto i = scene.find_set(name)) return *i;
        std::string names;
        for (const auto& s : scene.objects) names += (names.empty() ? "'" : ", '") + s.name + "'";
        t.fail(at, std::string(what) + " names no object set '" + name + "' (the sets are: " + names + ")");
    }

    std::size_t target_set(const table_reader& t, const scene_description& scene) const {
        const auto* n = t.node("target");
        if (!n) t.fail(t.position(), "needs the key 'target' (the name of an object set)");
        return set_index(t, *n, "'target'", scene);
    }

    void parse_effects(const table_reader& t, scene_description& scene) const {
        t.allow_only({"collide", "raycast", "nearest", "range", "churn"});
        if (const auto* c = t.table("collide")) scene.collide = parse_collide(table_reader(*this, *c, "[effects.collide]"), scene);
        if (const auto* r = t.table("raycast")) scene.raycast = parse_raycast(table_reader(*this, *r, "[effects.raycast]"), scene);
        if (const auto* n = t.table("nearest")) scene.nearest = parse_nearest(table_reader(*this, *n, "[effects.nearest]"), scene);
        if (const auto* r = t.table("range")) scene.range = parse_range(table_reader(*this, *r, "[effects.range]"), scene);
        if (const auto* c = t.table("churn")) scene.churn = parse_churn(table_reader(*this, *c, "[effects.churn]"), scene);
        if (!scene.collide && !scene.raycast && !scene.nearest && !scene.range && !scene.churn)
            t.fail(t.position(), "asks for no effect: add at least one of collide, raycast, nearest, range, churn");
    }

    // An effect on one set: only the keys `allowed`, its position, and its 'target'.
    template <class Effect>
    Effect targeted_effect(const table_reader& t, const scene_description& scene,
                           std::initializer_list<std::string_view> allowed) const {
        t.allow_only(allowed);
        Effect effect;
        effect.position = t.position();
        effect.target = target_set(t, scene);
        return effect;
    }

    nearest_effect parse_nearest(const table_reader& t, const scene_description& scene) const {
        auto effect = targeted_effect<nearest_effect>(t, scene, {"target", "queries_per_step", "k"});
        effect.queries_per_step = t.required_count("queries_per_step", 1);
        effect.k = t.count("k", 1, effect.k);
        return effect;
    }

    range_effect parse_range(const table_reader& t, const scene_description& scene) const {
        auto effect = targeted_effect<range_effect>(t, scene, {"target", "queries_per_step", "half_extent"});
        effect.queries_per_step = t.required_count("queries_per_step", 1);
        effect.half_extent = t.required_number("half_extent");
        if (!(effect.half_extent > 0))
            t.fail_key("half_extent", "must be > 0 (got " + format_number(effect.half_extent) + ")");
        return effect;
    }

    churn_effect parse_churn(const table_reader& t, const scene_description& scene) const {
        auto effect = targeted_effect<churn_effect>(t, scene, {"target", "inserts_per_step", "erases_per_step"});
        if (scene.objects[effect.target].is_mesh())
            t.fail(position_of(t.node("target")->source()),
                   "'target' must be a generator set: churn draws new objects like the set's initial ones, "
                   "and '" + scene.objects[effect.target].name + "' is a mesh");
        effect.inserts_per_step = t.count("inserts_per_step", 0, 0);
        effect.erases_per_step = t.count("erases_per_step", 0, 0);
        if (effect.inserts_per_step == 0 && effect.erases_per_step == 0)
            t.fail(t.position(), "needs inserts_per_step or erases_per_step > 0 (otherwise it does nothing)");
        return effect;
    }

    collide_effect parse_collide(const table_reader& t, const scene_description& scene) const {
        t.allow_only({"between", "filter", "strategy"});
        collide_effect c;
        c.position = t.position();
        const auto* between = t.array("between");
        if (!between)
            t.fail(t.position(), "needs the key 'between': the pairs of sets to test, e.g. between = [[\"boxes\", "
                                 "\"boxes\"]] for the self pairs of one set");
        if (between->empty()) t.fail_key("between", "must list at least one pair of sets");
        for (const auto& element : *between) {
            const auto at = position_of(element.source());
            const auto* pair = element.as_array();
            if (!pair || pair->size() != 2)
                t.fail(at, "'between' element must be a pair of set names, e.g. [\"boxes\", \"walls\"]");
            const std::size_t a = set_index(t, *pair->get(0), "'between'", scene);
            const std::size_t b = set_index(t, *pair->get(1), "'between'", scene);
            for (const auto& [x, y] : c.between)
                if ((x == a && y == b) || (x == b && y == a))
                    t.fail(at, "'between' lists the pair ('" + scene.objects[a].name + "', '" + scene.objects[b].name +
                                   "') twice");
            c.between.emplace_back(a, b);
        }
        if (auto f = t.choice("filter", collide_filter_names)) c.filter = *f;
        if (auto s = t.choice("strategy", update_strategy_names)) c.strategy = *s;
        return c;
    }

    raycast_effect parse_raycast(const table_reader& t, const scene_description& scene) const {
        t.allow_only({"targets", "rays_per_step", "kind", "thickness", "eye", "look_at", "field_of_view"});
        raycast_effect r;
        r.position = t.position();
        if (const auto* targets = t.array("targets")) {
            if (targets->empty()) t.fail_key("targets", "must name at least one set (omit it to target every set)");
            for (const auto& element : *targets) {
                const std::size_t i = set_index(t, element, "'targets'", scene);
                if (std::find(r.targets.begin(), r.targets.end(), i) != r.targets.end())
                    t.fail(position_of(element.source()), "'targets' names '" + scene.objects[i].name + "' twice");
                r.targets.push_back(i);
            }
        } else {
            for (std::size_t i = 0; i < scene.objects.size(); ++i) r.targets.push_back(i);
        }
        r.rays_per_step = t.required_count("rays_per_step", 1);
        if (auto k = t.choice("kind", ray_kind_names)) r.kind = *k;
        if (auto v = t.number("thickness")) {
            if (!(*v >= 0)) t.fail_key("thickness", "must be >= 0 (got " + format_number(*v) + ")");
            r.thickness = *v;
        }
        if (r.thickness == 0)
            for (std::size_t i : r.targets)
                if (scene.objects[i].kind == object_kind::point)
                    t.fail(t.has("targets") ? t.key_position("targets") : t.position(),
                           "targets the point set '" + scene.objects[i].name +
                               "' with thickness = 0: a thin ray almost never hits a point; set thickness > 0 " +
                               (t.has("targets") ? "or leave the point set out" : "or list 'targets'"));
        if (r.kind == ray_kind::camera) {
            const std::size_t dim = scene.dimension;
            r.look_at = t.vector("look_at", dim).value_or(scene.domain_centre());
            double extent = 0;
            for (std::size_t d = 0; d < dim; ++d) extent = std::max(extent, scene.domain_hi[d] - scene.domain_lo[d]);
            r.eye = r.look_at;
            r.eye[1] -= 2 * extent;
            if (auto v = t.vector("eye", dim)) r.eye = *v;
            if (r.eye == r.look_at) t.fail_key("eye", "must differ from look_at (the camera needs a view direction)");
            if (auto v = t.number("field_of_view")) {
                if (!(*v > 0 && *v < 180)) t.fail_key("field_of_view", "must be in (0, 180) degrees");
                r.field_of_view = *v;
            }
        } else {
            for (auto key : {"eye", "look_at", "field_of_view"})
                t.forbid(key, "applies only to kind = \"camera\"");
        }
        return r;
    }

    std::string file_;
    std::filesystem::path directory_;
};

}  // namespace

scene_description parse_scene(std::string_view toml_text, std::string_view file_name) {
    scene_parser parser(file_name);
    toml::table root;
    try {
        root = toml::parse(toml_text, file_name);
    } catch (const toml::parse_error& e) {
        parser.fail(position_of(e.source()), "", "TOML syntax error: " + std::string(e.description()));
    }
    return parser.parse(root);
}

scene_description load_scene(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw scene_error(file.string() + ": cannot open the scene file");
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw scene_error(file.string() + ": cannot read the scene file");
    return parse_scene(text.str(), file.string());
}

// ---- writing ---------------------------------------------------------------------------------

namespace {

// A TOML basic string: quotes, backslash and control characters escaped. Not named "quoted":
// for a std::string argument, argument-dependent lookup would find std::quoted (<iomanip>, an
// exact match where this one needs a conversion to string_view), which escapes only the quote
// and the backslash, and a control character would be written raw (found by fuzzing).
std::string toml_string(std::string_view s) {
    std::string out = "\"";
    for (const char c : s) {
        switch (c) {
            case '"': out += "\\\""; break;
            case '\\': out += "\\\\"; break;
            case '\n': out += "\\n"; break;
            case '\t': out += "\\t"; break;
            case '\r': out += "\\r"; break;
            default:
                if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
                    char buffer[8];
                    std::snprintf(buffer, sizeof buffer, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
                    out += buffer;
                } else {
                    out += c;
                }
        }
    }
    return out + "\"";
}

std::string number(double v) { return format_number(v); }

std::string vector_text(const scene_vector& v, std::size_t size) {
    std::string out = "[";
    for (std::size_t i = 0; i < size; ++i) out += (i ? ", " : "") + number(v[i]);
    return out + "]";
}

}  // namespace

std::string to_toml(const scene_description& scene) {
    const std::size_t dim = scene.dimension;
    std::ostringstream out;
    const auto name_of = [&](std::size_t i) { return toml_string(scene.objects[i].name); };

    out << "[scene]\n";
    out << "name = " << toml_string(scene.name) << "\n";
    out << "description = " << toml_string(scene.description) << "\n";
    out << "dimension = " << dim << "\n";
    out << "scalar = " << toml_string(to_string(scene.scalar)) << "\n";
    out << "steps = " << scene.steps << "\n";
    out << "time_step = " << number(scene.time_step) << "\n";
    out << "seed = " << scene.seed << "\n";
    out << "domain = { lo = " << vector_text(scene.domain_lo, dim) << ", hi = " << vector_text(scene.domain_hi, dim)
        << " }\n";

    for (const auto& set : scene.objects) {
        out << "\n[[objects]]\n";
        out << "name = " << toml_string(set.name) << "\n";
        out << "kind = " << toml_string(to_string(set.kind)) << "\n";
        if (set.mesh) {
            const auto& m = *set.mesh;
            out << "mesh = " << toml_string(m.reference) << "\n";
            if (m.from == mesh_source::origin::generated) out << "triangles = " << m.triangles << "\n";
            out << "scale = " << number(m.scale) << "\n";
            out << "offset = " << vector_text(m.offset, 3) << "\n";
            out << "normalize = " << (m.normalize ? "true" : "false") << "\n";
            out << "split = " << toml_string(to_string(m.split)) << "\n";
        } else {
            const auto& g = *set.generator;
            out << "placement = " << toml_string(to_string(g.placement)) << "\n";
            out << "count = " << g.count << "\n";
            if (set.kind != object_kind::point) {
                out << "size = " << number(g.size) << "\n";
                out << "size_distribution = " << toml_string(to_string(g.sizes)) << "\n";
                if (g.sizes == size_distribution::heavy_tailed) out << "size_max = " << number(g.size_max) << "\n";
            }
        }
        const auto& m = set.motion;
        out << "motion = { kind = " << toml_string(to_string(m.kind));
        switch (m.kind) {
            case motion_kind::static_: break;
            case motion_kind::linear:
                out << ", speed = " << number(m.speed);
                if (m.direction) out << ", direction = " << vector_text(*m.direction, dim);
                break;
            case motion_kind::random_walk: out << ", speed = " << number(m.speed); break;
            case motion_kind::rigid_rotation:
                out << ", angular_speed = " << number(m.angular_speed);
                if (dim == 3) out << ", axis = " << vector_text(m.axis, 3);
                out << ", centre = " << vector_text(m.centre, dim);
                break;
        }
        out << " }\n";
    }

    if (scene.collide) {
        const auto& c = *scene.collide;
        out << "\n[effects.collide]\nbetween = [";
        for (std::size_t i = 0; i < c.between.size(); ++i)
            out << (i ? ", " : "") << "[" << name_of(c.between[i].first) << ", " << name_of(c.between[i].second) << "]";
        out << "]\n";
        out << "filter = " << toml_string(to_string(c.filter)) << "\n";
        out << "strategy = " << toml_string(to_string(c.strategy)) << "\n";
    }
    if (scene.raycast) {
        const auto& r = *scene.raycast;
        out << "\n[effects.raycast]\ntargets = [";
        for (std::size_t i = 0; i < r.targets.size(); ++i) out << (i ? ", " : "") << name_of(r.targets[i]);
        out << "]\n";
        out << "rays_per_step = " << r.rays_per_step << "\n";
        out << "kind = " << toml_string(to_string(r.kind)) << "\n";
        out << "thickness = " << number(r.thickness) << "\n";
        if (r.kind == ray_kind::camera) {
            out << "eye = " << vector_text(r.eye, dim) << "\n";
            out << "look_at = " << vector_text(r.look_at, dim) << "\n";
            out << "field_of_view = " << number(r.field_of_view) << "\n";
        }
    }
    if (scene.nearest) {
        const auto& n = *scene.nearest;
        out << "\n[effects.nearest]\ntarget = " << name_of(n.target) << "\n";
        out << "queries_per_step = " << n.queries_per_step << "\nk = " << n.k << "\n";
    }
    if (scene.range) {
        const auto& r = *scene.range;
        out << "\n[effects.range]\ntarget = " << name_of(r.target) << "\n";
        out << "queries_per_step = " << r.queries_per_step << "\nhalf_extent = " << number(r.half_extent) << "\n";
    }
    if (scene.churn) {
        const auto& c = *scene.churn;
        out << "\n[effects.churn]\ntarget = " << name_of(c.target) << "\n";
        out << "inserts_per_step = " << c.inserts_per_step << "\nerases_per_step = " << c.erases_per_step << "\n";
    }
    return out.str();
}

}  // namespace datasets
