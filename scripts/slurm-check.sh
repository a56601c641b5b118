#!/usr/bin/env bash
# docs/guide/monte-carlo.md's Slurm recipe, run for real: a single-node Slurm (munge, slurmctld and
# slurmd from Debian's packages, started here and stopped on exit) runs the recipe's job array
# of campaign shards and its dependent merge; the merged report must equal the report of the
# same campaign flown in one process. The recipe is taken from the docs, with the campaign
# made small (3 shards of 6 runs of a 10 s flight) and nav-sim's path filled in.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# The test profile's binary, which the host tests have built already for the testsuite:
# `cargo test --no-run` with the host tests' arguments compiles nothing again (a `cargo build`
# would, without the dev-dependencies' features); the campaign is small enough for it.
(cd "$root" && cargo test --workspace --no-run)
nav_sim="${CARGO_TARGET_DIR:-$root/target}/debug/nav-sim"

if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
  if [ "$(id -u)" = 0 ]; then
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq slurmctld slurmd slurm-client munge >/dev/null
  else
    echo "Slurm is missing: install it (Debian/Ubuntu: sudo apt-get install slurmctld slurmd slurm-client munge)" >&2
    exit 1
  fi
fi
if [ "$(id -u)" != 0 ]; then
  echo "the Slurm check starts munged, slurmctld and slurmd and must run as root" >&2
  exit 1
fi

work="$(mktemp -d)"
started=()
# Stops the daemons and waits for each to exit before removing the work directory: slurmctld
# writes its state on SIGTERM, and removing the directory under it fails. The script's own exit
# status is kept; a directory that still cannot be removed is reported, not failed on.
cleanup() {
  local status=$?
  for pid in "${started[@]}"; do kill "$pid" 2>/dev/null || true; done
  for pid in "${started[@]}"; do
    for _ in $(seq 100); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$pid" 2>/dev/null || true
  done
  rm -rf "$work" 2>/dev/null || { sleep 1; rm -rf "$work" 2>/dev/null; } \
    || echo "note: could not remove $work" >&2
  exit "$status"
}
trap cleanup EXIT

# munge: the authentication Slurm's daemons and clients share (a key of our own, one socket).
mkdir -p "$work/munge" && chmod 700 "$work/munge"
dd if=/dev/urandom of="$work/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$work/munge/munge.key"
socket="$work/munge/munge.socket"
munged --force --key-file="$work/munge/munge.key" --socket="$socket" \
  --pid-file="$work/munge/munged.pid" --log-file="$work/munge/munged.log" \
  --seed-file="$work/munge/munge.seed"
started+=("$(cat "$work/munge/munged.pid")")

host="$(hostname -s)"
mkdir -p "$work/state" "$work/spool"
cat > "$work/slurm.conf" <<CONF
ClusterName=navcheck
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$socket
CredType=cred/munge
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
SlurmctldPort=16817
SlurmdPort=16818
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MpiDefault=none
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
NodeName=$host CPUs=$(nproc) RealMemory=1024 State=UNKNOWN
PartitionName=check Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$work/slurm.conf"
slurmctld -i
slurmd
for _ in $(seq 100); do [ -s "$work/slurmctld.pid" ] && [ -s "$work/slurmd.pid" ] && break; sleep 0.1; done
started+=("$(cat "$work/slurmctld.pid")" "$(cat "$work/slurmd.pid")")
for _ in $(seq 300); do sinfo -h -o %t 2>/dev/null | grep -qx idle && break; sleep 0.1; done
sinfo -h -o '%P %t %c' | grep -q idle || { cat "$work/slurmctld.log" "$work/slurmd.log" >&2; exit 1; }

# The campaign: the built-in scenario with one 10 s coast as its flight.
default="$("$nav_sim" scenario)"
{
  printf '%s\n' "$default" | sed -n '1,/^\[\[manoeuvre\]\]/p' | sed '$d'
  printf '[[manoeuvre]]\nlabel = "coast"\nduration_s = 10.0\nramp_s = 0.0\n'
  printf 'body_rate_deg_per_s = [2.4e-4, 2.4e-4, 2.4e-4]\nspecific_force_mps2 = [0.0, 0.0, 0.0]\n\n'
  printf '%s\n' "$default" | sed -n '/^\[filter\]/,$p'
} > "$work/scenario.toml"

# The recipe from the docs: the job script and the two submissions.
recipe() {
  awk -v block="$1" '/^### Slurm job array/ {found = 1; next}
    found && /^```sh/ {count++; if (count == block) {inside = 1}; next}
    inside && /^```/ {exit}
    inside {print}' "$root/docs/guide/monte-carlo.md"
}
small() {
  sed -e 's/--array=0-15 /--array=0-2 /' -e 's|/16"|/3"|' -e 's/--cpus-per-task=4/--cpus-per-task=1/' \
    -e 's/--runs 200/--runs 6/' -e "s|nav-sim |$nav_sim |g"
}
cd "$work"
recipe 1 | small > mc.sbatch
recipe 2 | small > submit.sh
grep -q -- '--array=0-2 ' mc.sbatch && grep -q -- '--shard "$SLURM_ARRAY_TASK_ID/3"' mc.sbatch \
  || { echo "FAIL: the docs' Slurm recipe changed shape:" >&2; cat mc.sbatch >&2; exit 1; }
echo "the recipe, made small:"; sed 's/^/    /' mc.sbatch submit.sh
# Submit as the docs do, then wait for the merge job (the last job) to end.
bash submit.sh
for _ in $(seq 600); do [ -z "$(squeue -h 2>/dev/null)" ] && break; sleep 0.5; done
[ -z "$(squeue -h)" ] || { squeue >&2; echo "FAIL: the Slurm jobs did not finish in 300 s" >&2; exit 1; }
[ -s report.txt ] || { cat slurm-*.out >&2 2>/dev/null; echo "FAIL: the merge wrote no report" >&2; exit 1; }
"$nav_sim" monte-carlo scenario.toml --runs 6 --check > whole.txt 2>/dev/null
if ! cmp -s report.txt whole.txt; then
  diff whole.txt report.txt >&2 || true
  echo "FAIL: the report merged under Slurm differs from the one-process report" >&2
  exit 1
fi
echo "Slurm: $(ls shards | wc -l) shards flown as a job array and merged by a dependent job; the report equals the one-process campaign's ($(wc -l < report.txt) lines)"
