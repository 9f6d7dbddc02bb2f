#!/usr/bin/env bash
# The test job: install dependencies, fetch the real data, then three builds — the ci build
# (the release configuration at -O1) of the harness and the peers' adapters with the tests
# that need them (smoke runs of every suite, the real data, sharded runs on a single-node
# Slurm, interrupted runs, the paper on smoke tables), and a Debug build of the library's own
# tests with -fsanitize=address,undefined (clang 15) — plus the plotting script's and the
# paper's tests, and a short run of every fuzz target (a third build: clang 15 again,
# libFuzzer, the same sanitizers).
set -euo pipefail
cd "$(dirname "$0")/.."

# Each phase's wall time goes to the log (CI must stay under 30 minutes on 2 cores).
phase() { echo "== $1 (at ${SECONDS} s)"; }

scripts/install_deps.sh
jobs="$(nproc)"

# A build prints no warnings (the project's rule; warnings are on for our own code,
# CMakeLists.txt): each build's output is kept, and a warning in it fails the job.
build_without_warnings() {
  local log
  log="$(mktemp /tmp/spatial_build.XXXXXX)"
  cmake --build --preset "$1" -j"$jobs" 2>&1 | tee "$log"
  if grep -q "warning:" "$log"; then
    echo "test: the $1 build printed warnings:" >&2
    grep -A3 "warning:" "$log" >&2
    rm -f "$log"
    exit 1
  fi
  rm -f "$log"
}

# Real data from Debian's archive (a few seconds): the tests that read it run instead of
# skipping. A machine that cannot download still tests everything else; the skip says so.
phase "real data"
datasets/fetch_real_data.sh || echo "test: real point sets unavailable; their tests will be skipped"
scripts/fetch_meshes.sh || echo "test: real meshes unavailable; their tests will be skipped"

# The ci build (CMakePresets.json: the release configuration at -O1 instead of -O3, half the
# compile time, in build/ci so a benchmark build in build/release is left alone): the harness,
# the peers' adapters and every test that needs them (smoke runs, real data, Slurm, the
# paper); the library's own tests run in the sanitizer build below.
phase "ci build"
cmake --preset ci -G Ninja
build_without_warnings ci
phase "ci tests"
ctest --preset ci -j"$jobs"

# Three single-threaded jobs of about half a minute each: the paper on smoke tables runs on
# one core while the plotting script's and the paper's unit tests run on the other.
phase "paper on smoke tables, beside the plot script and paper tests"
paper_log="$(mktemp /tmp/spatial_paper_smoke.XXXXXX)"
tests/check_paper_smoke.sh build/ci/harness/spatialbench > "$paper_log" 2>&1 &
paper_job=$!
/usr/bin/python3 -m unittest discover -s plots/tests -t plots
/usr/bin/python3 -m unittest discover -s paper/tests -t paper
paper_status=0
wait "$paper_job" || paper_status=$?
cat "$paper_log"
rm -f "$paper_log"
(( paper_status == 0 )) || { echo "test: the paper on smoke tables failed (exit $paper_status)" >&2; exit 1; }

phase "address+undefined sanitizer build"
source scripts/sanitizer_env.sh
cmake --preset asan -G Ninja
build_without_warnings asan
phase "sanitizer tests"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --preset asan -j"$jobs"

# Fuzzing (docs/fuzzing.md): the libFuzzer targets built with clang under address+undefined
# sanitizers, each run on its seed corpus and then mutated for a short fixed budget (every seed
# replayed is the regression part; the budget keeps CI under 30 minutes). Longer runs: by hand.
phase "fuzz build and ${SPATIAL_CI_FUZZ_SECONDS:-10} s per target"
FUZZ_BUILD_JOBS="$jobs" scripts/fuzz.sh "${SPATIAL_CI_FUZZ_SECONDS:-10}"
phase "done"
