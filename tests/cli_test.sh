#!/usr/bin/env bash
# End-to-end tests of the multifluid command: a run killed with SIGKILL and re-run gives the same
# files (particles, level sets, images, movie), bit for bit, as an uninterrupted run; stages re-run
# alone; diff passes equal and fails different sequences; validate reports broken files; bad
# options fail.
set -euo pipefail
bin=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

args=(run dam_break --set solver.particle_spacing=0.00714 --set scene.end_time=0.5 --threads 2 --resolution 64x36 --samples 2)
last=particles.0015.vdb

"$bin" "${args[@]}" --out "$work/straight" 2> "$work/straight.log" || fail "uninterrupted run failed: $(cat "$work/straight.log")"
[ -e "$work/straight/particles/$last" ] || fail "uninterrupted run did not write $last"
grep -q "summary for dam_break" "$work/straight.log" || fail "no summary printed"

"$bin" "${args[@]}" --out "$work/killed" 2> "$work/killed1.log" &
pid=$!
while [ ! -e "$work/killed/particles/particles.0004.vdb" ]; do
  kill -0 "$pid" 2>/dev/null || fail "run ended before it could be killed"
  sleep 0.02
done
kill -KILL "$pid"
wait "$pid" 2>/dev/null && fail "killed run exited normally"
[ -e "$work/killed/particles/$last" ] && fail "run finished before the kill: nothing was tested"
echo "killed after $(ls "$work/killed/particles" | grep -c '\.vdb$') frames"

"$bin" "${args[@]}" --out "$work/killed" 2> "$work/killed2.log" || fail "resumed run failed: $(cat "$work/killed2.log")"
grep -q "^resuming" "$work/killed2.log" || fail "second run did not resume from the checkpoint"
n=0
for f in "$work"/straight/particles/*.vdb; do
  cmp -s "$f" "$work/killed/particles/$(basename "$f")" || fail "$(basename "$f") differs after kill and resume"
  n=$((n + 1))
done
[ "$n" -eq 16 ] || fail "expected 16 frames, compared $n"
m=0
for f in "$work"/straight/surface/*.vdb; do
  cmp -s "$f" "$work/killed/surface/$(basename "$f")" || fail "surface $(basename "$f") differs after kill and resume"
  m=$((m + 1))
done
[ "$m" -eq 16 ] || fail "expected 16 surface frames, compared $m"
r=0
for f in "$work"/straight/render/*.png "$work"/straight/render/*.exr; do
  cmp -s "$f" "$work/killed/render/$(basename "$f")" || fail "render $(basename "$f") differs after kill and resume"
  r=$((r + 1))
done
[ "$r" -eq 32 ] || fail "expected 16 PNG and 16 EXR frames, compared $r"
cmp -s "$work/straight/dam_break.mp4" "$work/killed/dam_break.mp4" || fail "the movies differ after kill and resume"
ls "$work/killed/particles" "$work/killed/render" | grep -q '\.tmp' && fail "temporary files left behind"
echo "resume: $n particle frames, $m surface frames, $r images and the movie bit-identical"

# diff: equal sequences pass; a changed material fails, with difference images written.
"$bin" diff "$work/straight/render" "$work/killed/render" > "$work/diff_equal.out" || fail "diff of equal sequences failed: $(cat "$work/diff_equal.out")"
grep -q "16 frame(s) compared, 0 failed, 0 missing" "$work/diff_equal.out" || fail "diff summary: $(cat "$work/diff_equal.out")"
# Run folders stand for their render/ frames; --only-common lists one-sided frames without failing.
"$bin" diff "$work/straight" "$work/killed" > "$work/diff_runs.out" || fail "diff of run folders failed: $(cat "$work/diff_runs.out")"
grep -q "16 frame(s) compared, 0 failed, 0 missing" "$work/diff_runs.out" || fail "diff of run folders: $(cat "$work/diff_runs.out")"
mkdir -p "$work/partial" && cp "$work/straight/render/"render.000[0-3].png "$work/partial/"
"$bin" diff "$work/straight/render" "$work/partial" --format png --only-common > "$work/diff_common.out" ||
  fail "diff --only-common failed: $(cat "$work/diff_common.out")"
grep -q "4 frame(s) compared, 0 failed, 12 on one side only, skipped" "$work/diff_common.out" || fail "diff --only-common: $(cat "$work/diff_common.out")"
"$bin" diff "$work/straight/render" "$work/partial" --format png > /dev/null && fail "one-sided frames did not fail without --only-common"
rargs=(dam_break --set solver.particle_spacing=0.00714 --set scene.end_time=0.5 --resolution 64x36 --samples 2 --threads 2)
"$bin" render "${rargs[@]}" --frames 3 --out "$work/killed" 2> "$work/render.log" || fail "render stage failed"
grep -q "0 frame(s) rendered" "$work/render.log" || fail "finished render frames were redone"
rm "$work/killed/render/"*
"$bin" render "${rargs[@]}" --set 'render.material.water.absorption=[60.0, 8.0, 1.0]' --out "$work/killed" 2> /dev/null ||
  fail "render stage failed"
set +e
"$bin" diff "$work/straight/render" "$work/killed/render" --out "$work/diffs" > "$work/diff_changed.out"
status=$?
set -e
[ "$status" -eq 1 ] || fail "diff of different sequences exited $status: $(cat "$work/diff_changed.out")"
ls "$work/diffs"/*.diff.png > /dev/null 2>&1 || fail "no difference images written"
"$bin" diff "$work/straight/render/render.0003.png" "$work/straight/render/render.0003.png" > /dev/null || fail "diff of a file with itself failed"

# preview and encode alone: previews from particle files (here frames 4-9 only), and a movie
# from them when no rendered frames exist.
mkdir -p "$work/pv/particles"
mkdir -p "$work/pv/records"
for f in 4 5 6 7 8 9; do
  cp "$work/straight/particles/particles.000$f.vdb" "$work/pv/particles/"
  cp "$work/straight/records/particles.000$f.txt" "$work/pv/records/"
done
"$bin" preview dam_break --set solver.particle_spacing=0.00714 --set scene.end_time=0.5 --resolution 64x36 --frames 0-15 \
  --out "$work/pv" 2> "$work/preview.log" || fail "preview failed: $(cat "$work/preview.log")"
[ -e "$work/pv/preview/preview.0005.png" ] || fail "no preview frame 5: $(cat "$work/preview.log")"
"$bin" encode dam_break --set solver.particle_spacing=0.00714 --set scene.end_time=0.5 --out "$work/pv" \
  2> "$work/encode.log" || fail "encode failed: $(cat "$work/encode.log")"
grep -q "6 preview frames from 4" "$work/encode.log" || fail "encode did not use the preview frames: $(cat "$work/encode.log")"
[ -s "$work/pv/dam_break.mp4" ] || fail "no movie"

# A re-run of a finished output directory computes nothing new and changes nothing.
cp "$work/straight/particles/$last" "$work/last.vdb"
"$bin" "${args[@]}" --out "$work/straight" 2> "$work/again.log" || fail "re-run failed"
cmp -s "$work/last.vdb" "$work/straight/particles/$last" || fail "re-run changed $last"

# A later frame range first, then an earlier one: the earlier frames are simulated again
# (from frame 0) rather than skipped because the checkpoint is past them.
"$bin" "${args[@]}" --stages sim --frames 10-12 --out "$work/ranges" 2> /dev/null || fail "range run failed"
[ -e "$work/ranges/particles/particles.0005.vdb" ] && fail "frame 5 written outside --frames 10-12"
"$bin" "${args[@]}" --stages sim --frames 4-6 --out "$work/ranges" 2> "$work/ranges.log" || fail "second range run failed"
grep -q "simulating again from frame 0" "$work/ranges.log" || fail "missing earlier frames not noticed"
cmp -s "$work/ranges/particles/particles.0005.vdb" "$work/straight/particles/particles.0005.vdb" || fail "frame 5 differs"

# The surface stage alone, on frames that exist, with other surfacing settings: it does not
# touch the simulation's checkpoint (surfacing settings are not part of its identity).
"$bin" surface dam_break --set solver.particle_spacing=0.00714 --set scene.end_time=0.5 --set surfacing.voxel_ratio=0.7 \
  --frames 2-3 --out "$work/straight" 2> "$work/surface.log" || fail "surface stage failed: $(cat "$work/surface.log")"
grep -q "0 frame(s) surfaced" "$work/surface.log" || fail "finished surface frames were redone"
rm "$work/straight/surface/surface.0003.vdb"
"$bin" surface dam_break --set solver.particle_spacing=0.00714 --set scene.end_time=0.5 --set 'surfacing.meshes=["ply"]' \
  --frames 3 --out "$work/straight" 2> "$work/surface2.log" || fail "surface stage failed: $(cat "$work/surface2.log")"
[ -e "$work/straight/surface/surface.0003.vdb" ] && [ -e "$work/straight/mesh/water.0003.ply" ] || fail "surface frame 3 not redone"
head -c 3 "$work/straight/mesh/water.0003.ply" | grep -q ply || fail "not a PLY file"

# validate: a broken scene gets file, line, key and range; exit status 2.
cat > "$work/bad.toml" <<'TOML'
[scene]
name = "bad"
end_time = 1.0
frame_rate = 30
domain_min = [0.0, 0.0, 0.0]
domain_max = [1.0, 1.0, 1.0]
[solver]
particle_spacing = 0.05
cfl = 30.0
[[phase]]
name = "water"
stiffness = 1000.0
[[fluid]]
phase = "oil"
min = [0.0, 0.0, 0.0]
max = [0.5, 0.5, 0.5]
TOML
set +e
"$bin" validate "$work/bad.toml" > "$work/validate.out" 2>&1
status=$?
set -e
[ "$status" -eq 2 ] || fail "validate exit status $status for cfl = 30, expected 2"
grep -q "bad.toml:9: key 'solver.cfl': value 30 outside the allowed range (0, 10\]" "$work/validate.out" ||
  fail "validate message: $(cat "$work/validate.out")"
grep -q "bad.toml:14: key 'fluid\[0\].phase': unknown phase \"oil\"" "$work/validate.out" ||
  fail "validate did not report every problem: $(cat "$work/validate.out")"
"$bin" validate dam_break > /dev/null || fail "embedded dam_break does not validate"

# The default scene (the lava lamp), its first frames through every stage at tiny size.
"$bin" run lava_lamp --frames 0-2 --resolution 24x40 --samples 1 --threads 2 --out "$work/lamp" 2> "$work/lamp.log" ||
  fail "lava_lamp failed: $(tail -5 "$work/lamp.log")"
for f in particles/particles.0002.vdb surface/surface.0002.vdb render/render.0002.png render/render.0002.exr lava_lamp.mp4; do
  [ -s "$work/lamp/$f" ] || fail "lava_lamp did not write $f"
done

set +e
"$bin" run --frames 5-2 > /dev/null 2>&1
[ $? -eq 2 ] || fail "--frames 5-2 accepted"
"$bin" run --bogus > /dev/null 2>&1
[ $? -eq 2 ] || fail "unknown option accepted"
set -e
echo "cli: all checks passed"
