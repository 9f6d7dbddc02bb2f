#!/usr/bin/env bash
# Fuzzing (docs/fuzzing.md): configure and build the fuzz preset (clang, libFuzzer, address and
# undefined-behaviour sanitizers), then run every fuzz target for SECONDS each (default 60) on a
# scratch copy of its seed corpus, so the committed corpus is not polluted. Prints, per target,
# the executions run and what was found; exits non-zero when any target found a crash, a leak,
# a timeout, an out-of-memory or a wrong answer (its input is kept in the scratch directory).
#
#   scripts/fuzz.sh [SECONDS]
#   FUZZ_BUILD_JOBS=1            build jobs, and targets fuzzed at once (default: all cores)
#   SPATIAL_FUZZ_FULL_MATRIX=ON  the operations target over every structure and object type
#                                (about 5 more minutes of build; fuzz/operations/structure_table.hpp)
#   FUZZ_WORK_DIR=DIR            the scratch directory (default: a new one under /tmp)
set -euo pipefail
cd "$(dirname "$0")/.."

seconds="${1:-60}"
[[ "$seconds" =~ ^[0-9]+$ ]] || { echo "usage: scripts/fuzz.sh [seconds per target]" >&2; exit 2; }
jobs="${FUZZ_BUILD_JOBS:-$(nproc)}"
work="${FUZZ_WORK_DIR:-$(mktemp -d /tmp/spatial_fuzz.XXXXXX)}"
mkdir -p "$work"
build=build/fuzz/fuzz

phase() { echo "== $1 (at ${SECONDS} s)"; }

scripts/install_deps.sh
phase "configure (fuzz preset)"
cmake --preset fuzz -DSPATIAL_FUZZ_FULL_MATRIX="${SPATIAL_FUZZ_FULL_MATRIX:-OFF}" > "$work/configure.log"
phase "build"
cmake --build --preset fuzz -j"$jobs"

# target, -max_len, -len_control, extra seed directories (besides fuzz/corpus/<target>).
# The file seeds are below 2 KB. For operations, length is depth: libFuzzer's default length
# control (100) kept its inputs at 14 bytes (3 operations) for minutes, and the findings that
# need a few dozen operations were not reached; 0 lets mutations use the full 4 KB (several
# hundred operations) at once, at fewer executions per second.
targets=(
  "scene_file 4096 100 datasets/scenes"
  "point_set 4096 100"
  "mesh 4096 100"
  "command_line 1024 100"
  "operations 4096 0"
)

# Sanitizer reports with their stacks, by file and line (the preset aborts on the first UBSan
# report).
source scripts/sanitizer_env.sh
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1}"

# One target's run: its summary line goes to $work/<target>.summary, and its report (the
# findings' first lines, stack and bytes) to $work/<target>.report, which stays empty unless
# something was found.
run_target() {
  local name="$1" max_len="$2" len_control="$3" extra="${4:-}"
  local binary="$build/fuzz_$name" report="$work/$name.report"
  : > "$report"
  if [[ ! -x "$binary" ]]; then
    printf '%-12s not built (see fuzz/CMakeLists.txt)\n' "$name" > "$work/$name.summary"
    return
  fi
  local corpus="$work/corpus/$name" artifacts="$work/artifacts/$name/"
  mkdir -p "$corpus" "$artifacts"
  cp fuzz/corpus/"$name"/* "$corpus"/ 2>/dev/null || true
  [[ -n "$extra" ]] && cp "$extra"/* "$corpus"/
  local dict=()
  [[ -f "fuzz/dict/$name.dict" ]] && dict=(-dict="fuzz/dict/$name.dict")
  phase "fuzz $name for $seconds s"
  local status=0
  # -timeout: seconds per input before it counts as a hang: 120, because a legitimate input can
  # take half a minute under the sanitizers on a loaded machine (a hashed_grid object spanning
  # millions of cells, up to its documented 2^24, is listed in, and checked in, every one of
  # them; docs/fuzzing.md); -rss_limit_mb: libFuzzer's default,
  # stated. UBSan reports abort (the preset's -fno-sanitize-recover); leaks are checked (ASan).
  "$binary" -max_total_time="$seconds" -max_len="$max_len" -len_control="$len_control" -timeout=120 -rss_limit_mb=2048 \
    -print_final_stats=1 -artifact_prefix="$artifacts" "${dict[@]}" "$corpus" > "$work/$name.log" 2>&1 || status=$?
  local runs found slow
  runs="$(sed -n 's/^stat::number_of_executed_units: *//p' "$work/$name.log" | tail -n 1)"
  # Findings are crash-, leak-, timeout- and oom- files. A slow-unit- file (an input that ran
  # past libFuzzer's -report_slow_units, 10 s: hashed_grid boxes spanning millions of cells do
  # under the sanitizers on a loaded machine) is reported, not failed: -timeout judges hangs.
  found="$(ls "$artifacts" 2>/dev/null | grep -v '^slow-unit-' || true)"
  slow="$(ls "$artifacts" 2>/dev/null | grep -c '^slow-unit-' || true)"
  if [[ $status -eq 0 && -z "$found" ]]; then
    printf '%-12s %10s executions  nothing found (%s slow units)\n' "$name" "${runs:-?}" "${slow:-0}" > "$work/$name.summary"
    return
  fi
  {
    echo "$name:"
    grep -a -m 3 -E 'FINDING|ERROR:|SUMMARY:|runtime error' "$work/$name.log" | sed 's/^/    /' || true
    # The first report's stack, and each finding's bytes: CI keeps only this log, not the
    # scratch directory, so a finding made there must be reproducible from what is printed
    # (echo BASE64 | base64 -d > input; replay it as the last line says).
    grep -a -m 16 -E '^ *#[0-9]+ 0x' "$work/$name.log" | sed 's/^ */    /' || true
    for input in $found; do
      [[ -f "$artifacts/$input" ]] || continue
      echo "    input $input ($(stat -c %s "$artifacts/$input") bytes), base64:"
      head -c 8192 "$artifacts/$input" | base64 -w 0 | sed 's/^/    /'
      echo
    done
  } > "$report"
  printf '%-12s %10s executions  FOUND: %s (exit %d; log %s)\n' "$name" "${runs:-?}" \
    "${found:-no input saved}" "$status" "$work/$name.log" > "$work/$name.summary"
}

# The targets run side by side, as many at a time as there are build jobs (each is one
# process on one core): in CI's 2 cores the five short runs take three budgets, not five.
running=0
for entry in "${targets[@]}"; do
  read -r name max_len len_control extra <<< "$entry"
  run_target "$name" "$max_len" "$len_control" "${extra:-}" &
  running=$((running + 1))
  if ((running >= jobs)); then
    wait -n || true  # a run that stopped early shows below, as a target without a summary
    running=$((running - 1))
  fi
done
wait || true

failed=0
summary=()
for entry in "${targets[@]}"; do
  read -r name _ <<< "$entry"
  if [[ ! -f "$work/$name.summary" ]]; then
    summary+=("$(printf '%-12s stopped before its summary (log %s)' "$name" "$work/$name.log")")
    failed=1
    continue
  fi
  cat "$work/$name.report"
  summary+=("$(cat "$work/$name.summary")")
  if [[ -s "$work/$name.report" ]]; then failed=1; fi
done

phase "done"
printf '%s\n' "${summary[@]}"
if [[ $failed -ne 0 ]]; then
  echo "fuzz: findings above; inputs in $work/artifacts (replay: $build/fuzz_<target> <input>)"
  exit 1
fi
rm -rf "$work"
