#!/usr/bin/env bash
# The test job: install dependencies, then build and run every test twice — a Release
# build (with the peers' adapters and a smoke run of the harness) and a Debug build of the
# library's tests with
# -fsanitize=address,undefined — plus the plotting script's tests.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install_deps.sh
jobs="$(nproc)"

echo "== release build"
cmake --preset release -G Ninja
cmake --build --preset release -j"$jobs"
ctest --preset release -j"$jobs"

echo "== plot script tests"
/usr/bin/python3 -m unittest discover -s plots/tests -t plots

echo "== address+undefined sanitizer build"
cmake --preset asan -G Ninja
cmake --build --preset asan -j"$jobs"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --preset asan -j"$jobs"
