#pragma once
// The scene runner behind `spatialbench scene FILE...`: reads a scene (datasets/scene.hpp),
// builds exactly the pipeline its effects ask for, runs it on one or several of our
// structures, validates every answer against brute force (sampled for large scenes) and
// against the other structures, and reports per-stage timings (results/scenes.csv).
//
// What a scene does not ask for costs nothing — the counters below prove it in
// tests/scene_runner_test.cpp:
//   * no motion stage and no index update for a static scene (or a static set);
//   * no narrow phase when the collide effect asks for candidate pairs only;
//   * no index at all for a set that no effect queries;
//   * no rays, kNN or range queries unless the effect is present.
// Validation work (brute-force checks) is not counted and not timed.

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "datasets/scene.hpp"
#include "harness/csv_writer.hpp"

namespace harness {

// Calls each pipeline stage made (summed over steps and structures run).
struct scene_counters {
    std::size_t motion_steps = 0;        // set-steps of motion integration (moving sets only)
    std::size_t index_builds = 0;        // structures built (one per queried set and structure)
    std::size_t index_updates = 0;       // structure updates after motion or churn
    std::size_t churn_inserts = 0, churn_erases = 0;
    std::size_t pair_queries = 0;        // pair queries on a structure (self or bipartite)
    std::size_t exact_self_pair_queries = 0;  // self pairs asked exact of the structure itself
    std::size_t narrow_phase_tests = 0;  // the runner's exact tests of bipartite candidates
    std::size_t rays_cast = 0, nearest_queries = 0, range_queries = 0;
};

struct scene_run_options {
    // Structures to run: bvh, kd_tree, octree, uniform_grid, collision_grid, brute_force, or
    // "all" (each one that answers every effect of the scene). Empty: bvh.
    std::vector<std::string> structures;
    std::size_t steps = 0;  // 0: the scene's own steps
    bool quiet = false;
    std::string run_id;
};

// Runs one scene; returns its CSV rows (suite "scenes") and adds to `counters`.
// Throws validation_error on a wrong answer, std::invalid_argument for a structure that
// cannot answer one of the scene's effects (named), datasets::scene_error for a bad file.
std::vector<result_row> run_scene(const datasets::scene_description& scene, const scene_run_options& options,
                                  scene_counters& counters);

// The structures `all` expands to.
std::vector<std::string> scene_structure_names();

}  // namespace harness
