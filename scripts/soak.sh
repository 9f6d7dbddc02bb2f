#!/usr/bin/env bash
# Soak (docs/fuzzing.md, "Soak"; issue 19, part 5): configure and build spatial_soak in an
# optimised build of its own (build/soak: -O2 with assertions on, no sanitizers), then run it.
# Every argument goes to spatial_soak: by default 1e7 operations on each of the 24 structures
# of the full matrix (days at the rates in docs/fuzzing.md; --seconds bounds each). Exits with spatial_soak's status: 1 if any answer differed from
# brute_force; the failing sequences are then in soak_findings/ (replay: fuzz_operations FILE).
#
#   scripts/soak.sh [--structure NAME]... [--operations N] [--seconds T] [--seed S] [--first-sequence K] [--findings DIR] [--list]
#   scripts/soak.sh --replay FILE    one failing sequence again (SPATIAL_FUZZ_TRACE=1: every operation)
#   SOAK_BUILD_JOBS=1   build jobs (default: all cores)
set -euo pipefail
cd "$(dirname "$0")/.."

jobs="${SOAK_BUILD_JOBS:-$(nproc)}"
build=build/soak
echo "== configure and build $build (commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown))" >&2
# -O2 without NDEBUG: the structures' own assertions are checks too.
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE=-O2 -DSPATIAL_BUILD_SOAK=ON \
  -DSPATIAL_BUILD_TESTS=OFF -DSPATIAL_BUILD_HARNESS=OFF > /dev/null
cmake --build "$build" --target spatial_soak -j"$jobs"
echo "== run" >&2
exec "$build/fuzz/soak/spatial_soak" "$@"
