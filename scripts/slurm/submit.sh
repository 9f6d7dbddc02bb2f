#!/usr/bin/env bash
# A sharded benchmark run on a Slurm cluster: builds the harness (once, here), submits one
# job-array task per shard and a merge job that depends on all of them.
#
#   scripts/slurm/submit.sh [--wait] [--no-build] [--results DIR] [--plots DIR] PRESET SHARDS
#
# PRESET is smoke, quick or full; SHARDS the number of array tasks. Shards write to
# DIR.shards/shard<i> (default results.shards/), the merge job to DIR (default results/) and
# the plots to --plots (default plots/; "" for none). --wait blocks until the merge job has
# finished and exits with its status (what tests/check_slurm.sh uses); --no-build takes the
# harness already built: build/release/harness/spatialbench, or the binary SPATIALBENCH names
# (the jobs inherit it; the tests use the ci build's). Run from anywhere in the
# checkout, on a machine that can reach the cluster's controller and shares the checkout's file
# system with the compute nodes. sbatch options (partition, account, time) come from the
# usual SBATCH_* environment variables, e.g. SBATCH_PARTITION=compute.
set -euo pipefail
cd "$(dirname "$0")/../.."
wait=()
build=1
results=results
plots=plots
while [[ $# -gt 0 && "$1" == --* ]]; do
  case "$1" in
    --wait) wait=(--wait); shift ;;
    --no-build) build=0; shift ;;
    --results) results="$2"; shift 2 ;;
    --plots) plots="$2"; shift 2 ;;
    *) echo "submit.sh: unknown option $1" >&2; exit 1 ;;
  esac
done
if [[ $# -ne 2 ]]; then
  echo "usage: scripts/slurm/submit.sh [--wait] [--no-build] [--results DIR] [--plots DIR] smoke|quick|full SHARDS" >&2
  exit 1
fi
preset="$1"
shards="$2"
case "$preset" in smoke | quick | full) ;; *) echo "submit.sh: unknown preset '$preset'" >&2; exit 1 ;; esac
[[ "$shards" =~ ^[1-9][0-9]*$ ]] || { echo "submit.sh: SHARDS must be a positive count, not '$shards'" >&2; exit 1; }

if ((build)); then
  cmake --preset release -G Ninja >/dev/null
  cmake --build --preset release --target spatialbench
fi
export SPATIALBENCH="${SPATIALBENCH:-build/release/harness/spatialbench}"
[[ -x "$SPATIALBENCH" ]] || { echo "submit.sh: $SPATIALBENCH is missing" >&2; exit 1; }
shards_dir="${results}.shards"
rm -rf "$shards_dir"
mkdir -p "$shards_dir"

# The jobs' logs go next to the shards' results, not into the checkout.
array_job="$(sbatch --parsable --array="0-$((shards - 1))" --output="${shards_dir}/shard-%A_%a.out" \
  scripts/slurm/shard.sbatch "$preset" "$shards_dir")"
array_job="${array_job%%;*}"  # --parsable prints "jobid[;cluster]"
echo "submit.sh: shard array job ${array_job} (${shards} tasks, preset ${preset})"
merge_job="$(sbatch --parsable "${wait[@]}" --dependency="afterok:${array_job}" --kill-on-invalid-dep=yes \
  --output="${shards_dir}/merge-%j.out" scripts/slurm/merge.sbatch "$shards_dir" "$results" "$plots")"
echo "submit.sh: merge job ${merge_job%%;*} runs after every shard succeeded"
