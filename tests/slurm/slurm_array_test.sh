#!/usr/bin/env bash
# A sweep of 200 cases as a Slurm job array on a single-node Slurm started for this test:
# munged, slurmctld and slurmd on localhost (no cgroups, no accounting), all state in a
# temporary folder. Checks that the merged results equal a local run's, that --resume
# submits only a shard whose results are missing, that --no-wait and `clothlab merge` give the
# same rows, and shuts everything down on every exit.
# Needs root and Debian's slurmctld slurmd slurm-client munge (tools/install-deps.sh); without
# them it is skipped (exit 77), or fails when CLOTHLAB_REQUIRE_SLURM=1 (CI).
# Usage: slurm_array_test.sh CLOTHLAB SWEEP_YAML SAME_RESULTS_PY
set -euo pipefail
clothlab=$1 sweep=$2 same_results=$3

unavailable() {
  echo "slurm test: $*" >&2
  if [ "${CLOTHLAB_REQUIRE_SLURM:-0}" = 1 ]; then exit 1; fi
  exit 77
}
[ "$(id -u)" -eq 0 ] || unavailable "needs root (slurmd runs jobs as their user)"
for program in munged mungekey slurmctld slurmd sbatch squeue sinfo scontrol runuser; do
  command -v "$program" > /dev/null || unavailable "$program not found (bash tools/install-deps.sh)"
done
id munge > /dev/null 2>&1 || unavailable "no user munge (Debian package munge)"

work=$(mktemp -d /tmp/clothlab-slurm.XXXXXX)
chmod 755 "$work"  # munged runs as munge and must reach its socket folder
export SLURM_CONF=$work/slurm.conf
munged_pid=
shutdown() {
  local status=$?
  set +e
  if [ -f "$SLURM_CONF" ]; then
    scontrol shutdown > /dev/null 2>&1
    for daemon in slurmctld slurmd; do
      pid=$(cat "$work/$daemon.pid" 2> /dev/null)
      [ -n "$pid" ] || continue
      for _ in $(seq 50); do kill -0 "$pid" 2> /dev/null || break; sleep 0.2; done
      kill -KILL "$pid" 2> /dev/null  # still there after 10 s: stop it hard
    done
  fi
  if [ -n "$munged_pid" ]; then
    kill "$munged_pid" 2> /dev/null
    for _ in $(seq 50); do kill -0 "$munged_pid" 2> /dev/null || break; sleep 0.1; done
  fi
  if [ "$status" -ne 0 ]; then
    for log in "$work"/*.log "$work"/munge/*.log "$work"/slurm/*.log; do
      [ -f "$log" ] && { echo "--- $log"; tail -n 20 "$log"; }
    done
  fi
  rm -rf "$work"
  echo "slurm test: Slurm and munged stopped, $work removed (exit $status)"
  exit "$status"
}
trap shutdown EXIT
trap 'exit 130' INT TERM

# munged as user munge, with its own key and socket.
mkdir -m 755 "$work/munge"
mungekey --create --keyfile="$work/munge/munge.key"
chown -R munge:munge "$work/munge"
chmod 400 "$work/munge/munge.key"
runuser -u munge -- munged --socket="$work/munge/munge.socket" \
  --key-file="$work/munge/munge.key" --pid-file="$work/munge/munged.pid" \
  --log-file="$work/munge/munged.log" --seed-file="$work/munge/munged.seed"
munged_pid=$(cat "$work/munge/munged.pid")

# Ports away from a real Slurm's 6817/6818.
ctld_port=$((20000 + RANDOM % 20000))
node_line=$(slurmd -C | head -n 1 | sed 's/^NodeName=[^ ]*/NodeName=localhost/')
mkdir "$work/state" "$work/spool"
cat > "$SLURM_CONF" << CONF
ClusterName=clothlab-test
SlurmctldHost=localhost
SlurmctldPort=$ctld_port
SlurmdPort=$((ctld_port + 1))
SlurmUser=root
AuthType=auth/munge
AuthInfo=socket=$work/munge/munge.socket
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
ReturnToService=2
$node_line
PartitionName=test Nodes=localhost Default=YES MaxTime=INFINITE State=UP
CONF
slurmctld -c
slurmd -N localhost
for _ in $(seq 60); do
  state=$(sinfo -h -n localhost -o %t 2> /dev/null || true)
  [ "$state" = idle ] && break
  sleep 0.5
done
[ "$state" = idle ] || { echo "slurm test: node not idle after 30 s (state '$state')"; exit 1; }
echo "slurm test: single-node Slurm up ($(sinfo -h -o '%P %D %t %c CPUs'))"

cd "$work"
cp "$sweep" sweep.yaml
"$clothlab" --config sweep.yaml --out local
"$clothlab" --config sweep.yaml --out slurm --slurm --set slurm.tasks=4 --set slurm.time=10
python3 "$same_results" local/slurm-200 slurm/slurm-200

# Lose shard 3's results: --resume must submit that shard alone and merge the same rows again.
rm slurm/slurm-200.shard-3-of-4.sqlite* slurm/slurm-200.csv slurm/slurm-200.json
"$clothlab" --config sweep.yaml --out slurm --slurm --set slurm.tasks=4 --resume | tee resume.txt
grep -q "1 of 4 shard tasks submitted (--array=3)" resume.txt
python3 "$same_results" local/slurm-200 slurm/slurm-200

# --no-wait returns once submitted; `clothlab merge` joins the shards when the queue is empty.
"$clothlab" --config sweep.yaml --out nowait --slurm --set slurm.tasks=5 --no-wait
for _ in $(seq 120); do
  [ -z "$(squeue -h -o %i)" ] && break
  sleep 0.5
done
"$clothlab" merge nowait/slurm-200
python3 "$same_results" local/slurm-200 nowait/slurm-200
echo "slurm test: passed"
