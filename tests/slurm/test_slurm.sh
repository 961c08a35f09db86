#!/usr/bin/env bash
# `sdfgen batch` under a real Slurm: starts a private one-node cluster (Debian's slurm-wlm and
# munge) in a scratch folder, submits the batch as a 4-task job array with `sbatch --wait` over a
# generated dataset with broken meshes, checks every output and status line, resubmits and checks
# that nothing is baked again, then stops the daemons by PID and removes everything, also on failure.
#
# The cluster is isolated from any system Slurm or munge (their Debian services may be running):
# its own munge key and socket, its own slurm.conf (SLURM_CONF), ports, state and spool folders.
# Needs root (slurmd runs jobs as their users); skipped with exit 77 (ctest SKIP) when not root or
# when the packages are missing.
# usage: test_slurm.sh SDFGEN_BINARY
set -u
sdfgen=$(realpath "$1")
python=/usr/bin/python3

skip() {
  echo "SKIPPED: $*"
  exit 77
}
[ "$(id -u)" -eq 0 ] || skip "the Slurm test needs root (it starts slurmctld, slurmd and munged); run ctest as root"
for tool in munged slurmctld slurmd sbatch sinfo squeue; do
  command -v $tool >/dev/null || skip "$tool not found: install the Debian packages slurm-wlm and munge (scripts/setup.sh)"
done

work=$(mktemp -d /tmp/sdfgen-slurm.XXXXXX)
chmod 755 "$work" # munged wants its socket folder not writable by others; slurmd's jobs read the dataset
cleanup() {
  for pidfile in "$work/slurmd.pid" "$work/slurmctld.pid" "$work/munged.pid"; do
    [ -s "$pidfile" ] || continue
    pid=$(cat "$pidfile")
    kill "$pid" 2>/dev/null
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$pid" 2>/dev/null
  done
  if [ "${failed:-1}" -ne 0 ]; then
    for log in "$work"/*.log "$work"/logs/*; do [ -f "$log" ] && { echo "--- $log"; tail -15 "$log"; }; done
  fi
  rm -rf "$work"
}
trap cleanup EXIT
trap 'exit 1' INT TERM
. "$(dirname "$0")/../support/check.sh"

# poll SECONDS COMMAND...: until the command succeeds or the deadline passes.
poll() {
  local deadline=$(($(date +%s) + $1))
  shift
  until "$@" >/dev/null 2>&1; do
    [ "$(date +%s)" -lt $deadline ] || return 1
    sleep 0.2
  done
}

# --- munge, private: own key, socket, pid and log.
dd if=/dev/urandom of="$work/munge.key" bs=1024 count=1 status=none
chmod 400 "$work/munge.key"
munged --force --key-file="$work/munge.key" --socket="$work/munge.socket" --pid-file="$work/munged.pid" \
  --log-file="$work/munged.log" --seed-file="$work/munged.seed" ||
  { failed=1; echo "FAILED: munged did not start"; exit 1; }
poll 10 test -S "$work/munge.socket" || { failed=1; echo "FAILED: munged made no socket"; exit 1; }

# --- Slurm: one node (this machine), ports away from Slurm's defaults (a system slurmctld may hold those).
# The node claims 4 CPUs whatever it has (config_overrides) so that the four array tasks run at once;
# sched/builtin starts each job as soon as it fits, without backfill's periodic passes.
host=$(hostname -s)
port=$((20000 + $$ % 20000))
mkdir -p "$work/state" "$work/spool" "$work/logs"
export SLURM_CONF=$work/slurm.conf
cat >"$SLURM_CONF" <<EOF
ClusterName=sdfgentest
SlurmctldHost=$host
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$work/munge.socket
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
SchedulerType=sched/builtin
SlurmdParameters=config_overrides
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
ReturnToService=2
NodeName=$host CPUs=4 State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
slurmctld -f "$SLURM_CONF" || { failed=1; echo "FAILED: slurmctld did not start"; exit 1; }
slurmd -f "$SLURM_CONF" || { failed=1; echo "FAILED: slurmd did not start"; exit 1; }
node_idle() { sinfo -h -N -o '%T' | grep -qx idle; }
poll 30 node_idle || { failed=1; echo "FAILED: the node is not idle after 30 s: $(sinfo -N 2>&1)"; exit 1; }

# --- The dataset: a list with five good meshes (one in a subfolder, one open) and two broken ones.
data=$work/data
mkdir -p "$data/sub"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' >"$data/tet.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' >"$data/sub/open.obj"
printf 'v 0 0 0\nv 3 0 0\nv 0 3 0\nv 0 0 3\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' >"$data/sub/tet.obj"
printf 'v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\nf 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n' >"$data/octahedron.obj"
printf 'v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n' >"$data/cube.obj"
printf 'v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n' >"$data/broken.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n' >"$data/bad-index.obj"
(cd "$data" && printf '%s\n' tet.obj sub/open.obj sub/tet.obj octahedron.obj cube.obj broken.obj bad-index.obj) >"$data/list.txt"
cat >"$work/job.sh" <<EOF
#!/bin/bash
exec "$sdfgen" batch "$data/list.txt" --out "$work/out" --format sdf --res 16 --status "$work/status.jsonl"
EOF
chmod +x "$work/job.sh"

submit() { # submit RUN: one job array of four tasks, waiting for it; logs in logs/RUN.TASK
  timeout 120 sbatch --array=0-3 --wait -o "$work/logs/$1.%a" -e "$work/logs/$1.%a" "$work/job.sh"
}
submit first >"$work/sbatch1.txt" 2>&1
rc=$?
check "sbatch --wait reports the failed meshes' task (exit $rc)" test $rc -ne 0 -a $rc -ne 124
check "four array tasks ran" bash -c "ls '$work/logs' | grep -c '^first\.[0-3]$' | grep -qx 4"
check "every task printed its summary" bash -c "grep -l 'batch summary: shard [0-3]/4' '$work'/logs/first.* | wc -l | grep -qx 4"
for mesh in tet sub/open sub/tet octahedron cube; do
  check "$mesh has its output, equal to sdfgen bake's" bash -c "
    '$sdfgen' bake '$data/$mesh.obj' -o '$work/direct.sdf' --res 16 >/dev/null && '$sdfgen' compare '$work/direct.sdf' '$work/out/$mesh.sdf' | grep -q 'max 0 '"
done
check "no output for the broken meshes, no partial files" bash -c "test ! -e '$work/out/broken.sdf' -a ! -e '$work/out/bad-index.sdf' && test -z \"\$(find '$work/out' -name '.*')\""
check "one status line per mesh, each mesh in exactly one of the four shards" json_check "$work/status.jsonl" '
len(lines) == 7 and len({l["mesh"] for l in lines}) == 7
and sorted(l["shard"] for l in lines) == ["0/4", "0/4", "1/4", "1/4", "2/4", "2/4", "3/4"]
and all(l["status"] == "done" and l["error"] is None and max(l["dims"]) == 16 and l["voxel"] > 0 and l["sign"].startswith("auto/")
        for l in lines if "broken" not in l["mesh"] and "bad-index" not in l["mesh"])
and [l["sign"] for l in lines if l["mesh"].endswith("sub/open.obj")] == ["auto/winding"]
and [l["status"] for l in lines if "broken" in l["mesh"] or "bad-index" in l["mesh"]] == ["failed", "failed"]
and "broken.obj:2: vertex coordinate" in [l for l in lines if "broken" in l["mesh"]][0]["error"]
and "bad-index.obj" in [l for l in lines if "bad-index" in l["mesh"]][0]["error"]'

# The same job again: every finished mesh is skipped (files untouched), the broken ones fail again.
stat -c '%n %i %y' "$work"/out/*.sdf "$work"/out/sub/*.sdf >"$work/before.txt"
submit second >"$work/sbatch2.txt" 2>&1
check "the second run skipped every finished mesh and baked nothing" json_check "$work/status.jsonl" '
len(lines) == 14 and sorted(l["status"] for l in lines[7:]) == ["failed"] * 2 + ["skipped"] * 5
and sorted(l["mesh"] for l in lines[7:]) == sorted(l["mesh"] for l in lines[:7])'
stat -c '%n %i %y' "$work"/out/*.sdf "$work"/out/sub/*.sdf >"$work/after.txt"
check "the outputs were not rewritten" cmp "$work/before.txt" "$work/after.txt"
check "no job is left in the queue" bash -c "test -z \"\$(squeue -h)\""

check_summary slurm
