#!/usr/bin/env bash
# scripts/slurm-sweep.sh on a one-node Slurm cluster brought up inside this machine
# (munged, slurmctld -D, slurmd -D, all state under a temporary folder; no systemd):
# a 4-task sweep array with one task cancelled while it runs, resubmitted with
# --resume (the task resumes from its journal), then the merge job; the merged CSV
# must equal a single-machine `atmosh sweep` cell for cell (timing columns aside).
#
#   slurm_sweep_test.sh ATMOSH_BIN SOURCE_DIR
# Exit 77 (ctest: skipped) where the daemons are not installed or we are not root.
set -euo pipefail
atmosh=$1 src=$2
skip() { echo "SKIP: $*"; exit 77; }
for p in munged slurmctld slurmd sbatch squeue sinfo scancel; do
  command -v "$p" >/dev/null || [ -x "/usr/sbin/$p" ] || skip "$p not installed"
done
[ "$(id -u)" = 0 ] || skip "starting slurmd needs root"
export PATH=$PATH:/usr/sbin

t=$(mktemp -d /tmp/atmosh-slurm.XXXXXX)
chmod 700 "$t"
pids=()
cleanup() {
  set +e
  # Jobs still queued or running on this test's cluster (a failed run), then the
  # daemons started here, each by its own process id.
  if [ ${#pids[@]} -ge 2 ] && [ -n "$(timeout 5 squeue -h -o %i 2>/dev/null)" ]; then
    timeout 5 scancel --full -u "$(id -un)" 2>/dev/null
    for _ in $(seq 50); do [ -z "$(timeout 5 squeue -h -o %i 2>/dev/null)" ] && break; sleep 0.1; done
  fi
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do kill "${pids[$i]}" 2>/dev/null; done
  for p in "${pids[@]}"; do
    for _ in $(seq 50); do kill -0 "$p" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$p" 2>/dev/null
  done
  if [ "${KEEP:-0}" = 1 ]; then echo "kept $t"; else rm -rf "$t"; fi
}
trap cleanup EXIT
fail() {
  echo "FAIL: $*" >&2
  for f in "$t"/log/*.log "$t"/out/slurm/*.out; do [ -f "$f" ] && { echo "--- $f"; tail -20 "$f"; } >&2; done
  exit 1
}

# munge: a fresh key, socket, pid, seed and log in the temporary folder.
mkdir -p "$t/munge" "$t/log" "$t/state" "$t/spool"
dd if=/dev/urandom of="$t/munge/munge.key" bs=1 count=1024 status=none
chmod 400 "$t/munge/munge.key"
sock=$t/munge/munge.socket
munged -F --force --key-file="$t/munge/munge.key" --socket="$sock" --pid-file="$t/munge/munged.pid" \
  --seed-file="$t/munge/munged.seed" --log-file="$t/log/munged.log" > "$t/log/munged.stdout" 2>&1 &
pids+=($!)
for _ in $(seq 50); do [ -S "$sock" ] && break; sleep 0.1; done
[ -S "$sock" ] || fail "munged did not start"

# Ports from the process id, so two runs of this test on one machine do not meet.
port=$((20000 + ($$ % 20000) * 2))
cat > "$t/slurm.conf" <<EOF
ClusterName=atmoshtest
SlurmctldHost=localhost
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$sock
StateSaveLocation=$t/state
SlurmdSpoolDir=$t/spool/slurmd-%n
SlurmctldPidFile=$t/slurmctld.pid
SlurmdPidFile=$t/slurmd.pid
SlurmctldLogFile=$t/log/slurmctld.log
SlurmdLogFile=$t/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
ReturnToService=2
SlurmdParameters=config_overrides
SchedulerParameters=sched_interval=1
MessageTimeout=10
NodeName=localhost NodeAddr=127.0.0.1 CPUs=2 State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF=$t/slurm.conf
slurmctld -D -i -f "$SLURM_CONF" >> "$t/log/slurmctld.stdout" 2>&1 &
pids+=($!)
slurmd -D -N localhost -f "$SLURM_CONF" >> "$t/log/slurmd.stdout" 2>&1 &
pids+=($!)
up=0
for _ in $(seq 300); do
  if sinfo -h -N -o '%t' 2>/dev/null | grep -qx idle; then up=1; break; fi
  sleep 0.1
done
[ "$up" = 1 ] || fail "the node did not become idle"
echo "cluster up ($(sinfo -h -N -o '%N %t %c'))"

# A 32-point sweep (4 shards of 8 points), single scattering so each point is short.
cat > "$t/sweep.toml" <<'EOF'
version = 1
mode = "grid"
[[parameter]]
key = "sun.elevation_deg"
from = 2.0
to = 77.0
count = 16
[[parameter]]
key = "mie.scattering_per_m"
values = [2e-6, 8e-6]
[[parameter]]
key = "spectrum.count"
values = [32]
EOF
args="--scattering single --shells 128 --segments 64 --samples 8"
out=$t/out
submit=$("$src/scripts/slurm-sweep.sh" --shards 4 --atmosh "$atmosh" --sweep-args "$args" \
  "$t/sweep.toml" "$out" --cpus-per-task=1) || fail "slurm-sweep.sh failed: $submit"
echo "$submit"
array=$(sed -n 's/^array job: \([0-9]*\).*/\1/p' <<<"$submit")
merge=$(sed -n 's/^merge job: \([0-9]*\).*/\1/p' <<<"$submit")
[ -n "$array" ] || fail "no array job id in: $submit"
[ -n "$merge" ] || fail "no job ids in: $submit"

# The single-machine reference meanwhile (same quality, one thread like each task).
# shellcheck disable=SC2086
"$atmosh" sweep "$t/sweep.toml" -o "$t/single" --threads 1 $args > "$t/single.out" 2>&1 &
single=$!

# Cancel array task 1 (shard 2) once its journal holds a finished point.
journal=$out/.sweep.shard-2-of-4.journal
killed=0
for _ in $(seq 1200); do
  if [ -f "$journal" ] && [ "$(grep -c '^[0-9]' "$journal" || true)" -ge 1 ]; then
    scancel "${array}_1" && killed=1
    break
  fi
  sleep 0.05
done
[ "$killed" = 1 ] || fail "shard 2 never started writing its journal"

# The other tasks finish; the merge now waits on a dependency that can never be met.
for _ in $(seq 1200); do
  [ -z "$(squeue -h -j "$array" -o %i 2>/dev/null)" ] && break
  sleep 0.1
done
[ -z "$(squeue -h -j "$array" -o %i)" ] || fail "array $array did not finish"
[ ! -f "$out/sweep.shard-2-of-4.csv" ] || fail "shard 2 completed before it was cancelled (no resume tested)"
for k in 1 3 4; do [ -f "$out/sweep.shard-$k-of-4.csv" ] || fail "shard $k missing"; done
[ -f "$journal" ] || fail "the cancelled shard left no journal"
done_before=$(grep -c '^[0-9]' "$journal" || true)
echo "shard 2 cancelled with $done_before point(s) in its journal"

resub=$("$src/scripts/slurm-sweep.sh" --resume "$out") || fail "--resume failed: $resub"
echo "$resub"
grep -q 'tasks 1 of 4' <<<"$resub" || fail "--resume should resubmit task 1 only: $resub"
merge2=$(sed -n 's/^merge job: \([0-9]*\).*/\1/p' <<<"$resub")
for _ in $(seq 1200); do
  [ -z "$(squeue -h -j "$merge2" -o %i 2>/dev/null)" ] && [ -f "$out/sweep.csv" ] && break
  sleep 0.1
done
[ -f "$out/sweep.csv" ] || fail "the merge job wrote no sweep.csv"
[ -z "$(squeue -h -j "$merge" -o %i 2>/dev/null)" ] || fail "the first merge job $merge is still queued"
resumed=$(sed -n 's/.*(\([0-9]*\) resumed.*/\1/p' "$out"/slurm/shard-1.out | tail -1)
[ "${resumed:-0}" -ge 1 ] || fail "the resubmitted shard resumed no point: $(cat "$out"/slurm/shard-1.out)"
echo "resubmitted shard 2 resumed $resumed point(s)"

wait "$single" || fail "single-machine sweep failed: $(cat "$t/single.out")"

# Cell for cell, without the provenance lines and the timing columns.
strip() {
  awk -F, 'BEGIN{OFS=","} /^#/{next}
    !h{for(i=1;i<=NF;i++) keep[i]=($i !~ /time_s$/); h=1}
    {s=""; for(i=1;i<=NF;i++) if(keep[i]) s=s (s==""?"":",") $i; print s}' "$1"
}
strip "$t/single/sweep.csv" > "$t/a.csv"
strip "$out/sweep.csv" > "$t/b.csv"
rows=$(($(wc -l < "$t/a.csv") - 1))
[ "$rows" = 32 ] || fail "single-machine CSV has $rows rows, expected 32"
head -1 "$t/a.csv" | grep -q zenith_luminance_cd_m2 || fail "unexpected header: $(head -1 "$t/a.csv")"
diff "$t/a.csv" "$t/b.csv" > "$t/diff.txt" || fail "merged CSV differs from the single-machine run: $(head -5 "$t/diff.txt")"
echo "PASS: merged CSV equals the single-machine run ($rows rows)"
