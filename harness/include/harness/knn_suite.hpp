#pragma once
// The `knn` suite: point structures (ours and peers) on generated and real point sets —
// build, exact kNN (k = 1, 10), radius, (1+eps)-approximate kNN with recall, insert/erase
// churn, hinted against plain insertion of a coherent stream, and bulk against looped
// insertion and erasure. Every timed answer is validated first (see validation.hpp).

#include <string>
#include <vector>

#include "harness/suite_options.hpp"

namespace harness {

// Runs the suite and writes <results_dir>/<output_name> and its JSON sidecar. Throws
// validation_error (with a message naming structure, workload, n, operation and query) on
// any wrong answer; nothing is written then.
void run_knn_suite(const suite_options& options);
// The ids of the cases a run with these options would run, in order (suite_cases.hpp).
std::vector<std::string> knn_case_ids(const suite_options& options);

}  // namespace harness
