#!/usr/bin/env bash
# The test job: install dependencies, fetch the real data, then build and run every test
# twice — a Release build (with the peers' adapters, smoke runs of the harness, the real data
# and a single-node Slurm) and a Debug build of the
# library's tests with
# -fsanitize=address,undefined — plus the plotting script's tests.
set -euo pipefail
cd "$(dirname "$0")/.."

# Each phase's wall time goes to the log (CI must stay under 30 minutes on 2 cores).
phase() { echo "== $1 (at ${SECONDS} s)"; }

scripts/install_deps.sh
jobs="$(nproc)"

# Real data from Debian's archive (a few seconds): the tests that read it run instead of
# skipping. A machine that cannot download still tests everything else; the skip says so.
phase "real data"
datasets/fetch_real_data.sh || echo "test: real point sets unavailable; their tests will be skipped"
scripts/fetch_meshes.sh || echo "test: real meshes unavailable; their tests will be skipped"

phase "release build"
cmake --preset release -G Ninja
cmake --build --preset release -j"$jobs"
phase "release tests"
ctest --preset release -j"$jobs"

phase "paper on smoke tables"
tests/check_paper_smoke.sh build/release/harness/spatialbench

phase "plot script and paper tests"
/usr/bin/python3 -m unittest discover -s plots/tests -t plots
/usr/bin/python3 -m unittest discover -s paper/tests -t paper

phase "address+undefined sanitizer build"
cmake --preset asan -G Ninja
cmake --build --preset asan -j"$jobs"
phase "sanitizer tests"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --preset asan -j"$jobs"
phase "done"
