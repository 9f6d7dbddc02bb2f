#!/bin/bash
# scripts/drop_keys_held_elsewhere.py: a main table loses exactly the rows whose key a side
# table holds (the other rows unchanged, in order); a table without the key columns is refused
# naming it. Usage: check_drop_keys.sh SOURCE_DIR WORK_DIR
set -euo pipefail
source_dir=$1 work=$2
rm -rf "$work" && mkdir -p "$work"
header=suite,structure,bv,workload,n,dim,scalar,operation,params,metric,value,unit,validated,run_id,repetitions,min,max,check
cat > "$work/main.csv" <<CSV
$header
knn,kd_tree,,uniform,1000000,3,double,knn,k=1,time_per_op,900,ns,true,main-run,5,880,950,oracle:sample=200
knn,kd_tree,,uniform,1000000,3,double,knn_batch,k=10;order=morton,time_per_op,700,ns,true,main-run,5,690,720,oracle:sample=200
knn,bvh,,uniform,1000000,3,double,insert_bulk,into=empty;m=n,time,0.2,s,true,main-run,5,0.19,0.21,contents:all
knn,kd_tree,,uniform,100000,3,double,knn,k=1,time_per_op,500,ns,true,main-run,5,490,520,oracle:sample=200
CSV
cat > "$work/side.csv" <<CSV
$header
knn,kd_tree,,uniform,1000000,3,double,knn_batch,k=10;order=morton,time_per_op,650,ns,true,side-run,5,640,660,oracle:sample=200
knn,bvh,,uniform,1000000,3,double,insert_bulk,into=empty;m=n,time,0.25,s,true,side-run,5,0.24,0.26,contents:all
CSV
fail() { echo "check_drop_keys: $1"; cat "$work/main.csv"; exit 1; }
/usr/bin/python3 "$source_dir/scripts/drop_keys_held_elsewhere.py" "$work/main.csv" "$work/side.csv" "$work/absent.csv" > "$work/out.txt"
grep -q "2 row(s) whose key" "$work/out.txt" || fail "expected 2 rows taken out: $(cat "$work/out.txt")"
grep -q "absent.csv: no such table, skipped" "$work/out.txt" || fail "a missing side table is not reported"
[[ $(wc -l < "$work/main.csv") == 3 ]] || fail "expected the header and 2 rows"
grep -q "^knn,kd_tree,,uniform,1000000,3,double,knn,k=1," "$work/main.csv" || fail "a row the side table lacks was taken out"
grep -q "^knn,kd_tree,,uniform,100000,3,double,knn,k=1," "$work/main.csv" || fail "a row at another size was taken out"
if grep -q "main-run.*knn_batch\|knn_batch.*main-run\|insert_bulk" "$work/main.csv"; then fail "a row the side table holds is still there"; fi
printf 'name,value\nx,1\n' > "$work/not_a_table.csv"
if /usr/bin/python3 "$source_dir/scripts/drop_keys_held_elsewhere.py" "$work/main.csv" "$work/not_a_table.csv" 2> "$work/err.txt"; then
    fail "a side table without the key columns was accepted"
fi
grep -q "not_a_table.csv: no column suite" "$work/err.txt" || fail "the refusal does not name the file: $(cat "$work/err.txt")"
echo "check_drop_keys: side tables' keys taken out, the rest kept"
