#pragma once
// The `knn` suite: point structures (ours and peers) on generated and real point sets —
// build, exact kNN (k = 1, 10), radius, (1+eps)-approximate kNN with recall, insert/erase
// churn, hinted against plain insertion of a coherent stream, and bulk against looped
// insertion and erasure. Every timed answer is validated first (see validation.hpp).

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
    bool quiet = false;
    bool dynamic = true;  // run the insert/erase workloads
    std::string output_name = "knn.csv";
};

// Runs the suite and writes <results_dir>/<output_name> and its JSON sidecar. Throws
// validation_error (with a message naming structure, workload, n, operation and query) on
// any wrong answer; nothing is written then.
void run_knn_suite(const suite_options& options);

}  // namespace harness
