#!/usr/bin/env bash
# The sanitizer build (the asan preset) of a few of the library's heaviest tests under g++ 12
# and clang 15, one compile at a time, side by side in one run (README.md here): the shared
# precompiled header first, then each test; wall seconds and the compiler's peak memory.
#
#   results/checks/sanitizer_compiler/compare_compilers.sh [test...]   (default: three tests)
#   SCRATCH=DIR   where the two builds go (default: a new directory under /tmp)
set -euo pipefail
cd "$(dirname "$0")/../../.."

tests=("$@")
((${#tests[@]})) || tests=(bvh_test kdop_test collide_pairs_test)
scratch="${SCRATCH:-$(mktemp -d /tmp/sanitizer_compiler.XXXXXX)}"

# g++ as the asan preset had it before clang: the same flags plus g++'s collector settings.
configure() {
  local name="$1"; shift
  cmake --preset asan -G Ninja -B "$scratch/$name" "$@" > "$scratch/$name.configure.log"
}
configure gcc -DCMAKE_CXX_COMPILER=g++ \
  "-DCMAKE_CXX_FLAGS=--param=ggc-min-expand=100 --param=ggc-min-heapsize=2097152"
configure clang

echo "target,compiler,wall_s,peak_rss_mb"
for target in spatial_test_pch "${tests[@]}"; do
  for name in gcc clang; do
    /usr/bin/time -f "%e %M" -o "$scratch/time" ninja -C "$scratch/$name" -j1 "$target" > /dev/null
    read -r wall rss_kb < "$scratch/time"
    echo "$target,$name,$wall,$((rss_kb / 1024))"
  done
done
