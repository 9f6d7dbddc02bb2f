#!/usr/bin/env bash
# The real data end to end: the knn suite on every fetched point set (datasets/real/, put there
# by datasets/fetch_real_data.sh) and the raycast suite on the smallest fetched mesh
# (datasets/real/meshes/pig.stl, by scripts/fetch_meshes.sh), at smoke size; each must write
# validated rows for every real workload. scripts/test.sh fetches both before the tests, so CI
# runs this; elsewhere it is skipped (exit 77), saying how to fetch.
# Usage: check_real_data_smoke.sh SPATIALBENCH_BINARY REAL_DATA_DIR OUTPUT_DIR
set -euo pipefail
bin="$1"
real="$2"
out="$3"
[[ -d "$real" ]] || { echo "SKIPPED: no $real (run datasets/fetch_real_data.sh)"; exit 77; }
[[ -s "$real/meshes/pig.stl" ]] || { echo "SKIPPED: no $real/meshes/pig.stl (run scripts/fetch_meshes.sh)"; exit 77; }
rm -rf "$out"
mkdir -p "$out/mesh"
ln -s "$(cd "$real/meshes" && pwd)/pig.stl" "$out/mesh/pig.stl"

"$bin" run --suite knn --preset smoke --real-data "$real" --no-dynamic --quiet --results "$out"
"$bin" run --suite raycast --preset smoke --real-data "$out/mesh" --quiet --results "$out"

# Rows per real workload (column 4) and validated (by the header's name), per table.
summary() {
  awk -F, 'FNR == 1 { for (c = 1; c <= NF; ++c) if ($c == "validated") v = c; next }
           $4 ~ /^real:/ { rows[$4]++; if ($v != "true") bad[$4]++ }
           END { for (w in rows) printf "%s %d %d\n", w, rows[w], bad[w] + 0 }' "$1" | sort
}
point_sets=$(find "$real" -maxdepth 1 -type f \( -name '*.xyz' -o -name '*.ply' -o -name '*.pwn' -o -name '*.off' \) | wc -l)
knn_workloads=$(summary "$out/knn.csv" | wc -l)
summary "$out/knn.csv"
summary "$out/raycast.csv"
((knn_workloads > 0)) || { echo "FAIL: no real point set in knn.csv ($point_sets files in $real)"; exit 1; }
summary "$out/raycast.csv" | grep -q '^real:pig.stl ' || { echo "FAIL: no real:pig.stl rows in raycast.csv"; exit 1; }
if summary "$out/knn.csv" "$out/raycast.csv" | awk '$3 > 0 { bad = 1 } END { exit !bad }'; then
  echo "FAIL: real-data rows that are not validated"; exit 1
fi
echo "ok: $knn_workloads real point sets in knn.csv and real:pig.stl in raycast.csv, every row validated"
