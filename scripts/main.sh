#!/usr/bin/env bash
# The main job: install dependencies, fetch real data, build Release, run the benchmark
# suites knn, structures, bv, raycast and collide (default: the quick preset) and every shipped
# scene (datasets/scenes/*.toml), write results/*.csv and draw plots/*.png.
# Last, it builds the paper (scripts/paper.sh) into paper/spatialbench.pdf.
# Usage: scripts/main.sh [smoke|quick|full]
set -euo pipefail
cd "$(dirname "$0")/.."
preset="${1:-quick}"

scripts/install_deps.sh
datasets/fetch_real_data.sh || echo "main: real data unavailable; running generated workloads only"
scripts/fetch_meshes.sh || echo "main: real meshes unavailable; raycast runs generated meshes only"

cmake --preset release -G Ninja
cmake --build --preset release --target spatialbench -j"$(nproc)"

real_dir=datasets/real
mesh_dir=datasets/real/meshes
[[ "$preset" == smoke ]] && real_dir="" && mesh_dir=""   # smoke stays seconds long
for suite in knn structures bv raycast collide; do
  data_dir="$real_dir"
  [[ "$suite" == raycast ]] && data_dir="$mesh_dir"
  ./build/release/harness/spatialbench run --suite "$suite" --preset "$preset" --results results \
    ${data_dir:+--real-data "$data_dir"}
done

# Side tables of dedicated runs (results/README.md: knn_order_1e6.csv, knn_bulk_1e6.csv) hold
# figures the knn run above measured again; each key keeps one row across the tables, theirs.
/usr/bin/python3 scripts/drop_keys_held_elsewhere.py results/knn.csv results/knn_order_1e6.csv results/knn_bulk_1e6.csv

# Scenes: every structure that answers each scene's effects (smoke: 3 steps each; quick: 30).
scene_steps=()
[[ "$preset" == smoke ]] && scene_steps=(--steps 3)
[[ "$preset" == quick ]] && scene_steps=(--steps 30)
./build/release/harness/spatialbench scene datasets/scenes/*.toml --structure all --results results "${scene_steps[@]}"

/usr/bin/python3 scripts/provenance.py --results results   # results/provenance.md: which run made which table
/usr/bin/python3 scripts/scaling.py --results results      # results/scaling.md: fitted cost exponents, memory at the largest n
/usr/bin/python3 plots/plot_results.py --results results --out plots
scripts/paper.sh results paper/spatialbench.pdf
echo "main: results in results/, plots in plots/, the paper in paper/spatialbench.pdf"
