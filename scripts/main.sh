#!/usr/bin/env bash
# The main job: install dependencies, fetch real data, build Release, run the benchmark
# suites knn, structures, bv and raycast (default: the quick preset, < 15 min on 2 cores), write
# results/*.csv and draw plots/*.png.   Usage: scripts/main.sh [smoke|quick|full]
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
for suite in knn structures bv raycast; do
  data_dir="$real_dir"
  [[ "$suite" == raycast ]] && data_dir="$mesh_dir"
  ./build/release/harness/spatialbench run --suite "$suite" --preset "$preset" --results results \
    ${data_dir:+--real-data "$data_dir"}
done

/usr/bin/python3 plots/plot_results.py --results results --out plots
echo "main: results in results/, plots in plots/"
