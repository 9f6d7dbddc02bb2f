#!/usr/bin/env bash
# A sharded run on a real Slurm: starts a single-node Slurm on this machine (munge, slurmctld
# and slurmd from Debian's packages, a generated slurm.conf for localhost), submits the smoke
# preset as a 3-task job array with its dependent merge job (scripts/slurm/submit.sh --wait),
# and checks that the merged tables have the keys and answers of the local smoke run
# (tests/check_table_keys.py), that every row is validated and that every row's run id is of
# the array's family with its sidecar and host.
# Exit 77 (ctest: skipped) with the reason where Slurm cannot start: not root, or the packages
# missing (scripts/install_deps.sh installs them).
# Usage: check_slurm.sh OUTPUT_DIR SINGLE_RUN_TABLE...   (run from anywhere in the checkout)
set -euo pipefail
out="$1"
shift
here="$(cd "$(dirname "$0")" && pwd)"
repo="$(cd "$here/.." && pwd)"
skip() { echo "SKIPPED: $*"; exit 77; }

[[ $(id -u) -eq 0 ]] || skip "a single-node Slurm needs root here (SlurmUser=root)"
for tool in slurmctld slurmd sbatch sinfo munged mungekey; do
  command -v "$tool" > /dev/null || skip "$tool is missing (scripts/install_deps.sh installs slurmctld slurmd slurm-client munge)"
done

pkill -f -- "-f $out/slurm.conf" 2> /dev/null && sleep 1 || true  # a previous run's daemons
rm -rf "$out"
mkdir -p "$out/state" "$out/spool"
node="$(hostname -s)"
started_munge=0
cleanup() {
  # The daemons are found by their configuration file, which is this test's alone.
  pkill -f -- "-f $out/slurm.conf" 2> /dev/null || true
  if ((started_munge)) && [[ -s /run/munge/munged.pid ]]; then kill "$(cat /run/munge/munged.pid)" 2> /dev/null || true; fi
}
trap cleanup EXIT

# munge: a key and the daemon, as the munge user (unless one already answers).
if ! munge -n 2> /dev/null | unmunge > /dev/null 2>&1; then
  [[ -s /etc/munge/munge.key ]] || mungekey -c
  chown munge:munge /etc/munge/munge.key
  chmod 400 /etc/munge/munge.key
  mkdir -p /run/munge /var/lib/munge /var/log/munge
  chown munge:munge /run/munge /var/lib/munge /var/log/munge
  runuser -u munge -- munged
  started_munge=1
  munge -n | unmunge > /dev/null || { echo "FAIL: munged started but does not answer"; exit 1; }
fi

# MinJobAge=10: sbatch --wait polls after 2 s, then multiplies its sleep by 4 while it is under
# MinJobAge / 2 and 32 s (Slurm's sbatch.c, _job_wait); at the default 300 the smoke array's
# 11 s of jobs were seen done only at the 42nd second. With 10 it polls every 8 s at most, and
# a finished job's record still outlives the poll that finds it.
cat > "$out/slurm.conf" << CONF
ClusterName=spatialbench
SlurmctldHost=${node}(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
MpiDefault=none
ReturnToService=2
StateSaveLocation=$out/state
SlurmdSpoolDir=$out/spool
SlurmctldPidFile=$out/slurmctld.pid
SlurmdPidFile=$out/slurmd.pid
SlurmctldLogFile=$out/slurmctld.log
SlurmdLogFile=$out/slurmd.log
SlurmctldPort=6817
SlurmdPort=6818
JobCompType=jobcomp/none
MinJobAge=10
AccountingStorageType=accounting_storage/none
NodeName=${node} NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=local Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$out/slurm.conf"
slurmctld -f "$SLURM_CONF" || skip "slurmctld did not start: $(tail -3 "$out/slurmctld.log" 2> /dev/null)"
slurmd -f "$SLURM_CONF" || skip "slurmd did not start: $(tail -3 "$out/slurmd.log" 2> /dev/null)"
for ((t = 0; t < 60; ++t)); do
  sinfo -h -o %t 2> /dev/null | grep -q idle && break
  sleep 1
done
sinfo -h -o %t | grep -q idle || skip "the node did not become idle in 60 s: $(sinfo 2>&1 | tail -2)"
echo "slurm: $(sinfo -h -o '%P %D %t %c') ($(sbatch --version))"

# The two steps a cluster user runs, the build already done (ctest runs after it); the scenes
# are the smoke fixture's one scene file.
cd "$out"
export SPATIALBENCH_SCENES="$repo/datasets/scenes/falling_boxes.toml"
"$repo/scripts/slurm/submit.sh" --wait --no-build --results "$out/results" --plots "" smoke 3

# Run ids of the array's family (its job id, the shard), each with its sidecar and host.
source "$here/merged_tables_check.sh"
hosts="$(check_merged_tables "$out/results" "*-slurm[0-9]*-shard[0-2]of3" "$@" | grep -o '"[^"]*"$' | sort -u | tr '\n' ' ')"
echo "ok: Slurm ran the smoke preset as 3 array tasks and a dependent merge; the merged tables have the single run's keys and answers, every row validated (hosts: $hosts)"
