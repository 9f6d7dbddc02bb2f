#!/usr/bin/env bash
# Sharded runs merge to the single run's table: every suite run as three shards
# (`run --shard i/3`, scenes with `scene --shard i/3`), joined by `spatialbench merge`, must
# have exactly the keys of the single smoke run and the same answers of our structures
# (tests/check_table_keys.py), and every merged row must be validated. The single run's tables
# are the smoke fixture's (tests/harness.cmake).
# Usage: check_shards.sh SPATIALBENCH_BINARY OUTPUT_DIR SCENE_FILE SINGLE_RUN_TABLE...
set -euo pipefail
bin="$1"
out="$2"
scene="$3"
shift 3
here="$(cd "$(dirname "$0")" && pwd)"
rm -rf "$out"
mkdir -p "$out"

shards=3
for ((i = 0; i < shards; ++i)); do
  for suite in knn structures bv raycast collide; do
    "$bin" run --suite "$suite" --preset smoke --shard "$i/$shards" --quiet --results "$out/shard$i"
  done
  "$bin" scene "$scene" --structure all --steps 3 --shard "$i/$shards" --quiet --results "$out/shard$i"
done
"$bin" merge "$out"/shard* --results "$out/merged" --quiet

# The single run's keys and answers, every row validated, every run's sidecar merged.
source "$here/merged_tables_check.sh"
check_merged_tables "$out/merged" "*-shard[0-2]of3" "$@" > /dev/null
# Two shards that measured the same figure are refused by name.
if "$bin" merge "$out/shard0" "$out/shard0" --results "$out/refused" --quiet 2> "$out/err.txt"; then
  echo "FAIL: merging a shard with itself was accepted"; exit 1
fi
grep -q "spatialbench: error: key .* shards must hold disjoint cases" "$out/err.txt" ||
  { echo "FAIL: the overlap error does not say so:"; cat "$out/err.txt"; exit 1; }
echo "ok: $shards shards of every suite and a scene merge to the single run's keys and answers, every row validated"
