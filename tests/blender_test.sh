#!/usr/bin/env bash
# `multifluid export blender` with the real Blender: a tiny two-fluid run (4 frames, coarse),
# exported twice (level sets with Volume to Mesh, and the PLY mesh sequence), each .blend opened
# in Blender and checked against the scene's values by blender_check.py, with a small Cycles
# render; the PLY point cloud imported in Blender; and the export's errors. Blender is required:
# CI installs it (scripts/setup.sh --with-blender).
set -euo pipefail
bin=$1
src=$2
work=$(mktemp -d); echo "work folder: $work"
trap '[ -n "${KEEP:-}" ] || rm -rf "$work"' EXIT  # KEEP=1: keep it, to look at the .blend and renders
fail() { echo "FAIL: $*" >&2; exit 1; }
command -v blender > /dev/null ||
  fail "blender is not installed (this test needs it): run scripts/setup.sh --with-blender, or apt-get install blender"

# water_oil has no camera keys: the renderer frames the tank, and the export must use that camera.
args=(water_oil --set solver.particle_spacing=0.015 --set scene.end_time=0.12 --threads 2 --resolution 32x24 --samples 1
  --set 'render.light_position=[0.4, 0.6, 0.5]' --set render.light_radius=0.05 --set render.material.oil.ior=1.5
  --set 'surfacing.meshes=["ply"]' --set surfacing.points_ply=true)
"$bin" run "${args[@]}" --stages sim --out "$work/run" 2> "$work/sim.log" || fail "sim failed: $(cat "$work/sim.log")"

# Errors: no run folder; no surface frames yet; no blender on PATH.
set +e
"$bin" export blender "$work" > /dev/null 2> "$work/e1.log"; s1=$?
"$bin" export blender "$work/run" > /dev/null 2> "$work/e2.log"; s2=$?
env PATH=/nonexistent "$bin" export blender "$work/run" > /dev/null 2> "$work/e3.log"; s3=$?
set -e
[ "$s1" -ne 0 ] && grep -q "is not a run folder" "$work/e1.log" || fail "a folder that is not a run: status $s1, $(cat "$work/e1.log")"
[ "$s2" -ne 0 ] && grep -q "no finished surface frames; run the surface stage" "$work/e2.log" ||
  fail "a run without surfaces: status $s2, $(cat "$work/e2.log")"
[ "$s3" -ne 0 ] && grep -q "setup.sh --with-blender" "$work/e3.log" || fail "no blender on PATH: status $s3, $(cat "$work/e3.log")"
ls "$work/run"/*.blend > /dev/null 2>&1 && fail "a failed export left a .blend"

"$bin" run "${args[@]}" --stages surface,render --frames 0 --out "$work/run" 2> "$work/render.log" || fail "render failed: $(cat "$work/render.log")"
"$bin" run "${args[@]}" --stages surface --out "$work/run" 2> "$work/surface.log" || fail "surface failed: $(cat "$work/surface.log")"
# The camera the renderer used, from its message "... framing the solids [lo]-[hi] from (x, y, z)"
# (3 significant digits: hence camera_tolerance below); it looks at the box's centre.
framing=$(grep -o 'framing the solids.*' "$work/render.log") || fail "the renderer printed no framing: $(cat "$work/render.log")"
read -r -a nums <<< "$(echo "$framing" | grep -oE -- '-?[0-9]+(\.[0-9]+)?(e[-+]?[0-9]+)?' | tr '\n' ' ')"
[ "${#nums[@]}" -eq 9 ] || fail "cannot read the framing message: $framing"

expect() {  # $1 = vdb|ply: the scene's values, stated here (water_oil.toml and the --set above)
  cat << EOF
{"frame_start": 0, "frame_end": 3, "fps": 25, "fov": 40, "meshes": "$1", "image": [32, 24, 1],
 "camera_position": [${nums[6]}, ${nums[7]}, ${nums[8]}],
 "look_at": [$(python3 -c "n=[float(x) for x in '${nums[*]}'.split()]; print(', '.join(str((n[k]+n[k+3])/2) for k in range(3)))")],
 "light_position": [0.4, 0.6, 0.5], "light_radius": 0.05,
 "fluids": [{"name": "water", "ior": 1.33, "absorption": [4.0, 1.2, 0.8], "reference_ply": "$work/run/mesh/water.0003.ply"},
   {"name": "oil", "ior": 1.5, "absorption": [1.0, 3.0, 25.0], "reference_ply": "$work/run/mesh/oil.0003.ply"}],
 "camera_tolerance": 0.005, "containers": ["tank"], "min_changed_pixels": 20}
EOF
}
# A Blender that hangs is stopped at --timeout; one that fails, or exits 0 without writing the
# file, leaves no .blend (stand-ins for blender on PATH).
mkdir -p "$work/fake"
printf '#!/bin/sh\nexec sleep 60\n' > "$work/fake/blender"
chmod +x "$work/fake/blender"
set +e
PATH="$work/fake:$PATH" "$bin" export blender "$work/run" --timeout 1 > /dev/null 2> "$work/e4.log"; s4=$?
printf '#!/bin/sh\necho "some python error" >&2\nexit 1\n' > "$work/fake/blender"
PATH="$work/fake:$PATH" "$bin" export blender "$work/run" > /dev/null 2> "$work/e5.log"; s5=$?
printf '#!/bin/sh\nexit 0\n' > "$work/fake/blender"
PATH="$work/fake:$PATH" "$bin" export blender "$work/run" > /dev/null 2> "$work/e6.log"; s6=$?
set -e
[ "$s4" -ne 0 ] && grep -q "time limit of 1 s" "$work/e4.log" || fail "a hanging blender: status $s4, $(cat "$work/e4.log")"
[ "$s5" -ne 0 ] && grep -q "some python error" "$work/e5.log" || fail "a failing blender: status $s5, $(cat "$work/e5.log")"
[ "$s6" -ne 0 ] && grep -q "wrote no file" "$work/e6.log" || fail "a blender that wrote nothing: status $s6, $(cat "$work/e6.log")"
ls "$work/run" | grep -q '\.blend$\|tmp' && fail "a failed export left a file: $(ls "$work/run")"

for meshes in vdb ply; do
  # Hostile characters in the output's folder: they reach Blender as one argument and as JSON.
  out="$work/out $meshes 'q' \"\$(touch pwned)\""
  t0=$(date +%s.%N)
  "$bin" export blender "$work/run" --meshes "$meshes" --out "$out/water_oil.blend" 2> "$work/export_$meshes.log" ||
    fail "export --meshes $meshes failed: $(cat "$work/export_$meshes.log")"
  t1=$(date +%s.%N)
  [ -s "$out/water_oil.blend" ] || fail "no .blend written"
  ls "$out" | grep -q tmp && fail "a temporary was left: $(ls "$out")"
  [ -e pwned ] || [ -e "$work/pwned" ] && fail "a file name was run as a command"
  expect "$meshes" > "$work/expect_$meshes.json"
  blender -b "$out/water_oil.blend" --factory-startup --python-exit-code 1 -P "$src/tests/blender_check.py" -- \
    "$work/expect_$meshes.json" "$work/render_$meshes.png" > "$work/check_$meshes.log" 2>&1 ||
    fail "the $meshes .blend fails its checks:
$(grep -E '^(FAIL|ok)|Error|error' "$work/check_$meshes.log")"
  grep -c '^ok' "$work/check_$meshes.log" | xargs echo "--meshes $meshes: export $(python3 -c "print(f'{$t1-$t0:.1f}')") s, checks passed:"
done
# A moving camera ([[render.camera_key]], 0 s and 0.12 s = frames 0 and 3): Blender's camera
# takes the renderer's pose at each key.
keys='render.camera_key=[{time=0, position=[0.2, 0.25, 0.9], look_at=[0.1, 0.05, 0.1]}, {time=0.12, position=[0.6, 0.35, 0.7], look_at=[0.15, 0.08, 0.1], fov=30}]'
"$bin" run "${args[@]}" --set "$keys" --stages sim,surface --out "$work/keys" 2> "$work/keys.log" || fail "the camera-key run failed: $(cat "$work/keys.log")"
"$bin" export blender "$work/keys" --out "$work/keys/keys.blend" 2> "$work/export_keys.log" ||
  fail "export of the camera-key run failed: $(cat "$work/export_keys.log")"
python3 - "$work/expect_vdb.json" "$work/keys/mesh" > "$work/expect_keys.json" << 'PY'
import json, sys
ex = json.load(open(sys.argv[1]))
ex["camera_position"], ex["look_at"], ex["camera_tolerance"] = [0.2, 0.25, 0.9], [0.1, 0.05, 0.1], 1e-4
ex["camera_frames"] = [{"frame": 0, "position": [0.2, 0.25, 0.9], "look_at": [0.1, 0.05, 0.1], "fov": 40},
                       {"frame": 3, "position": [0.6, 0.35, 0.7], "look_at": [0.15, 0.08, 0.1], "fov": 30}]
for f in ex["fluids"]:
    f["reference_ply"] = f["reference_ply"].replace("/run/mesh/", "/keys/mesh/")
print(json.dumps(ex))
PY
blender -b "$work/keys/keys.blend" --factory-startup --python-exit-code 1 -P "$src/tests/blender_check.py" -- \
  "$work/expect_keys.json" "$work/render_keys.png" > "$work/check_keys.log" 2>&1 ||
  fail "the camera-key .blend fails its checks:
$(grep -E '^(FAIL|ok)|Error|error' "$work/check_keys.log")"
grep -c '^ok' "$work/check_keys.log" | xargs echo "camera keys: checks passed:"
# The ramps: a coarse run of a scene (1 cm) to END s in $work/NAME, exported to NAME.blend.
run_and_export() {  # $1 = NAME, $2 = scene, $3 = END
  "$bin" run "$2" --set solver.particle_spacing=0.01 --set scene.end_time="$3" --threads 2 --stages sim,surface \
    --out "$work/$1" 2> "$work/$1.log" || fail "the $2 run failed: $(tail -5 "$work/$1.log")"
  "$bin" export blender "$work/$1" --out "$work/$1/$1.blend" 2> "$work/export_$1.log" ||
    fail "export of the $2 run failed: $(cat "$work/export_$1.log")"
}
# Runs $blend_prelude (below) then the checks $3 in Blender on $work/NAME/NAME.blend ($1) and
# prints their line starting with $2 (what is checked, also named if it fails).
check_blend() {  # $1 = NAME, $2 = what, $3 = Python
  blender -b "$work/$1/$1.blend" --factory-startup --python-exit-code 1 --python-expr "$blend_prelude$3" \
    -- "$work/$1_render.png" > "$work/$1_check.log" 2>&1 ||
    fail "the $2 in Blender: $(grep -E 'Error|assert' "$work/$1_check.log" | tail -5)"
  grep "^$2" "$work/$1_check.log"
}
# What each check_blend runs in Blender first: ramp_volume(name, grids) asserts a visible volume
# object reading exactly those grids and gives its nodes and Color Ramp elements; mesh_nodes(name)
# the fluid mesh's material nodes; cycles_pixels(w, h, spp, frame) renders to `out` in Cycles.
blend_prelude='
import bpy, sys
out = sys.argv[sys.argv.index("--") + 1]
def ramp_volume(name, grids):
    obj = bpy.data.objects[name]
    assert obj.type == "VOLUME" and not obj.hide_render, "%s is not a visible volume" % name
    nodes = obj.data.materials[0].node_tree.nodes
    names = sorted(n.attribute_name for n in nodes if n.type == "ATTRIBUTE")
    assert names == grids, "attributes read: %s" % names
    return nodes, [n for n in nodes if n.type == "VALTORGB"][0].color_ramp.elements
def mesh_nodes(name):
    return bpy.data.objects[name].data.materials[0].node_tree.nodes
def cycles_pixels(w, h, spp, frame):
    s = bpy.context.scene
    s.render.engine = "CYCLES"; s.cycles.samples = spp; s.render.resolution_x, s.render.resolution_y = w, h
    s.render.resolution_percentage = 100; s.frame_set(frame)
    s.render.filepath = out; bpy.ops.render.render(write_still=True)
    return list(bpy.data.images.load(out).pixels)
'
# An emission ramp (boiling's flames, a blackbody over temperature): a visible volume object
# of the VDB sequence maps the flames' temperature grid through the ramp inside their level set;
# the flame mesh keeps no constant emission; Cycles renders it glowing orange.
run_and_export boil boiling 0.12
check_blend boil "emission ramp" '
nodes, ramp = ramp_volume("flame_emission", ["flame", "temperature_flame"])
assert len(ramp) == 32, "%d ramp elements" % len(ramp)
assert max(ramp[0].color[:3]) < 1e-3 and abs(max(ramp[-1].color[:3]) - 1) < 1e-6, "ramp ends %s %s" % (tuple(ramp[0].color), tuple(ramp[-1].color))
assert ramp[-1].color[0] > ramp[-1].color[2], "the hot end is not orange"
assert not [n for n in mesh_nodes("flame") if n.type == "EMISSION"], "the flame mesh still emits a constant"
px = cycles_pixels(48, 27, 4, 3)
glow = sum(1 for i in range(0, len(px), 4) if px[i] > 0.2 and px[i] > 1.5 * px[i + 2])
print("emission ramp: 32 elements; %d orange pixels in Cycles" % glow)
assert glow > 0, "no pixel glows orange"
'
# An absorption ramp (diffusion's liquid, tinted by temperature): a visible volume object of the
# VDB sequence absorbs sigma_a from the ramp over the temperature grid inside the level set, in
# Cycles' terms (density 18 per m, colour 1 - sigma / 18); the liquid mesh keeps no constant
# absorption; Cycles renders the hot half red, as our renderer does.
run_and_export dif diffusion 0.2
check_blend dif "absorption ramp" '
nodes, ramp = ramp_volume("liquid_absorption", ["liquid", "temperature_liquid"])
assert [n for n in nodes if n.bl_idname == "ShaderNodeVolumeAbsorption"], "no Volume Absorption"
want = [[1 - c / 18 for c in s] for s in ([4.0, 1.2, 0.8], [1.5, 8.0, 5.0], [0.6, 18.0, 12.0])]  # diffusion.toml
got = [list(e.color[:3]) for e in ramp]
assert len(got) == 3 and all(abs(a - b) < 1e-6 for g, w in zip(got, want) for a, b in zip(g, w)), "ramp %s, expected %s" % (got, want)
assert not [n for n in mesh_nodes("liquid") if n.bl_idname == "ShaderNodeVolumeAbsorption"], "the liquid mesh still absorbs a constant"
px = cycles_pixels(64, 36, 8, 2)
red = sum(1 for i in range(0, len(px), 4) if px[i] > 0.05 and px[i] > 1.5 * px[i + 1])
print("absorption ramp: 3 elements; %d red pixels in Cycles" % red)
assert red > 0, "no pixel is tinted red"
'
# Motion blur (render.shutter, with the velocity grids): the fluid set moving at 1 m/s along x;
# exported as the PLY sequence, each frame's mesh carries its PLY's velocities as the "velocity"
# attribute, Cycles' motion blur is on at the run's shutter, and a Cycles frame moves against the
# same frame with every velocity set to zero (the same samples otherwise). The level-set export
# of that run says it cannot blur.
"$bin" run "${args[@]}" --set surfacing.velocity=true --set render.shutter=0.5 --set 'fluid.0.velocity=[1.0, 0.0, 0.0]' \
  --stages sim,surface --out "$work/blur" 2> "$work/blur.log" || fail "the motion-blur run failed: $(tail -5 "$work/blur.log")"
"$bin" export blender "$work/blur" --meshes ply --out "$work/blur/blur.blend" 2> "$work/export_blur.log" ||
  fail "export of the motion-blur run failed: $(cat "$work/export_blur.log")"
"$bin" export blender "$work/blur" --out "$work/blur/blur_vdb.blend" 2> "$work/export_blur_vdb.log" ||
  fail "level-set export of the motion-blur run failed: $(cat "$work/export_blur_vdb.log")"
grep -q "export with --meshes ply for motion blur" "$work/export_blur_vdb.log" ||
  fail "the level-set export did not say it cannot blur: $(cat "$work/export_blur_vdb.log")"
check_blend blur "motion blur" '
import struct
s = bpy.context.scene
assert s.render.use_motion_blur and abs(s.render.motion_blur_shutter - 0.5) < 1e-6, "motion blur %s, shutter %s" % (s.render.use_motion_blur, s.render.motion_blur_shutter)
fastest = 0
for name in ("water", "oil"):
    me = bpy.data.objects["%s.0003" % name].data
    path = "'"$work"'/blur/mesh/%s.0003.ply" % name
    data = open(path, "rb").read()
    start = data.index(b"end_header\n") + 11
    assert b"property float vx" in data[:start], path + " has no velocities"
    n = len(me.vertices)
    want = struct.unpack_from("<%df" % (6 * n), data, start)
    got = [0.0] * (3 * n)
    me.attributes["velocity"].data.foreach_get("vector", got)
    worst = max(abs(got[3 * k + c] - want[6 * k + 3 + c]) for k in range(n) for c in range(3))
    assert worst < 1e-6, "%s: velocity attribute off its PLY by %g" % (name, worst)
    fastest = max(fastest, max(abs(v) for v in got))
assert fastest > 0.2, "the fluid hardly moves: %g m/s" % fastest
blurred = cycles_pixels(48, 36, 4, 3)
for ob in bpy.data.objects:
    if ob.type == "MESH" and "velocity" in ob.data.attributes:
        a = ob.data.attributes["velocity"]
        a.data.foreach_set("vector", [0.0] * (3 * len(a.data)))
still = cycles_pixels(48, 36, 4, 3)
moved = sum(1 for k in range(0, len(still), 4) if max(abs(blurred[k + c] - still[k + c]) for c in range(3)) > 0.02)
print("motion blur: shutter 0.5, velocity attributes equal their PLY (fastest %.2f m/s); %d of %d pixels move in Cycles" % (fastest, moved, len(still) // 4))
assert moved >= 10, "motion blur moved %d pixels" % moved
'
# The PLY point cloud in Blender's PLY importer: every particle a vertex; which properties it keeps.
ply=$work/run/points/points.0002.ply
n=$(head -c 2000 "$ply" | grep -a -m1 '^element vertex' | awk '{print $3}')
blender -b --factory-startup --python-exit-code 1 --python-expr '
import bpy, sys
path, n = sys.argv[sys.argv.index("--") + 1:]
bpy.ops.import_mesh.ply(filepath=path)
me = bpy.context.selected_objects[0].data
print("points: %d vertices, %d edges, %d faces; attributes: %s" % (len(me.vertices), len(me.edges), len(me.polygons),
      " ".join(sorted(a.name for a in me.attributes))))
if len(me.vertices) != int(n) or len(me.polygons) != 0:
    raise RuntimeError("expected %s vertices and no faces" % n)
import struct  # the first vertex where the file has it: float x y z right after the header
data = open(path, "rb").read()
x = struct.unpack_from("<3f", data, data.index(b"end_header\n") + 11)
if (me.vertices[0].co - __import__("mathutils").Vector(x)).length > 1e-7:
    raise RuntimeError("vertex 0 at %s, the file has %s" % (tuple(me.vertices[0].co), x))
' -- "$ply" "$n" > "$work/points.log" 2>&1 || fail "Blender did not import the PLY point cloud: $(tail -5 "$work/points.log")"
grep '^points:' "$work/points.log"
echo "PASS"
