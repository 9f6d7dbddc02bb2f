#!/usr/bin/env bash
# Interrupted and resumed runs (harness/include/harness/run_journal.hpp): a run interrupted by
# SIGINT, then by SIGKILL (as the OOM killer would), loses no completed case, leaves the
# previous table as it was, says what it finished and where the journal is; a plain rerun and a
# resume with other options are refused by name; `--resume` then finishes only the missing
# cases and writes a table with the keys and answers of an uninterrupted run, in one run id.
# The interruptions come from SPATIALBENCH_INTERRUPT_AFTER_CASES (fault_injection.hpp), so the
# test does not race the run.
# Usage: check_resume.sh SPATIALBENCH_BINARY OUTPUT_DIR UNINTERRUPTED_RAYCAST_SMOKE_TABLE
set -euo pipefail
bin="$1"
out="$2"
reference="$3"
here="$(cd "$(dirname "$0")" && pwd)"
rm -rf "$out"
mkdir -p "$out"
run=(run --suite raycast --preset smoke --results "$out" --quiet)
journal="$out/raycast.csv.journal"
fail() { echo "FAIL: $*"; exit 1; }

echo "suite,previous,table" > "$out/raycast.csv"  # the previous table: must survive untouched
cp "$out/raycast.csv" "$out/previous.csv"

# 1. Ctrl-C after two cases: exit by SIGINT, the message, the journal, the old table.
set +e
SPATIALBENCH_INTERRUPT_AFTER_CASES=2:INT "$bin" "${run[@]}" 2> "$out/err1.txt"
status=$?
set -e
((status == 130)) || fail "interrupted run exited $status, not by SIGINT (130)"
grep -q "interrupted: 2 case(s) of the raycast suite are finished and kept in $journal" "$out/err1.txt" ||
  fail "no interruption message: $(cat "$out/err1.txt")"
grep -q -- "--resume" "$out/err1.txt" || fail "the message does not say how to resume"
cmp -s "$out/raycast.csv" "$out/previous.csv" || fail "the previous table changed"
(($(wc -l < "$journal/completed.txt") == 2)) || fail "the journal does not hold 2 cases"

# 2. A plain rerun would discard them: refused, naming the journal. Other options: refused too.
if "$bin" "${run[@]}" 2> "$out/err2.txt"; then fail "a rerun without --resume started over the journal"; fi
grep -q "$journal holds the completed cases of an interrupted run" "$out/err2.txt" || fail "$(cat "$out/err2.txt")"
if "$bin" "${run[@]}" --resume --seed 7 2> "$out/err3.txt"; then fail "a resume with another seed was accepted"; fi
grep -q "the interrupted run had seed = " "$out/err3.txt" || fail "$(cat "$out/err3.txt")"
cmp -s "$out/raycast.csv" "$out/previous.csv" || fail "a refused run changed the previous table"

# 3. Resumed, then killed outright (SIGKILL: no handler runs) after one more case.
set +e
SPATIALBENCH_INTERRUPT_AFTER_CASES=1:KILL "$bin" "${run[@]}" --resume 2> "$out/err4.txt"
status=$?
set -e
((status == 137)) || fail "the killed run exited $status, not by SIGKILL (137)"
(($(wc -l < "$journal/completed.txt") == 3)) || fail "the journal does not hold 3 cases after the kill"
cmp -s "$out/raycast.csv" "$out/previous.csv" || fail "the previous table changed"

# 4. Resumed to the end: the journaled cases are not run again, the table is whole and one run.
"$bin" run --suite raycast --preset smoke --results "$out" --resume 2> "$out/err5.txt"
(($(grep -c "^\[.*\] resumed: raycast/" "$out/err5.txt") == 3)) || fail "3 cases should come from the journal: $(grep resumed "$out/err5.txt")"
[[ ! -e "$journal" ]] || fail "the journal is still there after the table was written"
/usr/bin/python3 "$here/check_table_keys.py" --write "$out/reference_keys.csv" "$reference"
/usr/bin/python3 "$here/check_table_keys.py" "$out/reference_keys.csv" "$out/raycast.csv"
run_ids=$(awk -F, 'NR == 1 { for (c = 1; c <= NF; ++c) if ($c == "run_id") r = c; next } { print $r }' "$out/raycast.csv" | sort -u | wc -l)
((run_ids == 1)) || fail "the resumed table has $run_ids run ids, not one"
echo "ok: interrupted twice (SIGINT, SIGKILL), nothing completed lost, previous table intact, resumed to the uninterrupted run's keys and answers"
