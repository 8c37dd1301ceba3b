#!/usr/bin/env bash
# The farm against a real single-node Slurm (scripts/slurm_local.sh): a tiny dam break through
# `farm submit` is byte-identical to a local run, also with its simulation job requeued mid-run
# (`scontrol requeue`) while a surfacing task waiting for it gives its CPU back; a damaged input
# makes `farm status` name the frame and the error. Before Slurm: bad options refused, --dry-run;
# stages of one folder run side by side while the same stage is refused, and a stage removes
# only its own stale temporaries. Needs root (CI runs as root); never skipped: if Slurm cannot
# start, this fails with the daemons' logs. About a minute on 2 cores.
set -euo pipefail
bin=$1
src=$2
work=$(mktemp -d)
state="$work/slurm"
export SLURM_CONF="$state/etc/slurm.conf"
slurm() { "$src/scripts/slurm_local.sh" "$1" "$state"; }
cleanup() {
  slurm stop > /dev/null 2>&1 || true
  rm -rf "$work"
}
trap cleanup EXIT
fail() {
  echo "FAIL: $*" >&2
  if [ -f "$SLURM_CONF" ]; then
    squeue 2>&1 | head -20 >&2 || true
    slurm logs || true
  fi
  exit 1
}
t0=$(date +%s)
cd "$work"
scene=(dam_break --set solver.particle_spacing=0.00714 --set scene.end_time=0.8 --resolution 64x36 --samples 2)

# --- The reference: one local run -------------------------------------------------------------
"$bin" run "${scene[@]}" --out "$work/local" 2> local.log || fail "local run failed: $(tail -3 local.log)"

# --- One folder, several stages: scoped locks and scoped clean-up (no Slurm needed) -------------
"$bin" sim "${scene[@]}" --set scene.end_time=2.0 --threads 1 --out "$work/shared" 2> shared-sim.log &
simpid=$!
for _ in $(seq 1 500); do [ -s shared/locks/sim.pid ] && break; sleep 0.02; done
[ -s shared/locks/sim.pid ] || fail "the simulation wrote no lock"
mkdir -p shared/surface shared/particles
touch shared/surface/surface.0000.vdb.tmp shared/surface/surface.0099.vdb.tmp shared/particles/particles.0099.vdb.tmp
"$bin" surface "${scene[@]}" --set scene.end_time=2.0 --frames 0-0 --wait-for-input 60 --out "$work/shared" 2> shared-surface.log \
  || fail "surfacing was refused while the simulation ran: $(tail -3 shared-surface.log)"
[ ! -e shared/surface/surface.0000.vdb.tmp ] || fail "surfacing frames 0-0 left its own stale temporary"
[ -e shared/surface/surface.0099.vdb.tmp ] && [ -e shared/particles/particles.0099.vdb.tmp ] \
  || fail "surfacing frames 0-0 removed temporaries it does not own"
set +e
"$bin" sim "${scene[@]}" --set scene.end_time=2.0 --out "$work/shared" > shared-sim2.log 2>&1
status=$?
set -e
kill "$simpid" 2>/dev/null || true
wait "$simpid" 2>/dev/null || true
[ "$status" -ne 0 ] && grep -q "in use by another multifluid run (PID $simpid), which holds its sim stage" shared-sim2.log \
  || fail "a second simulation in the same folder was not refused with the holder: $(cat shared-sim2.log)"
grep -q "stopped by SIGTERM during frame" shared-sim.log || fail "SIGTERM did not stop the simulation at a step: $(tail -2 shared-sim.log)"
echo "locks: surfacing ran beside the simulation, a second simulation was refused (PID $simpid); clean-up kept others' temporaries"

# --- Bad input is refused before anything is submitted; --dry-run submits nothing ---------------
bad() {
  local want=$1
  shift
  set +e
  "$bin" farm submit "${scene[@]}" "$@" > bad.log 2>&1
  local status=$?
  set -e
  [ "$status" -eq 2 ] && grep -q -- "$want" bad.log || fail "farm submit $* (exit $status): $(cat bad.log)"
}
bad "--out .*may not contain '%'" --out "$work/a%b"
bad "--time 1:2:3:4: takes M, M:S" --out "$work/bad" --time 1:2:3:4
bad "--partition a b: takes a partition name" --out "$work/bad" --partition "a b"
bad "--frames 0-99: the scene 'dam_break' has frames 0-24" --out "$work/bad" --frames 0-99
bad "--frames-per-task: Value 0 not in range" --out "$work/bad" --frames-per-task 0
bad "unknown stage 'foo'" --out "$work/bad" --stages sim,foo
[ ! -e "$work/bad/farm/jobs.txt" ] || fail "a refused submission recorded jobs"
"$bin" farm submit "${scene[@]}" --out "$work/dry" --frames-per-task 4 --dry-run > dry.log 2>&1 || fail "dry run: $(cat dry.log)"
[ "$(grep -c '^sbatch --parsable' dry.log)" -eq 4 ] && grep -q -- "--array=0-6 .*'--dependency=aftercorr:<surface job id>'" dry.log \
  || fail "dry run printed other command lines: $(cat dry.log)"
[ -s dry/farm/sim.sbatch ] && [ -s dry/farm/task.sbatch ] && [ ! -e dry/farm/jobs.txt ] || fail "dry run: scripts missing or jobs recorded"
echo "input: 6 bad submissions refused naming the option; dry run wrote scripts and 4 sbatch lines"

# --- Slurm --------------------------------------------------------------------------------------
slurm start || fail "the local Slurm did not start (logs above)"

# Wait (bounded) until none of the recorded jobs is queued, hurrying requeued jobs past the
# two-minute BeginTime that Slurm gives them (a test-only shortcut).
jobs_of() { awk '$1 == "job" {print $3}' "$1/farm/jobs.txt" | paste -sd, -; }
wait_jobs() {
  local dir=$1 limit=$2 ids left
  ids=$(jobs_of "$dir")
  for _ in $(seq 1 "$limit"); do
    left=$(squeue -h -r -j "$ids" -o '%i %r' 2> /dev/null || true)
    [ -z "$left" ] && return 0
    echo "$left" | awk '$2 == "BeginTime" {print $1}' | while read -r j; do scontrol update "JobId=$j" StartTime=now || true; done
    sleep 1
  done
  fail "jobs $ids still queued after $limit s: $left"
}
compare_with_local() {
  local dir=$1 n=0
  for f in $(cd local && find particles surface render records -type f) checkpoint.bin dam_break.mp4 scene.toml; do
    cmp -s "local/$f" "$dir/$f" || fail "$f differs between the farm ($dir) and the local run"
    n=$((n + 1))
  done
  for d in particles surface render records; do
    [ "$(ls "$dir/$d" | wc -l)" -eq "$(ls "local/$d" | wc -l)" ] || fail "$dir/$d has other files than the local run's"
  done
  echo "$n"
}

# --- Farm run with the simulation requeued mid-run; a run folder with a space, quotes and $( ) ---
farm="$work/farm 'q' \$(touch PWNED) \"dq\""
"$bin" farm submit "${scene[@]}" --out "$farm" --frames-per-task 4 --wait-for-input 10 > submit.log 2>&1 \
  || fail "farm submit failed: $(cat submit.log)"
sim=$(awk '$1 == "job" && $2 == "sim" {print $3}' "$farm/farm/jobs.txt")
[ -n "$sim" ] || fail "no sim job recorded: $(cat "$farm/farm/jobs.txt")"
# Requeued once frame 2 is out and a surfacing task is running (the first of 25 frames, so that a
# much faster machine is still simulating): a requeue before the array starts would hold it on its
# `after` dependency, and no task would be waiting.
for _ in $(seq 1 1200); do
  [ -e "$farm/records/particles.0002.txt" ] && grep -qs "^multifluid farm: surface task" "$farm"/farm/logs/surface-*.log && break
  sleep 0.05
done
[ -e "$farm/records/particles.0002.txt" ] || fail "the sim job wrote no frame 2 in 60 s: $(cat "$farm"/farm/logs/sim-*.log)"
grep -qs "^multifluid farm: surface task" "$farm"/farm/logs/surface-*.log || fail "no surfacing task started in 60 s"
[ -e "$farm/records/particles.0024.txt" ] && fail "the simulation finished before the requeue: nothing was tested"
scontrol requeue "$sim" || fail "scontrol requeue $sim failed"
# While the simulation waits in the queue, a surfacing task waiting for its frame must give its
# CPU back (exit 75, requeued) within --wait-for-input; only then is anything hurried.
for _ in $(seq 1 60); do cat "$farm"/farm/logs/surface-*.log 2> /dev/null | grep -q "input not ready; requeueing task" && break; sleep 1; done
yields=$(cat "$farm"/farm/logs/surface-*.log | grep -c "input not ready; requeueing task" || true)
[ "$yields" -ge 1 ] || fail "no waiting surfacing task gave its CPU back while the simulation was requeued"
wait_jobs "$farm" 200
log="$farm/farm/logs/sim-$sim.log"
grep -q "stopped by SIGTERM during frame" "$log" || fail "the requeued simulation did not stop at a step: $(cat "$log")"
grep -q "^resuming .* from its checkpoint at frame" "$log" || fail "the requeued simulation did not resume: $(cat "$log")"
# With one CPU the node runs one job at a time, and nothing can flow.
if [ "$(nproc)" -ge 2 ]; then
  [ "$farm/records/particles.0024.txt" -nt "$farm/records/surface.0000.txt" ] \
    || fail "surfacing did not start before the simulation ended (frames did not flow)"
fi
n=$(compare_with_local "$farm")
"$bin" farm status "$farm" > status.log 2>&1 || fail "farm status of a finished run failed: $(cat status.log)"
grep -q "particles 25/25 surface 25/25 render 25/25" status.log || fail "farm status: $(cat status.log)"
find "$work" "$src" -name PWNED 2> /dev/null | grep -q . && fail "a path ran a shell command"
echo "farm: $n files byte-identical to the local run; sim job $sim requeued, resumed from its $(grep -o 'checkpoint at frame [0-9]*' "$log" | head -1); $yields surfacing task(s) gave their CPUs back while it was queued"

# --- A damaged input: the surfacing task fails and farm status names the frame and the error ---
damaged="$work/damaged"
cp -a "$farm" "$damaged"
rm -f "$damaged/records/surface.0006.txt" "$damaged/records/render.0006.txt"
printf 'XXXX' | dd of="$damaged/particles/particles.0006.vdb" bs=1 seek=200 conv=notrunc status=none
"$bin" farm submit "${scene[@]}" --out "$damaged" --stages surface,render,encode --frames-per-task 4 > submit2.log 2>&1 \
  || fail "farm submit (surface, render, encode) failed: $(cat submit2.log)"
surface=$(awk '$1 == "job" && $2 == "surface" {print $3}' "$damaged/farm/jobs.txt")
wait_jobs "$damaged" 120  # every job, rendering task 1 and encoding too, whose dependency fails
set +e
"$bin" farm status "$damaged" > status2.log 2>&1
status=$?
set -e
[ "$status" -eq 1 ] || fail "farm status exited $status with a failed task: $(cat status2.log)"
grep -q "^failed: surface task 1 (job ${surface}_1, frames 4-7) FAILED exit 1 at frame 6: multifluid: .*particles.0006.vdb.*damaged" status2.log \
  || fail "farm status does not name the frame and the error: $(cat status2.log)"
grep -q "^render   job .*NOT RUN" status2.log && grep -q "^encode   job .*NOT RUN" status2.log \
  || fail "rendering task 1 and encoding, whose dependency failed, did not leave the queue: $(cat status2.log)"
echo "damaged input: $(grep '^failed:' status2.log)"

# --- A submission that fails half way cancels what it had queued ------------------------------
mkdir -p fakebin
real_sbatch=$(command -v sbatch)
cat > fakebin/sbatch <<EOF
#!/bin/bash
for a in "\$@"; do [ "\$a" = --job-name=mf-render-dam_break ] && { echo "sbatch: error: refused by the test" >&2; exit 1; }; done
exec "$real_sbatch" "\$@"
EOF
chmod +x fakebin/sbatch
set +e
PATH="$work/fakebin:$PATH" "$bin" farm submit "${scene[@]}" --out "$work/half" > half.log 2>&1
status=$?
set -e
[ "$status" -eq 1 ] && grep -q "sbatch failed for the render job (status 1): sbatch: error: refused by the test" half.log \
  || fail "a failing sbatch was not reported (exit $status): $(cat half.log)"
[ ! -e half/farm/jobs.txt ] || fail "a failed submission recorded jobs"
half_ids=$(sed -n 's/^submitted [a-z]* job \([0-9]*\)$/\1/p' half.log | paste -sd, -)
[ -n "$half_ids" ] || fail "no job was submitted before the failure: $(cat half.log)"
for _ in $(seq 1 30); do [ -z "$(squeue -h -j "$half_ids" 2> /dev/null)" ] && break; sleep 1; done
[ -z "$(squeue -h -j "$half_ids" 2> /dev/null)" ] || fail "jobs $half_ids of a failed submission are still queued: $(squeue)"
echo "half-failed submission: render refused, jobs $half_ids cancelled"

# --- farm cancel ---------------------------------------------------------------------------------
"$bin" farm submit "${scene[@]}" --out "$work/cancelled" --frames-per-task 4 > submit3.log 2>&1 || fail "farm submit: $(cat submit3.log)"
"$bin" farm cancel "$work/cancelled" > cancel.log 2>&1 || fail "farm cancel failed: $(cat cancel.log)"
grep -q "^cancelled jobs [0-9]*,[0-9]*,[0-9]*,[0-9]* of " cancel.log || fail "farm cancel: $(cat cancel.log)"
ids=$(jobs_of "$work/cancelled")
for _ in $(seq 1 30); do [ -z "$(squeue -h -j "$ids" 2> /dev/null)" ] && break; sleep 1; done
[ -z "$(squeue -h -j "$ids" 2> /dev/null)" ] || fail "jobs left after farm cancel: $(squeue)"
echo "cancel: $(cat cancel.log)"
echo "farm test: $(($(date +%s) - t0)) s"
