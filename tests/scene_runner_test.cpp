// The scene runner (harness/scene_runner.hpp) composes exactly the pipeline a scene asks for:
// proved by counting the calls each stage makes. Also: every structure reports the same
// exact pairs (the runner throws otherwise), churn and queries are counted, a structure that
// cannot answer an effect is refused by name, a mesh file that cannot be loaded is reported
// with the scene file and line, and every shipped scene runs (a few steps) and validates.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "datasets/scene.hpp"
#include "harness/answer_digest.hpp"
#include "harness/scene_runner.hpp"
#include "harness/validation.hpp"

namespace {

using harness::scene_counters;

harness::scene_run_options quiet(std::vector<std::string> structures = {"bvh"}, std::size_t steps = 0) {
    harness::scene_run_options o;
    o.structures = std::move(structures);
    o.steps = steps;
    o.quiet = true;
    o.run_id = "test";
    return o;
}

scene_counters run(const std::string& toml, harness::scene_run_options o = quiet()) {
    scene_counters k;
    const auto rows = harness::run_scene(datasets::parse_scene(toml, "test.toml"), o, k);
    EXPECT_FALSE(rows.empty());
    for (const auto& r : rows) EXPECT_TRUE(r.validated()) << r.suite << " " << r.structure << " " << r.operation << " " << r.metric << " check=" << r.check;
    return k;
}

// The [scene] table of a scene of `steps` steps.
std::string scene_of_steps(int steps) { return "[scene]\nsteps = " + std::to_string(steps) + "\n"; }

// An [[objects]] table: `count` generated objects of `kind`, of `size` (TOML text; none for
// points), moving by `motion` (the inside of its inline table) when one is given.
std::string objects_table(const std::string& name, const std::string& kind, int count, const std::string& size = "",
                          const std::string& motion = "") {
    std::string t =
        "[[objects]]\nname = \"" + name + "\"\nkind = \"" + kind + "\"\ncount = " + std::to_string(count) + "\n";
    if (!size.empty()) t += "size = " + size + "\n";
    if (!motion.empty()) t += "motion = { " + motion + " }\n";
    return t;
}

// An [effects.collide] table testing the pairs `between` (TOML text) with `filter`.
std::string collide_effect(const std::string& between, const std::string& filter) {
    return "[effects.collide]\nbetween = " + between + "\nfilter = \"" + filter + "\"\n";
}

const std::string boxes_set = objects_table("boxes", "box", 300, "0.08");

TEST(scene_runner, a_static_scene_with_rays_only_moves_nothing_and_tests_no_pairs) {
    const auto k = run(scene_of_steps(4) + boxes_set + "[effects.raycast]\nrays_per_step = 50\n");
    EXPECT_EQ(k.motion_steps, 0u);
    EXPECT_EQ(k.index_updates, 0u);
    EXPECT_EQ(k.index_builds, 1u);
    EXPECT_EQ(k.pair_queries, 0u);
    EXPECT_EQ(k.narrow_phase_tests, 0u);
    EXPECT_EQ(k.nearest_queries + k.range_queries + k.churn_inserts + k.churn_erases, 0u);
    EXPECT_EQ(k.rays_cast, 4u * 50u);
}

TEST(scene_runner, self_pairs_are_the_structures_own_query_and_pairs_between_sets_run_the_runners_narrow_phase) {
    const std::string moving =
        scene_of_steps(5) + objects_table("boxes", "box", 400, "0.06", "kind = \"linear\", speed = 1.0");
    const auto candidates = run(moving + collide_effect(R"([["boxes", "boxes"]])", "candidates"));
    EXPECT_EQ(candidates.narrow_phase_tests, 0u);
    EXPECT_EQ(candidates.exact_self_pair_queries, 0u);
    EXPECT_EQ(candidates.pair_queries, 5u);
    EXPECT_EQ(candidates.motion_steps, 5u);
    EXPECT_EQ(candidates.index_updates, 5u);
    EXPECT_EQ(candidates.rays_cast, 0u);
    // Exact self pairs: the structure's own exact query (its narrow phase runs inside it).
    const auto exact = run(moving + collide_effect(R"([["boxes", "boxes"]])", "exact"));
    EXPECT_EQ(exact.exact_self_pair_queries, 5u);
    EXPECT_EQ(exact.narrow_phase_tests, 0u);
    EXPECT_EQ(exact.pair_queries, 5u);
    // Exact pairs between two sets: box queries, then the runner's narrow phase per candidate.
    const auto between = run(moving + objects_table("balls", "sphere", 300, "0.06") +
                             collide_effect(R"([["boxes", "balls"]])", "exact"));
    EXPECT_GT(between.narrow_phase_tests, 0u);
    EXPECT_EQ(between.exact_self_pair_queries, 0u);
    EXPECT_EQ(between.pair_queries, 5u);
}

TEST(scene_runner, no_index_for_a_set_nobody_queries_and_no_update_for_a_static_set) {
    const auto k = run(scene_of_steps(3) +
                       objects_table("queried", "sphere", 200, "0.03", "kind = \"random_walk\", speed = 0.5") +
                       objects_table("ignored", "box", 500, "0.05", "kind = \"linear\", speed = 0.5") +
                       objects_table("still", "point", 100) + R"(
[effects.nearest]
target = "queried"
queries_per_step = 20
k = 4
[effects.range]
target = "still"
queries_per_step = 10
half_extent = 0.2
)");
    EXPECT_EQ(k.index_builds, 2u);      // "queried" and "still"; never "ignored"
    EXPECT_EQ(k.motion_steps, 2u * 3u); // the two moving sets move (motion is the scene's)
    EXPECT_EQ(k.index_updates, 3u);     // only the moving queried set's index follows
    EXPECT_EQ(k.nearest_queries, 3u * 20u);
    EXPECT_EQ(k.range_queries, 3u * 10u);
    EXPECT_EQ(k.pair_queries, 0u);
}

TEST(scene_runner, churn_is_counted_and_every_structure_reports_the_same_exact_pairs) {
    const std::string scene = scene_of_steps(4) +
                              objects_table("balls", "sphere", 300, "0.04", "kind = \"linear\", speed = 0.8") +
                              objects_table("boxes", "box", 200, "0.06") +
                              "[effects.churn]\ntarget = \"balls\"\ninserts_per_step = 7\nerases_per_step = 5\n" +
                              collide_effect(R"([["balls", "balls"], ["balls", "boxes"]])", "exact");
    const auto k = run(scene, quiet({"all"}));  // throws validation_error if any two disagree
    const std::size_t structures = harness::scene_structure_names().size();
    EXPECT_EQ(k.churn_inserts, structures * 4u * 7u);
    EXPECT_EQ(k.churn_erases, structures * 4u * 5u);
    EXPECT_EQ(k.pair_queries, structures * 4u * 2u);
    EXPECT_EQ(k.exact_self_pair_queries, structures * 4u);  // balls-balls; balls-boxes is bipartite
    EXPECT_GT(k.narrow_phase_tests, 0u);
}

TEST(scene_runner, structures_that_cannot_answer_an_effect_are_refused_by_name) {
    const std::string scene = scene_of_steps(1) + boxes_set + "\n[effects.raycast]\nrays_per_step = 5\n";
    scene_counters k;
    const auto description = datasets::parse_scene(scene, "test.toml");
    try {
        harness::run_scene(description, quiet({"collision_grid"}), k);
        FAIL() << "collision_grid cannot cast rays";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("collision_grid"), std::string::npos) << e.what();
    }
    EXPECT_THROW(harness::run_scene(description, quiet({"no_such_tree"}), k), std::invalid_argument);
}

TEST(scene_runner, a_mesh_file_that_cannot_be_loaded_names_the_scene_line) {
    const std::string scene = R"([scene]
steps = 1

[[objects]]
name = "mesh"
kind = "triangle"
mesh = "does_not_exist.off"

[effects.raycast]
rays_per_step = 5
)";
    scene_counters k;
    try {
        harness::run_scene(datasets::parse_scene(scene, "meshy.toml"), quiet(), k);
        FAIL() << "a missing mesh file must be an error";
    } catch (const std::invalid_argument& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("meshy.toml:4"), std::string::npos) << what;
        EXPECT_NE(what.find("does_not_exist.off"), std::string::npos) << what;
    }
}

TEST(scene_runner, every_shipped_scene_runs_and_validates) {
    for (const auto& entry : std::filesystem::directory_iterator(SPATIAL_SCENES_DIR)) {
        if (entry.path().extension() != ".toml") continue;
        SCOPED_TRACE(entry.path().string());
        scene_counters k;
        const auto description = datasets::load_scene(entry.path());
        // Two steps of every structure that answers the scene (each one's timed pass must
        // replay its validated pass's answers exactly); the 1e5-box scene on the collision grid
        // only (the suite times it).
        const bool big = description.objects.front().generator && description.objects.front().generator->count > 20000;
        const auto rows = harness::run_scene(description, quiet({big ? "collision_grid" : "all"}, 2), k);
        EXPECT_FALSE(rows.empty());
    }
}

}  // namespace

// The runner compares its two passes, and structures with each other, by digests of each
// step's answers (answer_digest.hpp): every kind of difference those comparisons exist to
// find must change the digest; equal answers must give equal digests.
TEST(scene_runner, the_answer_digest_tells_every_kind_of_difference_apart) {
    using pair32 = std::pair<std::uint32_t, std::uint32_t>;
    const std::vector<pair32> pairs{{0, 1}, {0, 7}, {3, 4}, {5, 9}};
    const std::uint64_t d = harness::digest_of(pairs);
    EXPECT_EQ(harness::digest_of(std::vector<pair32>(pairs)), d);
    auto dropped = pairs;
    dropped.pop_back();
    auto extra = pairs;
    extra.push_back({6, 8});
    auto swapped = pairs;
    std::swap(swapped[1], swapped[2]);
    auto changed = pairs;
    changed[2].second = 5;
    auto flipped = pairs;
    flipped[0] = {1, 0};
    for (const auto* other : {&dropped, &extra, &swapped, &changed, &flipped}) EXPECT_NE(harness::digest_of(*other), d);
    EXPECT_NE(harness::digest_of(std::vector<pair32>{}), harness::digest_of(std::vector<pair32>{{0, 0}}));
    // Rays: a miss is not a hit at distance 0; one ulp moves the digest.
    const std::vector<std::optional<double>> hits{0.5, std::nullopt, 2.0};
    EXPECT_NE(harness::digest_of(std::vector<std::optional<double>>{0.5, 0.0, 2.0}), harness::digest_of(hits));
    EXPECT_NE(harness::digest_of(std::vector<std::optional<double>>{0.5, std::nullopt, std::nextafter(2.0, 3.0)}),
              harness::digest_of(hits));
    EXPECT_EQ(harness::digest_of(std::vector<std::optional<double>>{0.5, std::nullopt, 2.0}), harness::digest_of(hits));
    // Nested answers (each query's list): where a boundary falls between lists matters.
    const std::vector<std::vector<std::uint32_t>> ranges{{1, 2}, {3}};
    EXPECT_NE(harness::digest_of(std::vector<std::vector<std::uint32_t>>{{1}, {2, 3}}), harness::digest_of(ranges));
    EXPECT_NE(harness::digest_of(std::vector<std::vector<float>>{{1.0f, 2.0f}}),
              harness::digest_of(std::vector<std::vector<float>>{{1.0f, -2.0f}}));
}
