// Scene files (datasets/scene.hpp and friends): every shipped scene parses and generates; a
// full example round-trips through to_toml; each kind of error names its file, line and column;
// generation is deterministic and its streams independent; motion keeps its promises (bounces
// stay in the domain, static never moves, rigid rotation preserves distances, random walks
// replay bit for bit); churn and query draws are reproducible.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <numeric>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "datasets/scene.hpp"
#include "datasets/scene_motion.hpp"
#include "datasets/scene_objects.hpp"
#include "datasets/scene_queries.hpp"

namespace {

namespace fs = std::filesystem;
using datasets::scene_description;
using datasets::scene_error;

// Lines joined by '\n': line k of the file is element k - 1, so tests can name lines exactly.
std::string lines_of(std::initializer_list<std::string_view> lines) {
    std::string out;
    for (auto l : lines) {
        out += l;
        out += '\n';
    }
    return out;
}

std::string error_of(const std::string& text, std::string_view file = "test.toml") {
    try {
        (void)datasets::parse_scene(text, file);
    } catch (const scene_error& e) {
        return e.what();
    }
    return "(no error)";
}

// "FILE:LINE:" prefix of an error message as a (line, column) pair.
std::pair<int, int> position_of(const std::string& message) {
    const auto a = message.find(':');
    const auto b = message.find(':', a + 1);
    const auto c = message.find(':', b + 1);
    if (a == std::string::npos || b == std::string::npos || c == std::string::npos) return {-1, -1};
    return {std::stoi(message.substr(a + 1, b - a - 1)), std::stoi(message.substr(b + 1, c - b - 1))};
}

// 1-based column of `needle` in `line`.
int column_of(std::string_view line, std::string_view needle) {
    return static_cast<int>(line.find(needle)) + 1;
}

#define EXPECT_ERROR_AT(text, line, column, fragment)                                              \
    do {                                                                                            \
        const std::string message_ = error_of(text);                                                \
        EXPECT_EQ(position_of(message_), std::make_pair(line, column)) << message_;                 \
        EXPECT_NE(message_.find(fragment), std::string::npos) << message_ << "\n  lacks: " << fragment; \
    } while (0)

// A small valid scene: one box set with exact self pairs.
const std::string minimal_scene = lines_of({
    "[scene]",                       // 1
    "dimension = 3",                 // 2
    "",                              // 3
    "[[objects]]",                   // 4
    "name = \"boxes\"",              // 5
    "kind = \"box\"",                // 6
    "count = 10",                    // 7
    "size = 0.1",                    // 8
    "",                              // 9
    "[effects.collide]",             // 10
    "between = [[\"boxes\", \"boxes\"]]",  // 11
});

// ---- shipped scenes --------------------------------------------------------------------------

std::vector<fs::path> shipped_scenes() {
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(SPATIAL_SCENES_DIR))
        if (entry.path().extension() == ".toml") files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    return files;
}

// Generates every set (mesh files aside), moves it one step, and draws one step of queries.
template <class T, std::size_t D>
void exercise(const scene_description& scene) {
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        const auto& set = scene.objects[i];
        if (set.mesh && set.mesh->from == datasets::mesh_source::origin::file) continue;
        datasets::with_object_type<T, D>(set.kind, [&](auto type) {
            using object = typename decltype(type)::type;
            auto objects = datasets::generate_objects<object>(scene, i);
            if (set.generator) {
                EXPECT_EQ(objects.size(), set.generator->count) << set.name;
            }
            EXPECT_FALSE(objects.empty()) << set.name;
            datasets::scene_motion<object> motion(scene, i, objects.size());
            EXPECT_EQ(motion.moves(), set.moves());
            motion.step(objects, scene.time_step);
            if (scene.churn && scene.churn->target == i) {
                const auto inserted = datasets::generate_churn_objects<object>(scene, 0);
                EXPECT_EQ(inserted.size(), scene.churn->inserts_per_step);
            }
        });
    }
    if (scene.raycast) {
        EXPECT_EQ((datasets::generate_rays<T, D>(scene, 0).size()), scene.raycast->rays_per_step);
    }
    if (scene.nearest) {
        EXPECT_EQ((datasets::generate_nearest_queries<T, D>(scene, 0).size()), scene.nearest->queries_per_step);
    }
    if (scene.range) {
        EXPECT_EQ((datasets::generate_range_queries<T, D>(scene, 0).size()), scene.range->queries_per_step);
    }
}

void exercise(const scene_description& scene) {
    const bool dbl = scene.scalar == datasets::scalar_kind::float64;
    if (scene.dimension == 3) dbl ? exercise<double, 3>(scene) : exercise<float, 3>(scene);
    else dbl ? exercise<double, 2>(scene) : exercise<float, 2>(scene);
}

TEST(scene_files, every_shipped_scene_parses_round_trips_and_generates) {
    const auto files = shipped_scenes();
    ASSERT_GE(files.size(), 7u);
    std::set<std::string> names;
    for (const auto& file : files) {
        SCOPED_TRACE(file.string());
        const scene_description scene = datasets::load_scene(file);
        EXPECT_EQ(scene.name, file.stem().string()) << "a shipped scene is named after its file";
        EXPECT_FALSE(scene.description.empty());
        EXPECT_TRUE(names.insert(scene.name).second);
        const std::string text = datasets::to_toml(scene);
        EXPECT_EQ(datasets::to_toml(datasets::parse_scene(text, file.string())), text);
        exercise(scene);
    }
}

TEST(scene_files, the_shipped_scenes_cover_the_effects_they_promise) {
    const auto load = [](const char* name) { return datasets::load_scene(fs::path(SPATIAL_SCENES_DIR) / name); };
    const auto camera = load("static_mesh_camera.toml");
    EXPECT_FALSE(camera.moves());
    EXPECT_TRUE(camera.raycast && camera.raycast->kind == datasets::ray_kind::camera);
    EXPECT_FALSE(camera.collide || camera.nearest || camera.range || camera.churn);

    const auto big = load("boxes_100k.toml");
    ASSERT_EQ(big.objects.size(), 1u);
    const auto& g = *big.objects[0].generator;
    EXPECT_EQ(g.count, 100000u);
    // ~2 overlaps per box: n (2s)^3 = 2 V.
    EXPECT_NEAR(static_cast<double>(g.count) * std::pow(2 * g.size, 3), 2.0, 0.05);
    EXPECT_TRUE(big.collide && big.collide->filter == datasets::collide_filter::exact);

    const auto flat = load("discs_2d.toml");
    EXPECT_EQ(flat.dimension, 2u);
    EXPECT_EQ(flat.scalar, datasets::scalar_kind::float32);
}

// ---- a full example --------------------------------------------------------------------------

const std::string full_scene = lines_of({
    "# every key of the format",
    "[scene]",
    "name = \"full\"",
    "description = \"all \\\"the\\\" keys\"",
    "dimension = 3",
    "scalar = \"float\"",
    "steps = 12",
    "time_step = 0.02",
    "seed = 1234567",
    "domain = { lo = [-1, -2, -3], hi = [1, 2.5, 3] }",
    "",
    "[[objects]]",
    "name = \"heavy\"",
    "kind = \"box\"",
    "placement = \"clusters\"",
    "count = 300",
    "size = 0.05",
    "size_distribution = \"heavy_tailed\"",
    "size_max = 0.3",
    "motion = { kind = \"linear\", speed = 2, direction = [0, 0, -3] }",
    "",
    "[[objects]]",
    "name = \"balls\"",
    "kind = \"sphere\"",
    "count = 50",
    "size = 0.1",
    "size_distribution = \"uniform\"",
    "[objects.motion]",
    "kind = \"random_walk\"",
    "speed = 0.25",
    "",
    "[[objects]]",
    "name = \"dust\"",
    "kind = \"point\"",
    "placement = \"lattice\"",
    "count = 64",
    "motion = { kind = \"rigid_rotation\", angular_speed = -1.5, axis = [1, 1, 0], centre = [0, 0.25, 0] }",
    "",
    "[[objects]]",
    "name = \"hull\"",
    "kind = \"triangle\"",
    "mesh = \"generated:soup\"",
    "triangles = 200",
    "scale = 0.5",
    "offset = [0.1, 0.2, 0.3]",
    "normalize = false",
    "split = \"triangles\"",
    "",
    "[[objects]]",
    "name = \"statue\"",
    "kind = \"triangle\"",
    "mesh = \"meshes/statue.off\"",
    "",
    "[effects.collide]",
    "between = [[\"heavy\", \"heavy\"], [\"heavy\", \"hull\"]]",
    "filter = \"candidates\"",
    "strategy = \"reinsert\"",
    "",
    "[effects.raycast]",
    "targets = [\"hull\", \"dust\"]",
    "rays_per_step = 100",
    "kind = \"camera\"",
    "thickness = 0.01",
    "eye = [0, -5, 0]",
    "look_at = [0, 0, 0.5]",
    "field_of_view = 30",
    "",
    "[effects.nearest]",
    "target = \"dust\"",
    "queries_per_step = 7",
    "k = 3",
    "",
    "[effects.range]",
    "target = \"balls\"",
    "queries_per_step = 9",
    "half_extent = 0.125",
    "",
    "[effects.churn]",
    "target = \"balls\"",
    "inserts_per_step = 4",
    "erases_per_step = 5",
});

TEST(scene_files, a_full_example_reads_every_key_and_round_trips) {
    const auto s = datasets::parse_scene(full_scene, "dir/full.toml");
    EXPECT_EQ(s.file, "dir/full.toml");
    EXPECT_EQ(s.name, "full");
    EXPECT_EQ(s.description, "all \"the\" keys");
    EXPECT_EQ(s.dimension, 3u);
    EXPECT_EQ(s.scalar, datasets::scalar_kind::float32);
    EXPECT_EQ(s.steps, 12u);
    EXPECT_EQ(s.time_step, 0.02);
    EXPECT_EQ(s.seed, 1234567u);
    EXPECT_EQ(s.domain_lo, (datasets::scene_vector{-1, -2, -3}));
    EXPECT_EQ(s.domain_hi, (datasets::scene_vector{1, 2.5, 3}));
    EXPECT_EQ(s.position.line, 2u);
    ASSERT_EQ(s.objects.size(), 5u);

    const auto& heavy = s.objects[0];
    EXPECT_EQ(heavy.position.line, 12u);
    EXPECT_EQ(heavy.kind, datasets::object_kind::box);
    ASSERT_TRUE(heavy.generator && !heavy.mesh);
    EXPECT_EQ(heavy.generator->placement, datasets::point_workload::clusters);
    EXPECT_EQ(heavy.generator->count, 300u);
    EXPECT_EQ(heavy.generator->size, 0.05);
    EXPECT_EQ(heavy.generator->sizes, datasets::size_distribution::heavy_tailed);
    EXPECT_EQ(heavy.generator->size_max, 0.3);
    EXPECT_EQ(heavy.motion.kind, datasets::motion_kind::linear);
    EXPECT_EQ(heavy.motion.speed, 2.0);
    ASSERT_TRUE(heavy.motion.direction);
    EXPECT_EQ(*heavy.motion.direction, (datasets::scene_vector{0, 0, -3}));  // as written
    EXPECT_EQ(heavy.motion.position.line, 20u);

    const auto& balls = s.objects[1];
    EXPECT_EQ(balls.generator->placement, datasets::point_workload::uniform);  // default
    EXPECT_EQ(balls.generator->sizes, datasets::size_distribution::uniform);
    EXPECT_EQ(balls.motion.kind, datasets::motion_kind::random_walk);
    EXPECT_EQ(balls.motion.speed, 0.25);
    EXPECT_EQ(balls.motion.position.line, 28u);

    const auto& dust = s.objects[2];
    EXPECT_EQ(dust.kind, datasets::object_kind::point);
    EXPECT_EQ(dust.generator->size, 0.0);
    EXPECT_EQ(dust.motion.kind, datasets::motion_kind::rigid_rotation);
    EXPECT_EQ(dust.motion.angular_speed, -1.5);
    EXPECT_EQ(dust.motion.axis, (datasets::scene_vector{1, 1, 0}));
    EXPECT_EQ(dust.motion.centre, (datasets::scene_vector{0, 0.25, 0}));

    const auto& hull = s.objects[3];
    ASSERT_TRUE(hull.mesh && !hull.generator);
    EXPECT_EQ(hull.mesh->from, datasets::mesh_source::origin::generated);
    EXPECT_EQ(hull.mesh->generator, "soup");
    EXPECT_EQ(hull.mesh->triangles, 200u);
    EXPECT_EQ(hull.mesh->scale, 0.5);
    EXPECT_EQ(hull.mesh->offset, (datasets::scene_vector{0.1, 0.2, 0.3}));
    EXPECT_FALSE(hull.mesh->normalize);
    EXPECT_EQ(hull.motion.kind, datasets::motion_kind::static_);
    EXPECT_EQ(hull.motion.position.line, hull.position.line);  // no motion table: the set's line

    const auto& statue = s.objects[4];
    ASSERT_TRUE(statue.mesh);
    EXPECT_EQ(statue.mesh->from, datasets::mesh_source::origin::file);
    EXPECT_EQ(statue.mesh->reference, "meshes/statue.off");
    EXPECT_EQ(statue.mesh->file, fs::path("dir/meshes/statue.off"));  // relative to the scene file
    EXPECT_TRUE(statue.mesh->normalize);
    EXPECT_EQ(statue.mesh->scale, 1.0);

    ASSERT_TRUE(s.collide);
    EXPECT_EQ(s.collide->between, (std::vector<std::pair<std::size_t, std::size_t>>{{0, 0}, {0, 3}}));
    EXPECT_EQ(s.collide->filter, datasets::collide_filter::candidates);
    EXPECT_EQ(s.collide->strategy, datasets::update_strategy::reinsert);
    EXPECT_EQ(s.collide->position.line, 54u);
    ASSERT_TRUE(s.raycast);
    EXPECT_EQ(s.raycast->targets, (std::vector<std::size_t>{3, 2}));
    EXPECT_EQ(s.raycast->rays_per_step, 100u);
    EXPECT_EQ(s.raycast->kind, datasets::ray_kind::camera);
    EXPECT_EQ(s.raycast->thickness, 0.01);
    EXPECT_EQ(s.raycast->eye, (datasets::scene_vector{0, -5, 0}));
    EXPECT_EQ(s.raycast->look_at, (datasets::scene_vector{0, 0, 0.5}));
    EXPECT_EQ(s.raycast->field_of_view, 30.0);
    ASSERT_TRUE(s.nearest);
    EXPECT_EQ(s.nearest->target, 2u);
    EXPECT_EQ(s.nearest->queries_per_step, 7u);
    EXPECT_EQ(s.nearest->k, 3u);
    ASSERT_TRUE(s.range);
    EXPECT_EQ(s.range->target, 1u);
    EXPECT_EQ(s.range->half_extent, 0.125);
    ASSERT_TRUE(s.churn);
    EXPECT_EQ(s.churn->target, 1u);
    EXPECT_EQ(s.churn->inserts_per_step, 4u);
    EXPECT_EQ(s.churn->erases_per_step, 5u);
    EXPECT_EQ(s.churn->position.line, 78u);

    // Round trip: the written form reads back to a description that writes the same text.
    const std::string text = datasets::to_toml(s);
    const auto again = datasets::parse_scene(text, "dir/full.toml");
    EXPECT_EQ(datasets::to_toml(again), text);
    EXPECT_EQ(again.objects[4].mesh->file, statue.mesh->file);
    EXPECT_EQ(again.description, s.description);
}

// Found by fuzzing (fuzz/scene_file, docs/fuzzing.md): a control character in a string (here a
// carriage return, written "\r" in the file) came out of to_toml unescaped, so the written
// scene did not parse. Every string field is written: the scene's name and description, a set
// name (also inside the collide pairs) and a mesh reference.
TEST(scene_files, to_toml_escapes_control_characters_in_every_string) {
    const std::string text = lines_of({
        "[scene]",
        R"(name = "a\rb")",
        R"(description = "c\u0001d\re")",
        "[[objects]]",
        R"(name = "f\rg")",
        R"(kind = "triangle")",
        R"(mesh = "h\ri.off")",
        "[effects.collide]",
        R"(between = [["f\rg", "f\rg"]])",
    });
    const scene_description s = datasets::parse_scene(text, "x.toml");
    ASSERT_EQ(s.description, "c\001d\re");
    const std::string written = datasets::to_toml(s);
    scene_description again;
    ASSERT_NO_THROW(again = datasets::parse_scene(written, "x.toml")) << written;
    EXPECT_EQ(again.name, s.name);
    EXPECT_EQ(again.description, s.description);
    EXPECT_EQ(again.objects.at(0).name, s.objects.at(0).name);
    EXPECT_EQ(again.objects.at(0).mesh->reference, s.objects.at(0).mesh->reference);
    EXPECT_EQ(datasets::to_toml(again), written);
}

TEST(scene_files, defaults_are_filled_in) {
    const auto s = datasets::parse_scene(minimal_scene, "some/where/minimal.toml");
    EXPECT_EQ(s.name, "minimal");  // the file's stem
    EXPECT_EQ(s.dimension, 3u);
    EXPECT_EQ(s.scalar, datasets::scalar_kind::float64);
    EXPECT_EQ(s.steps, 1u);
    EXPECT_EQ(s.time_step, 0.01);
    EXPECT_EQ(s.seed, 42u);
    EXPECT_EQ(s.domain_lo, (datasets::scene_vector{0, 0, 0}));
    EXPECT_EQ(s.domain_hi, (datasets::scene_vector{1, 1, 1}));
    const auto& g = *s.objects[0].generator;
    EXPECT_EQ(g.placement, datasets::point_workload::uniform);
    EXPECT_EQ(g.sizes, datasets::size_distribution::fixed);
    EXPECT_EQ(s.objects[0].motion.kind, datasets::motion_kind::static_);
    EXPECT_FALSE(s.moves());
    EXPECT_EQ(s.collide->filter, datasets::collide_filter::exact);
    EXPECT_EQ(s.collide->strategy, datasets::update_strategy::automatic);
    EXPECT_FALSE(s.raycast || s.nearest || s.range || s.churn);

    // raycast: every set by default; camera defaults look at the domain centre from -y.
    const auto r = datasets::parse_scene(
        minimal_scene + "[effects.raycast]\nrays_per_step = 5\nkind = \"camera\"\n", "m.toml");
    EXPECT_EQ(r.raycast->targets, (std::vector<std::size_t>{0}));
    EXPECT_EQ(r.raycast->look_at, (datasets::scene_vector{0.5, 0.5, 0.5}));
    EXPECT_EQ(r.raycast->eye, (datasets::scene_vector{0.5, -1.5, 0.5}));
    EXPECT_EQ(r.raycast->field_of_view, 45.0);
    EXPECT_EQ(r.raycast->thickness, 0.0);
}

TEST(scene_files, load_scene_reads_files_and_resolves_mesh_paths_against_their_directory) {
    const fs::path dir = fs::temp_directory_path() / "spatial_scene_file_test";
    fs::create_directories(dir);
    const fs::path file = dir / "on_disk.toml";
    {
        std::ofstream out(file);
        out << "[[objects]]\nname = \"m\"\nkind = \"triangle\"\nmesh = \"sub/x.off\"\n"
               "[effects.raycast]\nrays_per_step = 1\n";
    }
    const auto s = datasets::load_scene(file);
    EXPECT_EQ(s.file, file.string());
    EXPECT_EQ(s.name, "on_disk");
    EXPECT_EQ(s.objects[0].mesh->file, dir / "sub" / "x.off");
    fs::remove_all(dir);

    try {
        (void)datasets::load_scene(dir / "missing.toml");
        FAIL() << "no error for a missing file";
    } catch (const scene_error& e) {
        EXPECT_NE(std::string(e.what()).find("missing.toml: cannot open"), std::string::npos) << e.what();
    }
}

// ---- errors ----------------------------------------------------------------------------------

TEST(scene_errors, unknown_keys_are_errors_with_file_line_and_column) {
    const std::string text = minimal_scene + "filtr = \"exact\"\n";  // line 12
    EXPECT_EQ(error_of(text, "falling.toml"),
              "falling.toml:12:1: [effects.collide] unknown key 'filtr' (expected one of: between, filter, strategy)");

    // In [scene], in an object set (the first unknown key in file order), in an inline motion
    // table, in [scene.domain], at the top level and among the effects.
    EXPECT_ERROR_AT("[scene]\nsteps = 2\nstep = 3\n" + minimal_scene.substr(8), 3, 1,
                    "[scene] unknown key 'step' (expected one of: name, description, dimension, scalar, steps, "
                    "time_step, seed, domain)");
    EXPECT_ERROR_AT(lines_of({"[[objects]]", "name = \"b\"", "kind = \"box\"", "count = 1", "size = 1", "colour = 3",
                              "wieght = 1", "[effects.collide]", "between = [[\"b\", \"b\"]]"}),
                    6, 1, "[[objects]] unknown key 'colour'");
    const std::string motion_line = "motion = { kind = \"linear\", speed = 1, directoin = [1, 0, 0] }";
    EXPECT_ERROR_AT(lines_of({"[[objects]]", "name = \"b\"", "kind = \"box\"", "count = 1", "size = 1", motion_line,
                              "[effects.collide]", "between = [[\"b\", \"b\"]]"}),
                    6, column_of(motion_line, "directoin"), "[[objects]] 'b' motion unknown key 'directoin'");
    EXPECT_ERROR_AT("[scene]\ndomain = { lo = [0, 0, 0], high = [1, 1, 1] }\n" + minimal_scene.substr(8), 2,
                    column_of("domain = { lo = [0, 0, 0], high = [1, 1, 1] }", "high"),
                    "[scene.domain] unknown key 'high' (expected one of: lo, hi)");
    EXPECT_ERROR_AT(minimal_scene + "[effect.raycast]\nrays_per_step = 1\n", 12, 2,
                    "unknown key 'effect' (expected one of: scene, objects, effects)");
    EXPECT_ERROR_AT(minimal_scene + "[effects.raycasts]\nrays_per_step = 1\n", 12, 10,
                    "[effects] unknown key 'raycasts' (expected one of: collide, raycast, nearest, range, churn)");
}

TEST(scene_errors, wrong_types_name_the_key_and_its_line) {
    std::string text = minimal_scene;
    text.replace(text.find("count = 10"), 10, "count = \"ten\"");
    EXPECT_ERROR_AT(text, 7, 1, "[[objects]] 'boxes' 'count' must be an integer, not a string");

    text = minimal_scene;
    text.replace(text.find("size = 0.1"), 10, "size = [0.1]");
    EXPECT_ERROR_AT(text, 8, 1, "'size' must be a number, not an array");

    text = minimal_scene;
    text.replace(text.find("dimension = 3"), 13, "dimension = 3.0");
    EXPECT_ERROR_AT(text, 2, 1, "[scene] 'dimension' must be the integer 2 or 3, not a float");

    EXPECT_ERROR_AT(minimal_scene + "[effects.nearest]\ntarget = \"boxes\"\nqueries_per_step = 1\nk = true\n", 15, 1,
                    "[effects.nearest] 'k' must be an integer, not a boolean");
    EXPECT_ERROR_AT(minimal_scene + "[effects.churn]\ntarget = [\"boxes\"]\ninserts_per_step = 1\n", 13, 10,
                    "[effects.churn] 'target' must name an object set (a string), not an array");
    EXPECT_ERROR_AT("[scene]\ndomain = { lo = [0, \"0\", 0] }\n" + minimal_scene.substr(8), 2,
                    column_of("domain = { lo = [0, \"0\", 0] }", "\"0\""),
                    "'lo' element 2 must be a number, not a string");
    EXPECT_ERROR_AT("[scene]\ntime_step = inf\n" + minimal_scene.substr(8), 2, 1,
                    "'time_step' must be finite (got inf)");
    EXPECT_ERROR_AT(lines_of({"objects = 3", "[effects.collide]", "between = []"}), 1, 1,
                    "'objects' must be an array of tables");
}

TEST(scene_errors, bad_enum_values_list_the_valid_ones) {
    std::string text = minimal_scene;
    text.replace(text.find("kind = \"box\""), 12, "kind = \"cube\"");
    EXPECT_EQ(error_of(text),
              "test.toml:6:1: [[objects]] 'boxes' 'kind' has no value 'cube' (expected one of: point, box, sphere, "
              "triangle)");
    EXPECT_ERROR_AT(minimal_scene + "filter = \"approximate\"\n", 12, 1,
                    "'filter' has no value 'approximate' (expected one of: candidates, exact)");
    EXPECT_ERROR_AT(minimal_scene + "strategy = \"lazy\"\n", 12, 1,
                    "(expected one of: automatic, refit, rebuild, reinsert)");
    text = minimal_scene;
    text.replace(text.find("count = 10"), 10, "count = 10\nplacement = \"gaussian\"");
    EXPECT_ERROR_AT(text, 8, 1,
                    "'placement' has no value 'gaussian' (expected one of: uniform, clusters, sphere, plane, line, "
                    "lattice, duplicates, clusters_far)");
    EXPECT_ERROR_AT("[scene]\nscalar = \"half\"\n" + minimal_scene.substr(8), 2, 1,
                    "'scalar' has no value 'half' (expected one of: float, double)");
    EXPECT_ERROR_AT(minimal_scene + "[effects.raycast]\nrays_per_step = 1\nkind = \"laser\"\n", 14, 1,
                    "'kind' has no value 'laser' (expected one of: random, camera)");
    text = minimal_scene;
    text.replace(text.find("size = 0.1"), 10, "size = 0.1\nmotion = { kind = \"spin\" }");
    EXPECT_ERROR_AT(text, 9, column_of("motion = { kind = \"spin\" }", "kind"),
                    "'kind' has no value 'spin' (expected one of: static, linear, random_walk, rigid_rotation)");
}

TEST(scene_errors, effects_must_name_existing_sets) {
    const std::string between = "between = [[\"boxes\", \"walls\"]]";
    std::string text = minimal_scene;
    text.replace(text.find("between = [[\"boxes\", \"boxes\"]]"), 30, between);
    EXPECT_EQ(error_of(text), "test.toml:11:" + std::to_string(column_of(between, "\"walls\"")) +
                                  ": [effects.collide] 'between' names no object set 'walls' (the sets are: 'boxes')");
    EXPECT_ERROR_AT(minimal_scene + "[effects.nearest]\ntarget = \"box\"\nqueries_per_step = 1\n", 13, 10,
                    "'target' names no object set 'box'");
    const std::string targets = "targets = [\"boxes\", \"ghosts\"]";
    EXPECT_ERROR_AT(minimal_scene + "[effects.raycast]\n" + targets + "\nrays_per_step = 1\n", 13,
                    column_of(targets, "\"ghosts\""), "'targets' names no object set 'ghosts'");
    EXPECT_ERROR_AT(minimal_scene + "[effects.range]\nqueries_per_step = 1\nhalf_extent = 0.1\n", 12, 1,
                    "[effects.range] needs the key 'target'");
    // A pair listed twice (in either order), a malformed pair.
    text = minimal_scene;
    text.replace(text.find("between = [[\"boxes\", \"boxes\"]]"), 30,
                 "between = [[\"boxes\", \"boxes\"],\n  [\"boxes\", \"boxes\"]]");
    EXPECT_ERROR_AT(text, 12, 3, "'between' lists the pair ('boxes', 'boxes') twice");
    text = minimal_scene;
    text.replace(text.find("between = [[\"boxes\", \"boxes\"]]"), 30, "between = [\"boxes\"]");
    EXPECT_ERROR_AT(text, 11, 12, "'between' element must be a pair of set names");
}

TEST(scene_errors, toml_syntax_errors_cite_the_line) {
    std::string text = minimal_scene;
    text.replace(text.find("size = 0.1"), 10, "size = ");
    const std::string message = error_of(text);
    EXPECT_EQ(position_of(message).first, 8) << message;
    EXPECT_NE(message.find("test.toml:8:"), std::string::npos) << message;
    EXPECT_NE(message.find("TOML syntax error"), std::string::npos) << message;

    text = minimal_scene + "between = [[\"boxes\", \"boxes\"]]\n";  // a key defined twice
    EXPECT_EQ(position_of(error_of(text)).first, 12) << error_of(text);
}

TEST(scene_errors, out_of_range_and_inconsistent_values) {
    auto with = [](std::string_view from, std::string_view to) {
        std::string text = minimal_scene;
        text.replace(text.find(from), from.size(), to);
        return text;
    };
    EXPECT_ERROR_AT(with("dimension = 3", "dimension = 4"), 2, 1, "'dimension' must be 2 or 3 (got 4)");
    EXPECT_ERROR_AT(with("count = 10", "count = 0"), 7, 1, "'count' must be in [1, 4294967295] (got 0)");
    EXPECT_ERROR_AT(with("size = 0.1", "size = -0.1"), 8, 1, "'size' must be > 0 (got -0.1)");
    EXPECT_ERROR_AT(with("dimension = 3", "steps = 0"), 2, 1, "'steps' must be in [1, 4294967295] (got 0)");
    EXPECT_ERROR_AT(with("dimension = 3", "time_step = 0"), 2, 1, "'time_step' must be > 0 seconds");
    EXPECT_ERROR_AT(with("dimension = 3", "seed = -1"), 2, 1, "'seed' must be in [0, 9223372036854775807]");
    EXPECT_ERROR_AT(with("dimension = 3", "domain = { lo = [0, 0, 0], hi = [1, 0, 1] }"), 2,
                    column_of("domain = { lo = [0, 0, 0], hi = [1, 0, 1] }", "{"),
                    "[scene.domain] needs lo < hi on every axis (axis 1: lo = 0.0, hi = 0.0)");
    EXPECT_ERROR_AT(with("dimension = 3", "dimension = 2\ndomain = { lo = [0, 0, 0] }"), 3,
                    column_of("domain = { lo = [0, 0, 0] }", "lo"),
                    "'lo' must be an array of 2 numbers (one per axis), not of 3");
    EXPECT_ERROR_AT(with("size = 0.1", "size = 0.1\nsize_max = 1"), 9, 1,
                    "'size_max' applies only to size_distribution = \"heavy_tailed\"");
    EXPECT_ERROR_AT(with("size = 0.1", "size = 0.1\nsize_distribution = \"heavy_tailed\"\nsize_max = 0.05"), 10, 1,
                    "'size_max' must be >= size (0.1)");
    EXPECT_ERROR_AT(with("kind = \"box\"", "kind = \"point\""), 8, 1, "[[objects]] 'boxes' 'size' does not apply to points");
    EXPECT_ERROR_AT(with("size = 0.1", "size = 0.1\nscale = 2"), 9, 1,
                    "'scale' applies only to mesh sets (with mesh = \"...\")");
    EXPECT_ERROR_AT(with("size = 0.1", ""), 4, 1, "[[objects]] 'boxes' needs the key 'size'");
    EXPECT_ERROR_AT(with("name = \"boxes\"\n", ""), 4, 1, "[[objects]] needs the key 'name'");
    EXPECT_ERROR_AT(minimal_scene + "[effects.churn]\ntarget = \"boxes\"\n", 12, 1,
                    "needs inserts_per_step or erases_per_step > 0");
    EXPECT_ERROR_AT(minimal_scene + "[effects.range]\ntarget = \"boxes\"\nqueries_per_step = 3\nhalf_extent = 0\n",
                    15, 1, "'half_extent' must be > 0");
    EXPECT_ERROR_AT(minimal_scene + "[effects.raycast]\nrays_per_step = 1\nkind = \"camera\"\nfield_of_view = 180\n",
                    15, 1, "'field_of_view' must be in (0, 180) degrees");
    EXPECT_ERROR_AT(minimal_scene + "[effects.raycast]\nrays_per_step = 1\neye = [0, 0, 0]\n", 14, 1,
                    "'eye' applies only to kind = \"camera\"");
}

TEST(scene_errors, set_names_are_unique_and_scenes_need_sets_and_effects) {
    const std::string text = lines_of({
        "[[objects]]",     // 1
        "name = \"a\"",    // 2
        "kind = \"point\"",  // 3
        "count = 1",       // 4
        "[[objects]]",     // 5
        "name = \"a\"",    // 6
        "kind = \"box\"",  // 7
        "count = 1",       // 8
        "size = 1",        // 9
        "[effects.nearest]",
        "target = \"a\"",
        "queries_per_step = 1",
    });
    EXPECT_ERROR_AT(text, 6, 1, "[[objects]] 'name' 'a' is already the name of the set at line 1");
    EXPECT_ERROR_AT(lines_of({"[scene]", "steps = 3"}), 1, 1,
                    "the scene has no object set: add at least one [[objects]] table");
    EXPECT_ERROR_AT(minimal_scene.substr(0, minimal_scene.find("[effects")), 1, 1, "the scene asks for no effect");
}

TEST(scene_errors, meshes_and_motions_are_checked_against_the_dimension_and_kind) {
    const std::string flat_mesh = lines_of({
        "[scene]",
        "dimension = 2",
        "[[objects]]",
        "name = \"m\"",
        "kind = \"triangle\"",
        "mesh = \"generated:sphere\"",  // 6
        "triangles = 100",
        "[effects.raycast]",
        "rays_per_step = 1",
    });
    EXPECT_ERROR_AT(flat_mesh, 6, 1, "'mesh' needs a 3D scene (meshes are 3D; this scene has dimension = 2)");
    std::string text = minimal_scene;
    text.replace(text.find("count = 10\nsize = 0.1"), 21, "mesh = \"generated:sphere\"\ntriangles = 10");
    EXPECT_ERROR_AT(text, 7, 1, "'mesh' needs kind = \"triangle\"");
    text.replace(text.find("kind = \"box\""), 12, "kind = \"triangle\"");
    text.replace(text.find("generated:sphere"), 16, "generated:torus");
    EXPECT_ERROR_AT(text, 7, 1, "'mesh' names no mesh generator 'torus'");
    text.replace(text.find("generated:torus"), 15, "file.off");
    EXPECT_ERROR_AT(text, 8, 1, "'triangles' applies only to generated meshes");
    text.replace(text.find("triangles = 10"), 14, "count = 10");
    EXPECT_ERROR_AT(text, 8, 1, "'count' does not apply to a mesh set");

    const std::string rotating_2d = lines_of({
        "[scene]",
        "dimension = 2",
        "[[objects]]",
        "name = \"d\"",
        "kind = \"sphere\"",
        "count = 3",
        "size = 0.1",
        "motion = { kind = \"rigid_rotation\", angular_speed = 1, axis = [0, 0, 1] }",  // 8
        "[effects.collide]",
        "between = [[\"d\", \"d\"]]",
    });
    EXPECT_ERROR_AT(rotating_2d, 8, column_of("motion = { kind = \"rigid_rotation\", angular_speed = 1, axis", "axis"),
                    "'axis' is not used in a 2D scene (rotations turn in the plane");
    text = rotating_2d;
    text.replace(text.find(", axis = [0, 0, 1]"), 18, "");
    const auto ok = datasets::parse_scene(text, "r.toml");
    EXPECT_EQ(ok.objects[0].motion.centre, (datasets::scene_vector{0.5, 0.5, 0}));

    // A bad motion table added to the minimal scene's set (line 9): the error points at `key`.
    const struct {
        std::string_view motion, key, message;
    } bad_motions[] = {
        {"motion = { kind = \"static\", speed = 1 }", "speed",
         "'speed' does not apply to motion kind 'static' (only to linear and random_walk)"},
        {"motion = { kind = \"linear\" }", "{", "motion needs the key 'speed'"},
        {"motion = { kind = \"linear\", speed = 1, direction = [0, 0, 0] }", "direction",
         "'direction' must be a non-zero vector"},
        {"motion = { kind = \"random_walk\", speed = -1 }", "speed", "'speed' must be >= 0"},
    };
    for (const auto& bad : bad_motions) {
        SCOPED_TRACE(bad.motion);
        text = minimal_scene;
        text.replace(text.find("size = 0.1"), 10, "size = 0.1\n" + std::string(bad.motion));
        EXPECT_ERROR_AT(text, 9, column_of(bad.motion, bad.key), bad.message);
    }
}

TEST(scene_errors, effect_specific_checks) {
    const std::string points = lines_of({
        "[[objects]]",
        "name = \"p\"",
        "kind = \"point\"",
        "count = 5",
        "[effects.raycast]",  // 5
        "rays_per_step = 10",
    });
    EXPECT_ERROR_AT(points, 5, 1, "targets the point set 'p' with thickness = 0");
    EXPECT_NO_THROW((void)datasets::parse_scene(points + "thickness = 0.01\n", "p.toml"));

    const std::string churned_mesh = lines_of({
        "[[objects]]",
        "name = \"m\"",
        "kind = \"triangle\"",
        "mesh = \"generated:soup\"",
        "triangles = 10",
        "[effects.churn]",
        "target = \"m\"",  // 7
        "inserts_per_step = 1",
    });
    EXPECT_ERROR_AT(churned_mesh, 7, 10, "'target' must be a generator set");
}

// ---- generation ------------------------------------------------------------------------------

// One of the twin scene's two box sets: the same keys whatever the name.
std::string twin_box_set(std::string_view name) {
    const std::string name_line = "name = \"" + std::string(name) + "\"";
    return lines_of({"[[objects]]", name_line, "kind = \"box\"", "count = 500", "size = 0.05", "size_distribution = \"uniform\""});
}

// Two sets with the same keys (different names), plus a triangle set and a point set.
const std::string twin_scene = lines_of({
    "[scene]",
    "seed = 99",
    "domain = { lo = [-2, 0, 0], hi = [2, 1, 3] }",
}) + twin_box_set("a") + twin_box_set("b") + lines_of({
    "[[objects]]",
    "name = \"t\"",
    "kind = \"triangle\"",
    "placement = \"sphere\"",
    "count = 300",
    "size = 0.1",
    "[[objects]]",
    "name = \"s\"",
    "kind = \"sphere\"",
    "placement = \"clusters\"",
    "count = 300",
    "size = 0.02",
    "size_distribution = \"heavy_tailed\"",
    "[[objects]]",
    "name = \"p\"",
    "kind = \"point\"",
    "count = 300",
    "[effects.collide]",
    "between = [[\"a\", \"b\"]]",
});

template <class V>
bool bit_identical(const V& x, const V& y) {
    return x.size() == y.size() &&
           std::memcmp(x.data(), y.data(), x.size() * sizeof(typename V::value_type)) == 0;
}

template <class Object>
void expect_deterministic(const scene_description& scene, std::size_t set) {
    const auto first = datasets::generate_objects<Object>(scene, set);
    const auto second = datasets::generate_objects<Object>(datasets::parse_scene(datasets::to_toml(scene), "x"), set);
    EXPECT_TRUE(bit_identical(first, second)) << scene.objects[set].name;
}

TEST(scene_generation, same_seed_gives_bit_identical_objects) {
    const auto scene = datasets::parse_scene(twin_scene, "twins.toml");
    using namespace spatial::objects;
    expect_deterministic<box<double, 3>>(scene, 0);
    expect_deterministic<box<float, 3>>(scene, 1);
    expect_deterministic<triangle<double, 3>>(scene, 2);
    expect_deterministic<sphere<float, 3>>(scene, 3);
    expect_deterministic<spatial::point<double, 3>>(scene, 4);
}

TEST(scene_generation, each_set_and_seed_reads_its_own_streams) {
    auto scene = datasets::parse_scene(twin_scene, "twins.toml");
    using box = spatial::objects::box<double, 3>;
    const auto a = datasets::generate_objects<box>(scene, 0);
    const auto b = datasets::generate_objects<box>(scene, 1);  // same keys, set index 1
    ASSERT_EQ(a.size(), b.size());
    std::size_t equal = 0;
    for (std::size_t i = 0; i < a.size(); ++i) equal += a[i] == b[i];
    EXPECT_EQ(equal, 0u);

    // Another seed changes everything; the other sets do not change set 0 (drop them).
    auto reseeded = scene;
    reseeded.seed = 100;
    EXPECT_FALSE(bit_identical(a, datasets::generate_objects<box>(reseeded, 0)));
    auto alone = scene;
    alone.objects.resize(1);
    EXPECT_TRUE(bit_identical(a, datasets::generate_objects<box>(alone, 0)));
}

// Pinned output: changing a generator changes every recorded benchmark input, so it must be
// deliberate (update these values in the same change).
std::uint64_t fnv1a(const void* data, std::size_t bytes) {
    std::uint64_t h = 0xcbf29ce484222325ull;
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 0x100000001b3ull;
    return h;
}

TEST(scene_generation, pinned_fingerprints) {
    const auto scene = datasets::parse_scene(twin_scene, "twins.toml");
    const auto boxes = datasets::generate_objects<spatial::objects::box<double, 3>>(scene, 0);
    const auto tris = datasets::generate_objects<spatial::objects::triangle<float, 3>>(scene, 2);
    const auto spheres = datasets::generate_objects<spatial::objects::sphere<double, 3>>(scene, 3);
    EXPECT_EQ(fnv1a(boxes.data(), boxes.size() * sizeof(boxes[0])), 0xb91cb6510a306d03ull);
    EXPECT_EQ(fnv1a(tris.data(), tris.size() * sizeof(tris[0])), 0x609b115374122abfull);
    EXPECT_EQ(fnv1a(spheres.data(), spheres.size() * sizeof(spheres[0])), 0xa22a5656df3190c5ull);
}

TEST(scene_generation, objects_start_inside_the_domain_with_the_promised_sizes) {
    const auto scene = datasets::parse_scene(twin_scene, "twins.toml");
    const auto inside = [&](const double* lo, const double* hi) {
        for (std::size_t d = 0; d < 3; ++d)
            if (lo[d] < scene.domain_lo[d] || hi[d] > scene.domain_hi[d]) return false;
        return true;
    };
    for (const auto& b : datasets::generate_objects<spatial::objects::box<double, 3>>(scene, 0)) {
        EXPECT_TRUE(inside(b.lo.data(), b.hi.data()));
        const double edge = b.hi[0] - b.lo[0];
        EXPECT_GE(edge, 0.025 - 1e-12);
        EXPECT_LT(edge, 0.075 + 1e-12);
        EXPECT_NEAR(b.hi[1] - b.lo[1], edge, 1e-12);  // cubes
    }
    for (const auto& t : datasets::generate_objects<spatial::objects::triangle<double, 3>>(scene, 2)) {
        EXPECT_TRUE(inside(t.get_min_bound(), t.get_max_bound()));
        // The circumcentre is equidistant (size) from the three vertices: check via the centroid
        // being within the circumradius, and each edge at most the diameter.
        for (int k = 0; k < 3; ++k) {
            double e2 = 0;
            for (std::size_t d = 0; d < 3; ++d) e2 += std::pow(t.vertex(k)[d] - t.vertex((k + 1) % 3)[d], 2);
            EXPECT_LE(std::sqrt(e2), 0.2 + 1e-12);
        }
    }

    // Heavy-tailed radii: Pareto(alpha = 2, x_m = size / 2) clamped to 10 size; mean 0.975 size.
    auto big = scene;
    big.objects[3].generator->count = 200000;
    const auto spheres = datasets::generate_objects<spatial::objects::sphere<double, 3>>(big, 3);
    double sum = 0, largest = 0, smallest = 1;
    for (const auto& s : spheres) {
        sum += s.radius();
        largest = std::max(largest, s.radius());
        smallest = std::min(smallest, s.radius());
    }
    EXPECT_GE(smallest, 0.01);
    EXPECT_EQ(largest, 0.2);  // the cap is reached (P = 0.25% per object)
    EXPECT_NEAR(sum / static_cast<double>(spheres.size()), 0.975 * 0.02, 0.02 * 0.02);
}

TEST(scene_generation, mesh_sets_are_normalised_scaled_and_offset_keeping_shared_vertices) {
    datasets::triangle_mesh mesh;
    mesh.vertices = {{{0, 0, 0}}, {{2, 0, 0}}, {{0, 1, 0}}, {{2, 1, 1}}};
    mesh.triangles = {{0, 1, 2}, {1, 3, 2}};
    datasets::mesh_source source;
    source.reference = "test mesh";
    source.scale = 2;
    source.offset = {1, 1, 1};
    const auto tris = datasets::mesh_objects<double>(mesh, source);
    ASSERT_EQ(tris.size(), 2u);
    // Normalised: x in [0, 1], y in [0.25, 0.75], z in [0.25, 0.75]; then 1 + 2 * that.
    EXPECT_EQ(tris[0].vertex(0), (spatial::point<double, 3>{{1, 1.5, 1.5}}));
    EXPECT_EQ(tris[0].vertex(1), (spatial::point<double, 3>{{3, 1.5, 1.5}}));
    EXPECT_EQ(tris[1].vertex(1), (spatial::point<double, 3>{{3, 2.5, 2.5}}));
    EXPECT_EQ(tris[0].vertex(1), tris[1].vertex(0));  // shared vertex, bit for bit
    source.normalize = false;
    EXPECT_EQ(datasets::mesh_objects<double>(mesh, source)[1].vertex(1), (spatial::point<double, 3>{{5, 3, 3}}));
    EXPECT_THROW((void)datasets::mesh_objects<double>(datasets::triangle_mesh{}, source), std::invalid_argument);

    // A generated mesh set, and the errors for a file set or a mismatched object type.
    const auto scene = datasets::parse_scene(full_scene, "dir/full.toml");
    const auto soup = datasets::generate_objects<spatial::objects::triangle<float, 3>>(scene, 3);
    EXPECT_EQ(soup.size(), 200u);
    using tri3 = spatial::objects::triangle<float, 3>;
    using box3 = spatial::objects::box<float, 3>;
    using box2 = spatial::objects::box<float, 2>;
    EXPECT_THROW((void)datasets::generate_objects<tri3>(scene, 4), std::invalid_argument);  // a mesh file
    EXPECT_THROW((void)datasets::generate_objects<box3>(scene, 3), std::invalid_argument);  // wrong kind
    EXPECT_THROW((void)datasets::generate_objects<box2>(scene, 0), std::invalid_argument);  // wrong dimension
}

// ---- motion ----------------------------------------------------------------------------------

std::string moving_scene(std::string_view dimension_line, std::string_view set_lines) {
    return "[scene]\n" + std::string(dimension_line) + "\nseed = 5\n[[objects]]\nname = \"x\"\n" +
           std::string(set_lines) + "\n[effects.collide]\nbetween = [[\"x\", \"x\"]]\n";
}

template <class Object>
void expect_stays_inside(const scene_description& scene, std::size_t steps, double tolerance) {
    auto objects = datasets::generate_objects<Object>(scene, 0);
    datasets::scene_motion<Object> motion(scene, 0, objects.size());
    ASSERT_TRUE(motion.moves());
    const auto initial = objects;
    std::size_t outside = 0;
    for (std::size_t s = 0; s < steps; ++s) {
        motion.step(objects, scene.time_step);
        for (const auto& o : objects)
            for (std::size_t d = 0; d < Object::dimension; ++d)
                if (o.get_min_bound()[d] < scene.domain_lo[d] - tolerance ||
                    o.get_max_bound()[d] > scene.domain_hi[d] + tolerance)
                    ++outside;
    }
    EXPECT_EQ(outside, 0u);
    EXPECT_FALSE(bit_identical(initial, objects));
}

// moving_scene(dimension_line, set_lines), parsed as `file`, whose objects stay inside.
template <class Object>
scene_description expect_moving_scene_stays_inside(std::string_view dimension_line, std::string_view set_lines,
                                                   std::string_view file, std::size_t steps, double tolerance) {
    SCOPED_TRACE(file);
    const auto scene = datasets::parse_scene(moving_scene(dimension_line, set_lines), file);
    expect_stays_inside<Object>(scene, steps, tolerance);
    return scene;
}

TEST(scene_motion, linear_motion_bounces_and_stays_in_the_domain) {
    // Fast boxes (each crosses the domain in 50 steps): 500 steps means ~10 bounces each.
    const auto boxes = expect_moving_scene_stays_inside<spatial::objects::box<double, 3>>(
        "dimension = 3",
        "kind = \"box\"\ncount = 400\nsize = 0.05\nsize_distribution = \"heavy_tailed\"\n"
        "motion = { kind = \"linear\", speed = 2 }",
        "b.toml", 500, 1e-12);

    // Speeds are preserved by bounces (only signs flip).
    auto objects = datasets::generate_objects<spatial::objects::box<double, 3>>(boxes, 0);
    datasets::scene_motion<spatial::objects::box<double, 3>> motion(boxes, 0, objects.size());
    const auto v0 = motion.velocity(7);
    for (int s = 0; s < 200; ++s) motion.step(objects, boxes.time_step);
    const auto v1 = motion.velocity(7);
    for (std::size_t d = 0; d < 3; ++d) EXPECT_EQ(std::abs(v0[d]), std::abs(v1[d]));
    EXPECT_NEAR(std::hypot(v0[0], v0[1], v0[2]), 2.0, 1e-12);

    // 2D float discs in a non-unit domain.
    expect_moving_scene_stays_inside<spatial::objects::sphere<float, 2>>(
        "dimension = 2\ndomain = { lo = [-1, 2], hi = [0, 2.5] }",
        "kind = \"sphere\"\ncount = 300\nsize = 0.01\nmotion = { kind = \"linear\", speed = 3 }", "d.toml", 500,
        1e-5);

    // A mesh moves as one body: every triangle gets the same displacement, and the mesh's box
    // bounces (it stays inside though it starts touching the walls).
    expect_moving_scene_stays_inside<spatial::objects::triangle<double, 3>>(
        "dimension = 3",
        "kind = \"triangle\"\nmesh = \"generated:sphere\"\ntriangles = 200\nscale = 0.5\n"
        "offset = [0.25, 0.25, 0.25]\nmotion = { kind = \"linear\", speed = 3 }",
        "m.toml", 300, 1e-12);
}

TEST(scene_motion, static_motion_is_a_detectable_no_op) {
    const auto scene = datasets::parse_scene(minimal_scene, "s.toml");
    using box = spatial::objects::box<double, 3>;
    auto objects = datasets::generate_objects<box>(scene, 0);
    const auto before = objects;
    datasets::scene_motion<box> motion(scene, 0, objects.size());
    EXPECT_FALSE(motion.moves());
    EXPECT_FALSE(scene.moves());
    for (int s = 0; s < 10; ++s) motion.step(objects, scene.time_step);
    EXPECT_TRUE(bit_identical(before, objects));
}

template <class T>
double distance(const spatial::point<T, 3>& a, const spatial::point<T, 3>& b) {
    double s = 0;
    for (std::size_t d = 0; d < 3; ++d) s += std::pow(static_cast<double>(a[d]) - static_cast<double>(b[d]), 2);
    return std::sqrt(s);
}

TEST(scene_motion, rigid_rotation_preserves_distances_and_closes_a_full_turn) {
    // 100 steps of 2 pi / 100 radians: one full turn about an oblique axis.
    const double omega = 2 * 3.14159265358979323846 / (100 * 0.01);
    const auto scene = datasets::parse_scene(
        moving_scene("dimension = 3",
                     "kind = \"triangle\"\nmesh = \"generated:sphere\"\ntriangles = 300\nscale = 0.3\n"
                     "motion = { kind = \"rigid_rotation\", angular_speed = " +
                         std::to_string(omega) + ", axis = [1, 2, 3], centre = [0.5, 0.4, 0.6] }"),
        "r.toml");
    using tri = spatial::objects::triangle<double, 3>;
    auto objects = datasets::generate_objects<tri>(scene, 0);
    const auto initial = objects;
    datasets::scene_motion<tri> motion(scene, 0, objects.size());
    double worst = 0, moved = 0;
    for (int s = 0; s < 100; ++s) {
        motion.step(objects, scene.time_step);
        for (std::size_t i = 0; i < objects.size(); i += 7) {
            const std::size_t j = (i * 31 + 5) % objects.size();  // a far triangle too
            for (int k = 0; k < 3; ++k) {
                worst = std::max(worst, std::abs(distance(objects[i].vertex(k), objects[i].vertex((k + 1) % 3)) -
                                                 distance(initial[i].vertex(k), initial[i].vertex((k + 1) % 3))));
                worst = std::max(worst, std::abs(distance(objects[i].vertex(k), objects[j].vertex(k)) -
                                                 distance(initial[i].vertex(k), initial[j].vertex(k))));
            }
            if (s == 24) moved = std::max(moved, distance(objects[i].vertex(0), initial[i].vertex(0)));
        }
    }
    EXPECT_LT(worst, 1e-12);
    EXPECT_GT(moved, 0.05);  // a quarter turn really moved the mesh
    // The omega written with 6 decimals is not exactly 2 pi: back within 1e-5 after a turn.
    for (std::size_t i = 0; i < objects.size(); ++i)
        for (int k = 0; k < 3; ++k) EXPECT_LT(distance(objects[i].vertex(k), initial[i].vertex(k)), 1e-5);

    // 2D: boxes and points turn about the centre; a box stays a box of the same size.
    const auto flat = datasets::parse_scene(
        moving_scene("dimension = 2",
                     "kind = \"box\"\ncount = 50\nsize = 0.01\n"
                     "motion = { kind = \"rigid_rotation\", angular_speed = 1.5707963267948966 }"),
        "f.toml");
    using box2 = spatial::objects::box<double, 2>;
    auto boxes = datasets::generate_objects<box2>(flat, 0);
    const auto start = boxes;
    datasets::scene_motion<box2> turn(flat, 0, boxes.size());
    for (int s = 0; s < 100; ++s) turn.step(boxes, flat.time_step);  // a quarter turn in total
    for (std::size_t i = 0; i < boxes.size(); ++i) {
        const auto c0 = start[i].center(), c1 = boxes[i].center();
        EXPECT_NEAR(c1[0] - 0.5, -(c0[1] - 0.5), 1e-12);  // (x, y) -> (-y, x) about the centre
        EXPECT_NEAR(c1[1] - 0.5, c0[0] - 0.5, 1e-12);
        EXPECT_NEAR(boxes[i].hi[0] - boxes[i].lo[0], 0.01, 1e-12);
    }
}

TEST(scene_motion, random_walk_is_reproducible_and_bounces) {
    const std::string text = moving_scene(
        "dimension = 3", "kind = \"point\"\ncount = 2000\nplacement = \"clusters\"\nmotion = { kind = \"random_walk\", speed = 5 }");
    const auto scene = datasets::parse_scene(text, "w.toml");
    using point = spatial::point<float, 3>;
    const auto run = [](const scene_description& s, int steps) {
        auto objects = datasets::generate_objects<point>(s, 0);
        datasets::scene_motion<point> motion(s, 0, objects.size());
        for (int i = 0; i < steps; ++i) motion.step(objects, s.time_step);
        return objects;
    };
    const auto a = run(scene, 50), b = run(scene, 50);
    EXPECT_TRUE(bit_identical(a, b));
    auto reseeded = scene;
    reseeded.seed = 6;
    EXPECT_FALSE(bit_identical(a, run(reseeded, 50)));
    // RMS displacement per axis per step: speed * dt = 0.05; walls reflect, so after many steps
    // every point is inside (the clusters may start up to 0.072 outside the unit cube).
    std::size_t outside = 0;
    for (const auto& p : run(scene, 200))
        for (std::size_t d = 0; d < 3; ++d) outside += p[d] < 0 || p[d] > 1;
    EXPECT_EQ(outside, 0u);
}

// ---- churn and queries -----------------------------------------------------------------------

TEST(scene_churn, erase_indices_are_distinct_decreasing_and_reproducible) {
    const auto scene = datasets::parse_scene(full_scene, "full.toml");  // 4 inserts, 5 erases per step
    const auto e = datasets::churn_erase_indices(scene, 3, 50);
    ASSERT_EQ(e.size(), 5u);
    EXPECT_TRUE(std::is_sorted(e.begin(), e.end(), std::greater<>()));
    EXPECT_EQ(std::set<std::size_t>(e.begin(), e.end()).size(), 5u);
    EXPECT_LT(e.front(), 50u);
    EXPECT_EQ(e, datasets::churn_erase_indices(scene, 3, 50));
    EXPECT_NE(e, datasets::churn_erase_indices(scene, 4, 50));
    EXPECT_EQ(datasets::churn_erase_indices(scene, 0, 3).size(), 3u);  // no more than there are
    EXPECT_TRUE(datasets::churn_erase_indices(scene, 0, 0).empty());

    // Erasing them by swap-and-pop removes exactly those objects; the motion state follows.
    using sphere = spatial::objects::sphere<float, 3>;
    auto objects = datasets::generate_objects<sphere>(scene, 1);
    datasets::scene_motion<sphere> motion(scene, 1, objects.size());
    for (std::size_t step = 0; step < 5; ++step) {
        motion.step(objects, scene.time_step);
        const auto gone = datasets::churn_erase_indices(scene, step, objects.size());
        std::vector<sphere> expected;
        for (std::size_t i = 0; i < objects.size(); ++i)
            if (std::find(gone.begin(), gone.end(), i) == gone.end()) expected.push_back(objects[i]);
        for (std::size_t i : gone) {
            objects[i] = objects.back();
            objects.pop_back();
            motion.erase(i);
        }
        const auto added = datasets::generate_churn_objects<sphere>(scene, step);
        EXPECT_EQ(added.size(), 4u);
        objects.insert(objects.end(), added.begin(), added.end());
        motion.insert(added.size());
        expected.insert(expected.end(), added.begin(), added.end());
        const auto key = [](const sphere& s) { return std::make_tuple(s.center()[0], s.center()[1], s.center()[2]); };
        auto got = objects;
        std::sort(got.begin(), got.end(), [&](auto& x, auto& y) { return key(x) < key(y); });
        std::sort(expected.begin(), expected.end(), [&](auto& x, auto& y) { return key(x) < key(y); });
        EXPECT_TRUE(bit_identical(got, expected));
        EXPECT_EQ(motion.size(), objects.size());
    }
    EXPECT_EQ(objects.size(), 50u - 5 * 1);
    EXPECT_TRUE(bit_identical(datasets::generate_churn_objects<sphere>(scene, 2),
                              datasets::generate_churn_objects<sphere>(scene, 2)));
    EXPECT_FALSE(bit_identical(datasets::generate_churn_objects<sphere>(scene, 2),
                               datasets::generate_churn_objects<sphere>(scene, 3)));
}

TEST(scene_queries, rays_and_query_points_are_reproducible_and_well_formed) {
    const auto scene = datasets::parse_scene(full_scene, "full.toml");
    const auto rays = datasets::generate_rays<double, 3>(scene, 1);
    ASSERT_EQ(rays.size(), 100u);
    for (const auto& r : rays) {
        EXPECT_EQ(r.origin, (spatial::point<double, 3>{{0, -5, 0}}));
        EXPECT_NEAR(std::hypot(r.direction[0], r.direction[1], r.direction[2]), 1.0, 1e-12);
        EXPECT_GT(r.direction[1], 0.9);  // within the 30 degree field of view, looking along +y
        EXPECT_EQ(r.thickness, 0.01);
    }
    // The first ray is through the top-left pixel, the last through the bottom-right.
    EXPECT_LT(rays.front().direction[0], 0);
    EXPECT_GT(rays.front().direction[2], 0.1);
    EXPECT_GT(rays.back().direction[0], 0);
    EXPECT_EQ(rays[5].direction, (datasets::generate_rays<double, 3>(scene, 1)[5].direction));
    EXPECT_NE(rays[5].direction, (datasets::generate_rays<double, 3>(scene, 2)[5].direction));

    auto random_scene = datasets::parse_scene(minimal_scene + "[effects.raycast]\nrays_per_step = 200\n", "r.toml");
    for (const auto& r : datasets::generate_rays<float, 3>(random_scene, 0)) {
        for (std::size_t d = 0; d < 3; ++d) EXPECT_TRUE(r.origin[d] >= 0 && r.origin[d] < 1);
        EXPECT_NEAR(std::hypot(r.direction[0], r.direction[1], r.direction[2]), 1.0, 1e-6);
    }

    const auto queries = datasets::generate_nearest_queries<float, 3>(scene, 0);
    ASSERT_EQ(queries.size(), 7u);
    for (const auto& q : queries)
        for (std::size_t d = 0; d < 3; ++d)
            EXPECT_TRUE(q[d] >= scene.domain_lo[d] && q[d] <= scene.domain_hi[d]);
    for (const auto& b : datasets::generate_range_queries<double, 3>(scene, 0))
        for (std::size_t d = 0; d < 3; ++d) EXPECT_NEAR(b.hi[d] - b.lo[d], 0.25, 1e-12);

    // A 2D camera: a fan of rays from the eye.
    const auto flat = datasets::parse_scene(
        "[scene]\ndimension = 2\n[[objects]]\nname = \"d\"\nkind = \"sphere\"\ncount = 4\nsize = 0.1\n"
        "[effects.raycast]\nrays_per_step = 9\nkind = \"camera\"\nfield_of_view = 90\n",
        "fan.toml");
    const auto fan = datasets::generate_rays<double, 2>(flat, 0);
    ASSERT_EQ(fan.size(), 9u);
    for (std::size_t i = 0; i < fan.size(); ++i) {
        EXPECT_EQ(fan[i].origin, (spatial::point<double, 2>{{0.5, -1.5}}));
        const double angle = std::atan2(fan[i].direction[0], fan[i].direction[1]);  // from +y
        EXPECT_LE(std::abs(angle), 3.14159265358979 / 4 + 1e-12);
        if (i > 0) {
            EXPECT_LT(std::atan2(fan[i - 1].direction[0], fan[i - 1].direction[1]), angle);
        }
    }
}

}  // namespace
