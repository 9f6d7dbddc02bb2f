#!/usr/bin/env bash
# The proof of docs/adding-a-structure.md: the example structure (examples::morton_array,
# added with its header, one registry line, one test line and docs) appears in every suite
# and in a scene, with validated rows. Fails naming the first suite where it is missing.
# Usage: check_example_structure.sh SPATIALBENCH_BINARY SCENE_FILE OUTPUT_DIR
set -euo pipefail
bin="$1"
scene="$2"
out="$3"
name=morton_array
rm -rf "$out"
mkdir -p "$out"

# Captured first: grep -q stops reading early, and a binary killed by SIGPIPE fails the pipe.
listing="$("$bin" list)"
grep -q "^  $name \[example\]" <<< "$listing" || { echo "FAIL: $name is not in 'spatialbench list'"; exit 1; }
json="$("$bin" list --json)"
grep -q "\"name\": \"$name\"" <<< "$json" || { echo "FAIL: $name is not in the registry JSON"; exit 1; }

# Validated rows of the structure in a table: the structure column is the 2nd, validated the 13th.
has_rows() {
  awk -F, -v s="$name" 'NR > 1 && $2 == s && $13 == "true" { found = 1 } END { exit !found }' "$1"
}

for suite in knn structures raycast collide; do
  "$bin" run --suite "$suite" --preset smoke --quiet --structure "$name" --structure brute_force \
    --results "$out" --output "$suite.csv"
  has_rows "$out/$suite.csv" || { echo "FAIL: no validated $name rows in the $suite suite"; exit 1; }
done
"$bin" scene "$scene" --structure "$name" --structure brute_force --steps 3 --quiet --results "$out"
has_rows "$out/scenes.csv" || { echo "FAIL: no validated $name rows in the scene"; exit 1; }
grep -q "\"name\": \"$name\"" "$out/registry.json" || { echo "FAIL: $name missing from $out/registry.json"; exit 1; }
echo "ok: $name has validated rows in knn, structures, raycast, collide and a scene"
