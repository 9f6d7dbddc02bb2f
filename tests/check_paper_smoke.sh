#!/usr/bin/env bash
# The paper on smoke tables: run every suite's smoke preset and one scene into a temporary
# results folder, run the paper tests on them (lint, every key generated and validated, every
# number read back), and build the PDF from them with scripts/paper.sh.
# Usage: tests/check_paper_smoke.sh path/to/spatialbench
set -euo pipefail
cd "$(dirname "$0")/.."
harness="$(realpath "${1:?usage: $0 path/to/spatialbench}")"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

for suite in knn structures bv raycast collide; do
  "$harness" run --suite "$suite" --preset smoke --results "$work/results" --quiet
done
"$harness" scene datasets/scenes/falling_boxes.toml --structure all --steps 3 \
  --results "$work/results" --quiet
PAPER_RESULTS="$work/results" /usr/bin/python3 -m unittest discover -s paper/tests -t paper
scripts/paper.sh "$work/results" "$work/spatialbench.pdf"
test -s "$work/spatialbench.pdf"
echo "check_paper_smoke: the paper builds from smoke tables"
