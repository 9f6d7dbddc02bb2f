#!/bin/bash
# scripts/scaling.py lists a figure at its suite's largest size when its own largest size is in
# the same decade: a generated sphere of 9,991,920 triangles counts at 1e7, a figure that stops
# at 1e5 does not. Usage: check_scaling.sh SPATIALBENCH SOURCE_DIR WORK_DIR
set -euo pipefail
spatialbench=$1 source_dir=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
"$spatialbench" list --json > "$work/registry.json"
cp "$source_dir/tests/data/scaling_nominal_sizes/raycast.csv" "$work/"
/usr/bin/python3 "$source_dir/scripts/scaling.py" --results "$work" --output "$work/scaling.md"
fail() { echo "check_scaling: $1"; cat "$work/scaling.md"; exit 1; }
grep -q '^## raycast: largest size 1e7' "$work/scaling.md" || fail "no raycast section at 1e7"
grep -q '| bvh (aabb) | sphere 3d double | build | — | build_time | 9,800 – 9,991,920 (3) |' "$work/scaling.md" ||
    fail "the sphere of 9,991,920 triangles is not listed at 1e7"
grep -q '| bvh (aabb) | soup 3d double | build | — | build_time | 1e4 – 1e7 (3) |' "$work/scaling.md" ||
    fail "the soup at 1e7 is not listed"
if grep -q '| kd_tree |' "$work/scaling.md"; then fail "a figure that stops at 1e5 is listed at 1e7"; fi
echo "check_scaling: nominal sizes listed at their decade"
