# The check shared by tests/check_shards.sh and tests/check_slurm.sh (which source this file; it
# does nothing on its own): merged tables against the single run's.
#
# check_merged_tables MERGED_DIR RUN_ID_PATTERN SINGLE_RUN_TABLE...
#   the tables of MERGED_DIR named like the single run's have its keys and our structures'
#   answers (tests/check_table_keys.py), every row is validated, and every row's run id matches
#   the glob RUN_ID_PATTERN and names a sidecar in MERGED_DIR/runs that records its host.
#   Prints the hosts' lines; exits 1 with a FAIL line on stderr otherwise.
check_merged_tables() {
  local merged_dir="$1" pattern="$2" here table run_id sidecar
  shift 2
  here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
  /usr/bin/python3 "$here/check_table_keys.py" --write "$merged_dir/../single_keys.csv" "$@"
  local merged=()
  for table in "$@"; do merged+=("$merged_dir/$(basename "$table")"); done
  /usr/bin/python3 "$here/check_table_keys.py" "$merged_dir/../single_keys.csv" "${merged[@]}"
  for table in "${merged[@]}"; do
    awk -F, 'NR == 1 { for (c = 1; c <= NF; ++c) if ($c == "validated") v = c; next }
             $v != "true" { bad++ } END { exit bad > 0 }' "$table" ||
      { echo "FAIL: $table has rows that are not validated" >&2; exit 1; }
  done
  for run_id in $(awk -F, 'FNR == 1 { for (c = 1; c <= NF; ++c) if ($c == "run_id") r = c; next } { print $r }' "${merged[@]}" | sort -u); do
    # shellcheck disable=SC2053  # the pattern is a glob on purpose
    [[ "$run_id" == $pattern ]] || { echo "FAIL: run id $run_id does not match $pattern" >&2; exit 1; }
    sidecar="$merged_dir/runs/$run_id.json"
    [[ -s "$sidecar" ]] || { echo "FAIL: merged rows name run $run_id, whose sidecar is missing" >&2; exit 1; }
    grep -o '"host": *"[^"]*"' "$sidecar" || { echo "FAIL: sidecar $run_id names no host" >&2; exit 1; }
  done
}
