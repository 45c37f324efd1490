#!/usr/bin/env bash
# A throwaway one-node Slurm cluster (Debian's slurm-wlm and munge; root, no systemd) that runs
# deploy/slurm/study.sbatch as the README says, with the array's tasks running at the same time:
#   1. the unsharded study;
#   2. an array of 3 shards started together, the merge chained on it;
#   3. an array with task 1 cancelled mid-run: the merge names shard 1; `sbatch --array=1` (the
#      natural rerun) resumes it as shard 1 of the folder's 3;
#   4. an array with task 1 cancelled mid-run and requeued by Slurm;
# every merge equal to the unsharded table byte for byte; an adaptive study's rounds as an array
# of 3 (studies/fig05_adaptive.toml), equal to the unsharded folder; and deploy/slurm/design.sbatch: a
# small design searched as an array of 3 shards, the chained merge's report equal to the whole
# search's file for file, and a small design against earthquake records as an array of 2. Tears down on success, on failure and
# on SIGTERM/SIGINT. Usage, from a checkout with target/release/shotdamp built (or under
# $CARGO_TARGET_DIR when that is set):
#   bash deploy/slurm/ci.sh [WORK_DIR]        (STUDY=studies/... to choose another study)
# It writes the system paths a Slurm install needs (/etc/slurm, /var/lib/slurm, /run/munge):
# run it only on a machine or container made for it (CI).
set -euo pipefail
REPO=$(realpath "$(dirname "$0")/../..")
W=${1:-$(mktemp -d)}; STUDY=${STUDY:-studies/fig05_damping_clearance.toml}
TARGET=${CARGO_TARGET_DIR:-target}; case $TARGET in /*) ;; *) TARGET=$REPO/$TARGET ;; esac
BIN=$TARGET/release/shotdamp
[ -x "$BIN" ] || { echo "build first: cargo build --release --locked"; exit 2; }
# The jobs take the submitting environment (sbatch's default): they run this binary.
export SHOTDAMP=$BIN
ID=$(sed -n 's/^id = "\(.*\)"$/\1/p' "$REPO/$STUDY"); R=$W/runs; P=$W/pids.txt
say() { echo "[$(date +%T)] $*"; }
teardown() {  # cancel our jobs, stop exactly the daemons started here (newest first), drop state
  scancel -p ci 2>/dev/null || true   # and let each slurmstepd finish while slurmd still answers:
  for _ in $(seq 60); do { squeue -h 2>/dev/null | grep -q . || pgrep -x slurmstepd > /dev/null; } || break; sleep 0.5; done
  [ -f "$P" ] && tac "$P" | while read -r pid name; do
    [ "$(cat /proc/"$pid"/comm 2>/dev/null)" = "$name" ] || continue
    kill "$pid" || true; for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.2; done; done
  rm -rf /var/lib/slurm/slurmctld/* /var/lib/slurm/slurmd/* /etc/slurm/slurm.conf /run/slurm*.pid; }
trap teardown EXIT; trap 'exit 143' TERM INT   # a CI timeout (SIGTERM) tears down too
waitfor() { local n=0; until eval "$1"; do sleep 0.5; n=$((n+1)); [ $n -lt 600 ] || { say "timeout: $1"; exit 1; }; done; }
gone() { ! squeue -h -j "$1" 2>/dev/null | grep -q .; }
all_ok() { local s; s=$(scontrol -o show job "$1"); [ -n "$s" ] && ! grep -v 'JobState=COMPLETED' <<< "$s" | grep -q .; }
batch_of() { compgen -G "$1/parts/shard-0001-of-0003-*/batch-*" > /dev/null; }
mkdir -p "$W/logs" "$R"; : > "$P"
say "install"; export DEBIAN_FRONTEND=noninteractive
apt-get update -qq; apt-get install -y -qq slurm-wlm munge > "$W/apt.log"
say "munged"; install -d -o munge -g munge -m 0755 /run/munge   # no systemd: nobody makes it
setsid setpriv --reuid=munge --regid=munge --init-groups munged --foreground > "$W/munged.log" 2>&1 &
echo "$! munged" >> "$P"; waitfor 'munge -n >/dev/null 2>&1'
H=$(hostname -s); NODE=$(slurmd -C | head -1)   # NodeName=H CPUs=.. RealMemory=..
cat > /etc/slurm/slurm.conf <<EOF
ClusterName=ci
SlurmctldHost=$H(127.0.0.1)
SlurmUser=slurm
StateSaveLocation=/var/lib/slurm/slurmctld
SlurmdSpoolDir=/var/lib/slurm/slurmd
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
MailProg=/bin/true
$NODE NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=ci Nodes=$H Default=YES MaxTime=INFINITE State=UP
EOF
say "slurmctld, slurmd"; setsid slurmctld -D > "$W/slurmctld.log" 2>&1 & echo "$! slurmctld" >> "$P"
setsid slurmd -D > "$W/slurmd.log" 2>&1 & echo "$! slurmd" >> "$P"   # setsid: a group kill spares them
waitfor 'sinfo -h -o %T 2>/dev/null | grep -qx idle'
cd "$REPO"   # as the README says: submit from the checkout
say "unsharded"; "$BIN" study "$STUDY" --out "$R/whole" --jobs 2 > "$W/logs/whole.log" 2>&1
# One CPU a task, so that two tasks run at the same time on this 2-CPU node.
ONE=(--cpus-per-task=1 --mem=1G)
say "array of 3 shards started together + chained merge"
j=$(sbatch --parsable "${ONE[@]}" --array=0-2 deploy/slurm/study.sbatch "$STUDY" "$R/array" 3)
m=$(sbatch --parsable --dependency=afterok:"$j" --output="$W/logs/merge-%j.out" --wrap "$BIN study merge $R/array")
waitfor "gone $j && gone $m"; all_ok "$j"; all_ok "$m"
cmp "$R/whole/$ID.csv" "$R/array/$ID.csv"; cmp "$R/whole/${ID}_summary.csv" "$R/array/${ID}_summary.csv"

say "array, task 1 cancelled mid-run, rerun with sbatch --array=1"
j=$(sbatch --parsable "${ONE[@]}" --array=0-2 deploy/slurm/study.sbatch "$STUDY" "$R/rerun" 3)
waitfor "batch_of $R/rerun"; scancel "${j}_1"
waitfor "gone $j"
if compgen -G "$R/rerun/parts/part-0001-of-0003-*" > /dev/null; then say "task 1 ended before the cancel: use a larger STUDY"; exit 1; fi
if "$BIN" study merge "$R/rerun" 2> "$W/logs/merge-incomplete.log"; then exit 1; fi
grep -q "shards 1/3 have not finished" "$W/logs/merge-incomplete.log"
j2=$(sbatch --parsable "${ONE[@]}" --array=1 deploy/slurm/study.sbatch "$STUDY" "$R/rerun")   # no count: the folder's
waitfor "gone $j2"; all_ok "$j2"
grep -q "^resuming: " "$R/rerun/logs/${j2}_1.out"; grep -q "shard 1/3" "$R/rerun/logs/${j2}_1.out"
"$BIN" study merge "$R/rerun" > "$W/logs/merge-rerun.log"
cmp "$R/whole/$ID.csv" "$R/rerun/$ID.csv"

say "array, task 1 cancelled mid-run, requeued"
j=$(sbatch --parsable "${ONE[@]}" --array=0-2 deploy/slurm/study.sbatch "$STUDY" "$R/requeue" 3)
waitfor "batch_of $R/requeue"; scancel "${j}_1"
waitfor "gone $j"
scontrol requeue "${j}_1"; scontrol update JobId="${j}_1" StartTime=now   # else held 120 s (cred_expire)
waitfor "gone $j"; all_ok "$j"
grep -q "^resuming: " "$R/requeue/logs/${j}_1.out"   # the requeued task appended to its log
[ "$(grep -c '^== ' "$R/requeue/logs/${j}_1.out")" -ge 2 ]
"$BIN" study merge "$R/requeue" > "$W/logs/merge-requeue.log"
cmp "$R/whole/$ID.csv" "$R/requeue/$ID.csv"
say "adaptive study: an array of 3 shards, rounds computed by whichever task is free"
A=studies/fig05_adaptive.toml; AID=fig05_adaptive
"$BIN" study "$A" --out "$R/adaptive-whole" --jobs 2 > "$W/logs/adaptive-whole.log" 2>&1
j=$(sbatch --parsable "${ONE[@]}" --array=0-2 deploy/slurm/study.sbatch "$A" "$R/adaptive" 3)
m=$(sbatch --parsable --dependency=afterok:"$j" --output="$W/logs/adaptive-merge-%j.out" --wrap "$BIN study merge $R/adaptive")
waitfor "gone $j && gone $m"; all_ok "$j"; all_ok "$m"
for f in "$AID.csv" "${AID}_map.csv" "${AID}_summary.csv" "${AID}_samples.csv"; do cmp "$R/adaptive-whole/$f" "$R/adaptive/$f"; done
say "design: an array of 3 shards + chained merge, equal to the whole search's report"
D=$W/design.toml   # a small design: the 5-storey frame, two candidates, coarse bands
sed -e 's/candidates = \[1, 2, 3, 4, 5\]/candidates = [4, 5]/' \
    -e 's/^max_beds = 2/max_beds = 2\nstarts = 2\nmax_iters = 8\npareto_mass_ratios = [0.05]/' \
    -e 's/step = 0.1 }/step = 0.5 }/; s/step = 0.2 }/step = 1.0 }/' designs/five_storey.toml > "$D"
"$BIN" design "$D" --out "$R/design-whole" --jobs 2 > "$W/logs/design-whole.log" 2>&1
j=$(sbatch --parsable "${ONE[@]}" --array=0-2 deploy/slurm/design.sbatch "$D" "$R/design-parts")   # count: the array's
m=$(sbatch --parsable --dependency=afterok:"$j" --output="$W/logs/design-merge-%j.out" --wrap "$BIN design $D --merge $R/design-parts --out $R/design-merged")
waitfor "gone $j && gone $m"; all_ok "$j"; all_ok "$m"
grep -q "shard 1/3" "$R/design-parts/logs/${j}_1.out"
diff -r "$R/design-whole" "$R/design-merged"
say "design against earthquakes: an array of 2 shards + chained merge, equal to the whole search's report"
Q=$W/seismic.toml   # the five-storey building under two of the shipped records, short searches
sed -e 's/candidates = \[3, 4, 5\]/candidates = [4, 5]/' -e 's/^max_beds = 3/max_beds = 2\nmax_iters = 12/' \
    -e '/RSN1690/d' -e "s|\.\./reference/|$REPO/reference/|" designs/five_storey_seismic.toml > "$Q"
"$BIN" design "$Q" --out "$R/seismic-whole" --jobs 2 > "$W/logs/seismic-whole.log" 2>&1
j=$(sbatch --parsable "${ONE[@]}" --array=0-1 deploy/slurm/design.sbatch "$Q" "$R/seismic-parts")
m=$(sbatch --parsable --dependency=afterok:"$j" --output="$W/logs/seismic-merge-%j.out" --wrap "$BIN design $Q --merge $R/seismic-parts --out $R/seismic-merged")
waitfor "gone $j && gone $m"; all_ok "$j"; all_ok "$m"
diff -r "$R/seismic-whole" "$R/seismic-merged"
# Job logs and study folders of a run from the checkout are ignored by git.
[ -z "$(git -C "$REPO" status --porcelain)" ] || { git -C "$REPO" status --porcelain; say "the checkout changed"; exit 1; }
say "PASS: arrays run together, rerun with --array=1 and requeued equal the unsharded $ID.csv; the adaptive study's array equals its unsharded folder; the sharded designs' reports (frequency bands, earthquakes) equal the whole searches'"
