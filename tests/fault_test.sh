#!/usr/bin/env bash
# Faults a hostile user or a bad day brings, end to end through the command: names that try to
# reach a shell or leave the run folder, two runs into one folder, a full disk (a small tmpfs),
# damaged particle, surface, image and checkpoint files, and bad command lines. Each check says
# what must hold; the script stops at the first that does not.
set -euo pipefail
bin=$(realpath "$1")
work=$(mktemp -d)
mnt="$work/small"
cleanup() {
  mountpoint -q "$mnt" 2>/dev/null && umount "$mnt"
  rm -rf "$work"
}
trap cleanup EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
cd "$work"

# A tiny dam break: 8 frames, every stage, a few seconds.
base=(dam_break --set solver.particle_spacing=0.01 --set scene.end_time=0.25 --resolution 48x27 --samples 1 --threads 2)
"$bin" run "${base[@]}" --out "$work/ref" 2> ref.log || fail "reference run failed: $(tail -5 ref.log)"
[ -s ref/dam_break.mp4 ] || fail "reference run wrote no movie"
grep -q "frames present: particles 8/8 surface 8/8 render 8/8" ref.log || fail "summary of frames present: $(grep present ref.log)"
echo "reference: $(find ref -type f | wc -l) files, $(du -sk ref | cut -f1) KiB"

# --- Names never reach a shell, and runs stay inside their folder -----------------------------
src_dam="$work/dam.toml"
# The shipped scene file, from the source tree next to this script.
cp "$(dirname "$(realpath "${BASH_SOURCE[0]}")")/../configs/dam_break.toml" "$src_dam"
scene_with_name() {  # $1: the scene name as the body of a TOML basic string; writes $2
  NAME="$1" python3 -c 'import os,sys; t=open(sys.argv[1]).read(); print(t.replace("name = \"dam_break\"", "name = \"" + os.environ["NAME"] + "\"", 1), end="")' "$src_dam" > "$2"
}
n=0
for name in "x'; touch PWNED_A; echo '" 'x$(touch PWNED_B)' 'x`touch PWNED_C`' 'x; touch PWNED_D' '../../escaped' '/tmp/abs' 'a/b' '..' '' \
            'x\" y' 'name with spaces' "$(printf 'x%.0s' {1..200})"; do
  esc=${name//\\/\\\\}
  scene_with_name "${esc//\"/\\\"}" "$work/n$n.toml"
  set +e
  "$bin" run "$work/n$n.toml" --frames 0-1 --set solver.particle_spacing=0.02 > "n$n.out" 2>&1
  status=$?
  set -e
  [ "$status" -eq 2 ] || fail "scene name '$name' was accepted (exit $status): $(head -3 "n$n.out")"
  grep -q "n$n.toml:.*scene.name" "n$n.out" || fail "no file:line:key for scene name '$name': $(head -3 "n$n.out")"
  n=$((n + 1))
done
ls PWNED_* /tmp/PWNED_* ../PWNED_* 2>/dev/null && fail "a name ran a shell command"
[ -e "$work/escaped" ] || [ -e /tmp/abs ] && fail "a run was written outside runs/"
[ -d runs ] && fail "a refused scene created a run folder: $(ls runs)"
# A phase name becomes file names (meshes) and metadata (comma-joined): the same rule holds.
sed 's|^name = "water"|name = "wa,ter"|' "$src_dam" > badphase.toml
set +e; "$bin" validate badphase.toml > badphase.out 2>&1; status=$?; set -e
[ "$status" -eq 2 ] && grep -q "badphase.toml:.*phase\[0\].name" badphase.out || fail "phase name with a comma: $(cat badphase.out)"
# --out is the user's own path: quotes and $( ) in it are just characters (ffmpeg gets argv).
odd="$work/out 'q' \$(touch PWNED_E) \`touch PWNED_F\` ; x"
"$bin" run "${base[@]}" --frames 0-2 --out "$odd" 2> odd.log || fail "run into a folder with quotes failed: $(tail -3 odd.log)"
[ -s "$odd/dam_break.mp4" ] || fail "no movie in the folder with quotes: $(tail -3 odd.log)"
ls PWNED_* "$odd"/PWNED_* 2>/dev/null && fail "--out ran a shell command"
echo "names: $n hostile scene names refused with file, line and key; nothing ran; quotes in --out harmless"

# --- Two runs into one folder: the second is refused with the holder's PID ------------------------
"$bin" run "${base[@]}" --set scene.end_time=1.0 --out "$work/busy" 2> busy1.log &
pid=$!
for _ in $(seq 1 500); do [ -s busy/locks/sim.pid ] && break; sleep 0.02; done
[ -s busy/locks/sim.pid ] || fail "first run wrote no lock"
set +e; "$bin" run "${base[@]}" --set scene.end_time=1.0 --out "$work/busy" > busy2.log 2>&1; status=$?; set -e
kill "$pid" 2>/dev/null || true
wait "$pid" 2>/dev/null || true
[ "$status" -ne 0 ] || fail "a second run into a busy folder was accepted"
grep -q "in use by another multifluid run (PID $pid)" busy2.log || fail "refusal does not name the holder: $(cat busy2.log)"
echo "lock: second run refused (PID $pid named)"

# --- A full disk: no final-named partial file; after freeing space the re-run completes identically
if [ "$(id -u)" -eq 0 ] && mkdir -p "$mnt" && mount -t tmpfs -o size=1m tmpfs "$mnt" 2>/dev/null; then
  set +e; "$bin" run "${base[@]}" --out "$mnt/run" > full.log 2>&1; status=$?; set -e
  [ "$status" -ne 0 ] || fail "a run on a full disk reported success"
  grep -q "No space left on device" full.log || fail "the full disk is not named: $(tail -3 full.log)"
  ! find "$mnt/run" -name '*.tmp*' | grep -q . || fail "temporaries left: $(find "$mnt/run" -name '*.tmp*')"
  partial=0
  for f in $(cd "$mnt/run" && find particles surface render -type f 2>/dev/null); do
    cmp -s "$mnt/run/$f" "ref/$f" || { echo "partial or wrong: $f"; partial=$((partial + 1)); }
  done
  [ "$partial" -eq 0 ] || fail "$partial final-named file(s) differ from the uninterrupted run"
  # A stage the full disk stopped before has no folder: find fails on it, which is no error here.
  kept=$(cd "$mnt/run" && { find particles surface render -type f 2>/dev/null || true; } | wc -l)
  mount -o remount,size=64m "$mnt"
  "$bin" run "${base[@]}" --out "$mnt/run" 2> full2.log || fail "re-run after freeing space failed: $(tail -3 full2.log)"
  for f in $(cd ref && find particles surface render -type f) dam_break.mp4; do
    cmp -s "$mnt/run/$f" "ref/$f" || fail "$f differs from the uninterrupted run after the disk-full re-run"
  done
  echo "disk full: failed with ENOSPC after $kept complete file(s), none partial; re-run identical to the uninterrupted run"
  umount "$mnt"
else
  fail "the disk-full check needs root and tmpfs (mount -t tmpfs); CI runs as root"
fi

# --- Damaged files -----------------------------------------------------------------------------------
damage() { printf '\xde\xad\xbe\xef\xde\xad\xbe\xef\xde\xad\xbe\xef\xde\xad\xbe\xef' | dd of="$1" bs=1 seek="$2" conv=notrunc status=none; }
cp -r ref dmg
damage dmg/particles/particles.0005.vdb 400
rm dmg/records/surface.0005.txt
set +e; "$bin" surface "${base[@]}" --out "$work/dmg" > dmg1.log 2>&1; status=$?; set -e
[ "$status" -eq 1 ] && grep -q "particles.0005.vdb" dmg1.log || fail "damaged particle file not named (exit $status): $(tail -3 dmg1.log)"
# The whole run again: the sim stage sees frame 5 damaged and simulates again; every file ends
# identical to the uninterrupted run (a damaged frame is redone, never skipped).
"$bin" run "${base[@]}" --out "$work/dmg" 2> dmg2.log || fail "re-run over a damaged particle file failed: $(tail -3 dmg2.log)"
grep -q "frame 5 was never finished" dmg2.log || fail "damaged frame 5 not noticed: $(head -3 dmg2.log)"
cmp -s dmg/particles/particles.0005.vdb ref/particles/particles.0005.vdb || fail "frame 5 not rewritten"
damage dmg/surface/surface.0003.vdb 300
rm dmg/records/render.0003.txt
set +e; "$bin" render "${base[@]}" --out "$work/dmg" > dmg3.log 2>&1; status=$?; set -e
[ "$status" -eq 1 ] && grep -q "surface.0003.vdb" dmg3.log || fail "damaged surface file not named (exit $status): $(tail -3 dmg3.log)"
cp ref/surface/surface.0003.vdb dmg/surface/
damage dmg/render/render.0006.png 60
"$bin" run "${base[@]}" --out "$work/dmg" 2> dmg4.log || fail "re-run over a damaged image failed: $(tail -3 dmg4.log)"
cmp -s dmg/render/render.0006.png ref/render/render.0006.png || fail "damaged render.0006.png was skipped, not redone"
cmp -s dmg/dam_break.mp4 ref/dam_break.mp4 || fail "movie differs after redoing a damaged frame"
damage dmg/checkpoint.bin 2000
set +e; "$bin" run "${base[@]}" --out "$work/dmg" > dmg5.log 2>&1; status=$?; set -e
[ "$status" -ne 0 ] && grep -q "checkpoint.bin" dmg5.log || fail "damaged checkpoint accepted (exit $status): $(tail -3 dmg5.log)"
echo "damaged files: particle, surface and checkpoint files named; a damaged frame and image redone, identical"

# --- Scenes that would hang or swamp the machine: refused up front, or stopped when dt collapses ---
# The stiffness sets the step on WCSPH (the shipped dam break runs on DFSPH, which has none).
sed 's|^pressure = "dfsph"|pressure = "wcsph"|; s|^\(rest_density = .*\)|\1\nstiffness = 1e10|' "$src_dam" > stiff.toml
set +e; "$bin" validate stiff.toml > stiff.out 2>&1; status=$?; set -e
[ "$status" -eq 2 ] && grep -q "stiff.toml:[0-9]*: key 'phase\[0\].stiffness'.*steps per frame" stiff.out || fail "stiffness 1e10 not refused: $(cat stiff.out)"
set +e; "$bin" run "${base[@]}" --set 'solver.pressure="wcsph"' --set effects.pressure.enabled=true --set phase.water.stiffness=1e8 --force --max-steps-per-frame 300 --out "$work/stiff" > stiff2.out 2>&1
status=$?; set -e
[ "$status" -eq 3 ] && grep -q "time step has collapsed" stiff2.out && grep -q "set by the sound speed" stiff2.out ||
  fail "a collapsing dt did not stop the run (exit $status): $(tail -3 stiff2.out)"
sed 's|^particle_spacing = .*|particle_spacing = 1e-4|' "$src_dam" > fine.toml
set +e; "$bin" validate fine.toml > fine.out 2>&1; status=$?; set -e
[ "$status" -eq 2 ] && grep -q "fine.toml:[0-9]*: key 'solver.particle_spacing'.*MiB" fine.out || fail "1e-4 spacing not refused: $(cat fine.out)"
echo "budget: stiffness 1e10 and spacing 1e-4 refused at validate; a collapsing dt stopped the run (exit 3)"

# --- Bad command lines: each a usage error (exit 2) -----------------------------------------------
check_usage() {
  set +e; "$bin" "$@" > usage.out 2>&1; status=$?; set -e
  [ "$status" -eq 2 ] || fail "'$*' exited $status, expected a usage error: $(head -2 usage.out)"
}
check_usage run dam_break --threads 2abc
check_usage run dam_break --samples 2.5
check_usage run dam_break --frames 2-3x
check_usage run dam_break --resolution 64x48x3
check_usage run dam_break --frames 100-200
check_usage run dam_break --stages ''
check_usage run dam_break --stages sim,,render
check_usage validate
check_usage diff ref/render ref/render --threshold abc
check_usage run "$work"
check_usage run nonexistent_scene
check_usage run dam_break --bogus
echo "command line: 12 bad command lines refused with exit 2"
echo "faults: all checks passed"
