#!/usr/bin/env bash
# A run split over a Slurm cluster equals the run in one process: a one-node cluster on this
# machine's loopback (munged, slurmctld and slurmd in the foreground, on ports of their own, in a
# scratch folder, stopped at the end), scripts/slurm-verify's job array of shards and its merge job;
# the merged tables' JSON equal one process's field for field (same_run.js) and its corpus equal
# byte for byte. Then a shard cancelled before it runs: the merge names it missing and fails; the
# shard re-run with the line slurm-verify printed, and the merge again, give the whole run.
# Needs root (slurmd starts the jobs) and Debian's slurmctld, slurmd, slurm-client and munge.
# Usage: slurm_verify.sh CULLPROOF SOURCE-DIR; exits 77 (skipped) when not root.
set -euo pipefail
cullproof=$(realpath "$1")
src=$(realpath "$2")

if [ "$(id -u)" -ne 0 ]; then
  echo "skipped: slurmd must run as root to start jobs"
  exit 77
fi
for p in munged mungekey slurmctld slurmd sbatch sinfo scancel node; do
  command -v "$p" > /dev/null || { echo "FAIL: $p is not installed (scripts/install-deps installs it)"; exit 1; }
done

dir=$(mktemp -d /tmp/cullproof-slurm.XXXXXX)
chmod 755 "$dir"
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2> /dev/null || true; done
  for p in "${pids[@]}"; do wait "$p" 2> /dev/null || true; done
  if [ "${keep:-0}" = 1 ]; then echo "kept: $dir"; else rm -rf "$dir"; fi
}
trap cleanup EXIT
fail() {
  echo "FAIL: $*"
  for f in "$dir"/log/*.log; do echo "--- $f"; tail -n 20 "$f"; done
  keep=1
  exit 1
}

# Two free ports on the loopback (nothing answers there).
free_port() {
  local p
  for p in $(seq "$1" 2 "$(($1 + 200))"); do
    if ! (exec 3<> "/dev/tcp/127.0.0.1/$p") 2> /dev/null; then echo "$p"; return; fi
  done
  fail "no free port from $1"
}
ctld_port=$(free_port $((26800 + ($$ % 50) * 4)))
d_port=$(free_port $((ctld_port + 1)))

mkdir -p "$dir"/{munge,state,spool,log}
chmod 700 "$dir/munge"
mungekey --create --keyfile="$dir/munge/key" --bits=1024
munged --foreground --force --socket="$dir/munge/socket" --key-file="$dir/munge/key" --pid-file="$dir/munge/pid" \
  --seed-file="$dir/munge/seed" --log-file="$dir/log/munged.log" 2>> "$dir/log/munged.log" &
pids+=($!)
for _ in $(seq 50); do [ -S "$dir/munge/socket" ] && break; sleep 0.1; done
[ -S "$dir/munge/socket" ] || fail "munged did not start"
chmod 755 "$dir/munge"

cat > "$dir/slurm.conf" <<EOF
ClusterName=cullproof-test
SlurmctldHost=$(hostname -s)(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$d_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$dir/munge/socket
CredType=cred/munge
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
ReturnToService=2
NodeName=cullproof-node NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=cullproof Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$dir/slurm.conf"
slurmctld -D -i -f "$SLURM_CONF" >> "$dir/log/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -N cullproof-node -f "$SLURM_CONF" >> "$dir/log/slurmd.out" 2>&1 &
pids+=($!)
ready=0
for _ in $(seq 120); do
  if sinfo -h -o '%T' 2> /dev/null | grep -qx idle; then ready=1; break; fi
  sleep 0.5
done
[ "$ready" = 1 ] || fail "the node is not idle after 60 s: $(sinfo 2>&1)"
echo "a one-node Slurm cluster on 127.0.0.1:$ctld_port (slurmd :$d_port), $(nproc) CPUs"

run=(--seed 5 --cases 1200 -d uniform -d camera-path -d contact -d ulp --threads 1)

# One process.
status=0
(cd "$dir" && "$cullproof" verify "${run[@]}" --json one.json --corpus one-corpus --no-progress > one.txt) || status=$?
[ "$status" -le 3 ] && [ "$status" -ne 2 ] || fail "the one-process run exited with $status"

# Four shards on the cluster, merged.
merged=0
"$src/scripts/slurm-verify" --shards 4 --out "$dir/run" --cullproof "$cullproof" --wait -- "${run[@]}" \
  > "$dir/slurm.txt" 2>&1 || merged=$?
cat "$dir/slurm.txt"
[ "$merged" = "$status" ] || fail "the merge exited with $merged, the one-process run with $status"
node "$src/tests/cluster/same_run.js" "$dir/one.json" "$dir/run/run.json" || fail "the merged result differs"
diff -r --exclude=faults "$dir/one-corpus" "$dir/run/corpus" > "$dir/corpus.diff" || { cat "$dir/corpus.diff"; fail "the merged corpus differs"; }
echo "the merged corpus equals the one process's: $(find "$dir/run/corpus" -name '*.json' | wc -l) records"

# A shard cancelled: the merge names it missing and fails; re-run, the merge gives the whole run.
out=$(SBATCH_HOLD=1 "$src/scripts/slurm-verify" --shards 4 --out "$dir/again" --cullproof "$cullproof" -- "${run[@]}")
echo "$out"
array=$(echo "$out" | sed -n 's/^shards: job array \([0-9]*\).*/\1/p')
merge=$(echo "$out" | sed -n 's/^merge: job \([0-9]*\).*/\1/p')
[ -n "$array" ] && [ -n "$merge" ] || fail "no job ids in slurm-verify's output"
# Submitted held (SBATCH_HOLD): shard 2 is cancelled before it could start, then the rest released.
scancel "${array}_2"
scontrol release "$array"
scontrol release "$merge"
for _ in $(seq 600); do
  [ -z "$(squeue -h -o '%i' 2> /dev/null)" ] && break
  sleep 0.5
done
[ -z "$(squeue -h 2> /dev/null)" ] || fail "jobs still queued: $(squeue)"
[ ! -e "$dir/again/shard-2.json" ] || fail "the cancelled shard wrote its result"
grep -q "missing shards: 2 of 4" "$dir/again/logs/merge.out" || { cat "$dir/again/logs/merge.out"; fail "the merge did not name the missing shard"; }
echo "cancelled shard 2: $(grep -o 'missing shards: 2 of 4' "$dir/again/logs/merge.out")"
rerun=$(echo "$out" | sed -n 's/^re-run shard K: //p' | sed 's/--array=K/--array=2 --wait/')
eval "$rerun" > /dev/null
[ -e "$dir/again/shard-2.json" ] || fail "the re-run shard wrote no result"
again=0
sbatch --wait --output="$dir/again/logs/merge-again.out" "$dir/again/merge.sh" > /dev/null || again=$?
[ "$again" = "$status" ] || { cat "$dir/again/logs/merge-again.out"; fail "the merge after the re-run exited with $again, not $status"; }
node "$src/tests/cluster/same_run.js" "$dir/one.json" "$dir/again/run.json" || fail "the merged result after the re-run differs"
diff -r --exclude=faults "$dir/one-corpus" "$dir/again/corpus" > /dev/null || fail "the merged corpus after the re-run differs"
echo "PASS"
