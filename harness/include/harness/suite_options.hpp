#pragma once
// Options shared by every suite of the spatialbench CLI (each suite reads the ones it uses).

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace harness {

struct suite_options {
    std::string preset = "quick";  // smoke | quick | full
    std::filesystem::path results_dir = "results";
    std::filesystem::path real_data_dir;  // point sets (.xyz/.ply/.off) to add as workloads; may be empty
    std::uint64_t seed = 20261122;
    std::vector<std::string> workloads;   // empty = the preset's
    std::vector<std::string> structures;  // empty = all available
    std::vector<std::size_t> sizes;       // empty = the preset's
    std::vector<std::string> cases;       // empty = every case (suite_cases.hpp); else these ids
    // Sharding (`--shard i/N`): of the selected cases, this run takes those whose position in
    // the suite's case list is i modulo N (0 <= i < N). N = 1: every case.
    std::size_t shard_index = 0, shard_count = 1;
    bool quiet = false;
    // Finish an interrupted run: skip the cases its journal holds (run_journal.hpp).
    bool resume = false;
    bool dynamic = true;  // run the insert/erase workloads
    std::string output_name = "knn.csv";  // the CLI sets <suite>.csv unless --output is given
    // The `structures` suite is the knn suite's static part run on EVERY structure of the
    // library (kd_tree, bvh, octree, uniform and hashed grids) next to the peers.
    std::string suite_name = "knn";
    bool all_structures = false;

    // "shard<i>of<N>" for a sharded run (part of its run id and sidecar), "" otherwise.
    std::string shard_label() const {
        return shard_count > 1 ? "shard" + std::to_string(shard_index) + "of" + std::to_string(shard_count) : "";
    }
};

// Parses "i/N" (0 <= i < N) into options.shard_index and shard_count; throws
// std::invalid_argument saying what is wrong.
void parse_shard(const std::string& text, suite_options& options);

}  // namespace harness
