#!/usr/bin/env bash
# A one-node Slurm cluster on this machine (munge, slurmctld and slurmd on localhost, every file in a
# private directory, SlurmUser the test's user, ports of its own), then a reference rendered as a job
# array by scripts/farm_reference.sh and merged, checked bit-identical to the single-process reference.
#   tests/farm/slurm_local.sh PRW WORKDIR [SIZE] [SPP] [TASKS]
# Exit 0: passed; 77: SKIP (Slurm or munge not installed: scripts/setup.sh installs them); else failed.
set -uo pipefail
prw=$1
work=$2
size=${3:-64x64}
spp=${4:-8}
tasks=${5:-4}
here="$(cd "$(dirname "$0")/../.." && pwd)"
PATH="$PATH:/usr/sbin:/sbin" # the daemons live in sbin, which a user's PATH may lack
for b in munged slurmctld slurmd sbatch sinfo; do
  if ! command -v "$b" >/dev/null 2>&1; then
    echo "SKIP: $b not installed (Debian packages slurm-wlm and munge; scripts/setup.sh installs them)"
    exit 77
  fi
done
rm -rf "$work"
mkdir -p "$work"/{munge,spool,state,log,out}
work="$(cd "$work" && pwd)"
user="$(id -un)"
host="$(hostname -s)"
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done
  sleep 0.5
  for p in "${pids[@]}"; do kill -9 "$p" 2>/dev/null; done
}
trap cleanup EXIT
fail() {
  echo "FAIL: $*"
  for f in "$work"/log/*.log; do echo "--- $f"; tail -20 "$f"; done
  exit 1
}

# munge: a key of its own, a socket of its own
dd if=/dev/urandom of="$work/munge/munge.key" bs=1024 count=1 status=none
chmod 700 "$work/munge"
chmod 400 "$work/munge/munge.key"
sock="$work/munge/munge.socket"
munged --force --key-file="$work/munge/munge.key" --socket="$sock" --pid-file="$work/munge/munged.pid" \
  --log-file="$work/log/munged.log" --seed-file="$work/munge/munged.seed" || fail "munged did not start"
for _ in $(seq 50); do [ -S "$sock" ] && break; sleep 0.1; done
[ -S "$sock" ] || fail "munged: no socket"
pids+=("$(cat "$work/munge/munged.pid")")

# ports away from a real cluster's 6817/6818, derived from the process id
base=$((20000 + ($$ % 20000)))
cpus=$(nproc)
mem=$(awk '/MemTotal/ {print int($2 / 1024 / 2)}' /proc/meminfo)
cat > "$work/slurm.conf" <<CONF
ClusterName=prwtest
SlurmctldHost=$host
SlurmctldPort=$base
SlurmdPort=$((base + 1))
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
AuthInfo=socket=$sock
CredType=cred/munge
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/log/slurmctld.log
SlurmdLogFile=$work/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SwitchType=switch/none
MpiDefault=none
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
SlurmdTimeout=60
InactiveLimit=0
KillWait=5
NodeName=$host CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=prwtest Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$work/slurm.conf"
slurmctld -i -f "$SLURM_CONF" || fail "slurmctld did not start"
for _ in $(seq 50); do [ -f "$work/slurmctld.pid" ] && break; sleep 0.1; done
pids+=("$(cat "$work/slurmctld.pid" 2>/dev/null)")
slurmd -f "$SLURM_CONF" || fail "slurmd did not start"
for _ in $(seq 50); do [ -f "$work/slurmd.pid" ] && break; sleep 0.1; done
pids+=("$(cat "$work/slurmd.pid" 2>/dev/null)")
up=0
for _ in $(seq 100); do
  if sinfo -h -o '%t' 2>/dev/null | grep -qE '^idle'; then up=1; break; fi
  sleep 0.2
done
[ "$up" = 1 ] || fail "the node did not come up ($(sinfo -h -o '%t' 2>&1))"
echo "slurm: one-node cluster up ($(sinfo -V), node $host, $cpus CPUs)"

# the job array (the README's command), then the single-process reference
bash "$here/scripts/farm_reference.sh" --prw "$prw" --out "$work/out" --tasks "$tasks" --wait -- \
  demo --size "$size" --spp "$spp" --seed 1 || fail "farm_reference.sh failed"
"$prw" --threads 1 reference demo --size "$size" --spp "$spp" --seed 1 --out "$work/single.exr" \
  --acc "$work/single.acc" >/dev/null || fail "single-process reference failed"
cmp "$work/out/reference.acc" "$work/single.acc" || fail "merged accumulation differs from the single-process one"
"$prw" compare "$work/single.exr" "$work/out/reference.exr" > "$work/compare.txt" 2>&1
grep -qE 'PSNR \(dB\) +inf' "$work/compare.txt" || fail "merged image differs: $(cat "$work/compare.txt")"
echo "PASS: $tasks-task job array merged bit-identical to the single-process reference ($size, $spp spp)"
