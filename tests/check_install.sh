#!/usr/bin/env bash
# The library in another project: `cmake --install` of this build into a fresh prefix, then
# tests/install_consumer (find_package(spatial CONFIG), spatial::structures) configured, built
# and run against that prefix alone. Usage: check_install.sh BUILD_DIR SOURCE_DIR WORK_DIR
set -euo pipefail
build="$1"
source="$2"
work="$3"
rm -rf "$work"
mkdir -p "$work"
cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
test -f "$work/prefix/lib/cmake/spatial/spatialConfig.cmake" || { echo "FAIL: no package config installed"; exit 1; }
test -f "$work/prefix/include/spatial/kdtree/kd_tree.hpp" || { echo "FAIL: headers not installed"; exit 1; }
cmake -S "$source/tests/install_consumer" -B "$work/consumer" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$work/prefix" > "$work/configure.log"
cmake --build "$work/consumer" > "$work/build.log"
"$work/consumer/consumer"
echo "ok: installed to a fresh prefix, found with find_package(spatial CONFIG), built and run"
