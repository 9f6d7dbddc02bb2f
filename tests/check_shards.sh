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

/usr/bin/python3 "$here/check_table_keys.py" --write "$out/single_keys.csv" "$@"
merged=()
for table in "$@"; do merged+=("$out/merged/$(basename "$table")"); done
/usr/bin/python3 "$here/check_table_keys.py" "$out/single_keys.csv" "${merged[@]}"

# Every merged row is validated, and names a sidecar that was merged with it.
for table in "${merged[@]}"; do
  awk -F, 'NR == 1 { for (c = 1; c <= NF; ++c) if ($c == "validated") v = c; next }
           $v != "true" { bad++ } END { exit bad > 0 }' "$table" ||
    { echo "FAIL: $table has rows that are not validated"; exit 1; }
done
for run_id in $(awk -F, 'FNR == 1 { for (c = 1; c <= NF; ++c) if ($c == "run_id") r = c; next } { print $r }' "${merged[@]}" | sort -u); do
  [[ -s "$out/merged/runs/$run_id.json" ]] || { echo "FAIL: merged rows name run $run_id, whose sidecar is missing"; exit 1; }
  grep -q '"host"' "$out/merged/runs/$run_id.json" || { echo "FAIL: sidecar $run_id names no host"; exit 1; }
done
# Two shards that measured the same figure are refused by name.
if "$bin" merge "$out/shard0" "$out/shard0" --results "$out/refused" --quiet 2> "$out/err.txt"; then
  echo "FAIL: merging a shard with itself was accepted"; exit 1
fi
grep -q "spatialbench: error: key .* shards must hold disjoint cases" "$out/err.txt" ||
  { echo "FAIL: the overlap error does not say so:"; cat "$out/err.txt"; exit 1; }
echo "ok: $shards shards of every suite and a scene merge to the single run's keys and answers, every row validated"
