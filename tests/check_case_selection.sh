#!/usr/bin/env bash
# Suites are lists of cases with stable ids (harness/include/harness/suite_cases.hpp):
# `list --cases` prints them, `run --case ID` runs exactly that case, and an unknown id is an
# error that names it. Usage: check_case_selection.sh SPATIALBENCH_BINARY OUTPUT_DIR
set -euo pipefail
bin="$1"
out="$2"
rm -rf "$out"
mkdir -p "$out"

expected=$'collide/boxes/n=1000\ncollide/boxes/n=5000\ncollide/moving_boxes/n=2000\ncollide/triangles/n=2000'
got="$("$bin" list --cases --suite collide --preset smoke)"
[[ "$got" == "$expected" ]] || { echo "FAIL: collide smoke cases:"; echo "$got"; exit 1; }
knn_cases="$("$bin" list --cases --suite knn --preset smoke --workload lattice)"
grep -qx "knn/lattice/n=10000/3d/double" <<< "$knn_cases" || { echo "FAIL: knn case ids:"; echo "$knn_cases"; exit 1; }

"$bin" run --suite collide --preset smoke --case collide/boxes/n=5000 --quiet --results "$out"
# Every row is of that case (workload column 4, n column 5), and there are some.
awk -F, 'NR > 1 { rows++; if ($4 != "boxes" || $5 != "5000") bad++ } END { exit !(rows > 0 && bad == 0) }' "$out/collide.csv" ||
  { echo "FAIL: --case ran more or less than collide/boxes/n=5000"; exit 1; }
# The run's sidecar lists the one case it ran with its wall time (where a preset's time goes).
sidecars=("$out"/runs/collide-*.json)
/usr/bin/python3 - "${sidecars[@]}" <<'PY' || { echo "FAIL: the sidecar's case_seconds"; cat "${sidecars[@]}"; exit 1; }
import json, sys
cases = json.load(open(sys.argv[1]))["case_seconds"]
assert len(sys.argv) == 2 and [c["case"] for c in cases] == ["collide/boxes/n=5000"], cases
assert 0 < cases[0]["seconds"] < 600, cases
PY

if "$bin" run --suite collide --preset smoke --case collide/boxes/n=7 --quiet --results "$out" 2> "$out/err.txt"; then
  echo "FAIL: an unknown case id was accepted"; exit 1
fi
grep -q "unknown case 'collide/boxes/n=7'" "$out/err.txt" || { echo "FAIL: the error does not name the id:"; cat "$out/err.txt"; exit 1; }
echo "ok: case ids listed, one case run alone with its time in the sidecar, an unknown id rejected by name"
