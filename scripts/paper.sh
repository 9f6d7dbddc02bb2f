#!/usr/bin/env bash
# Builds the paper from a results folder: the plotting package draws the figures the paper uses
# as vector PDF into paper/generated/figures/ (with runs.json: the run ids of each figure's
# rows), paper/generate.py writes paper/generated/ (every quoted value with its provenance, the
# tables, the run facts, the figures' run lists for the captions), and latexmk builds the PDF.
# Usage: scripts/paper.sh [results_dir (default results)] [output pdf (default paper/spatialbench.pdf)]
set -euo pipefail
cd "$(dirname "$0")/.."
results="$(realpath "${1:-results}")"
output="$(realpath -m "${2:-paper/spatialbench.pdf}")"
# The figure families the paper includes (not the complexity family's hundred curves, nor the
# ratio grids, which have too many panels for a printed page).
families=bv_tradeoff,bvh_tradeoff,raycast,collide,scenes,summary

rm -rf paper/generated paper/build
mkdir -p paper/generated/figures
/usr/bin/python3 plots/plot_results.py --results "$results" --out paper/generated/figures \
  --formats pdf --families "$families" --runs-manifest paper/generated/figures/runs.json > /dev/null
/usr/bin/python3 paper/generate.py --results "$results" --out paper/generated \
  --figure-runs paper/generated/figures/runs.json
(cd paper && latexmk -pdf -interaction=nonstopmode -halt-on-error -output-directory=build \
  spatialbench.tex > build.log 2>&1) || { tail -40 paper/build.log; exit 1; }
cp paper/build/spatialbench.pdf "$output"
echo "paper: $output"
