# Opens a .blend written by `multifluid export blender` (this runs inside Blender:
#   blender -b FILE.blend --python-exit-code 1 -P blender_check.py -- EXPECT.json RENDER.png)
# and checks it against values the test states from the scene file (not from the manifest):
# objects, modifiers, materials, camera, light, frame range and rate, containers; then renders
# one small Cycles frame and checks that the fluid shows (pixels differ from a render without it).
import json
import math
import sys

import bpy
from mathutils import Vector

expect_path, png = sys.argv[sys.argv.index("--") + 1:]
with open(expect_path) as fh:
    ex = json.load(fh)
scene = bpy.context.scene
failures = []


def check(ok, what):
    print(("ok  " if ok else "FAIL") + " " + what)
    if not ok:
        failures.append(what)


def close(a, b, tol):
    return all(abs(x - y) <= tol for x, y in zip(a, b))


def to_blender(p):  # the scene's y up -> Blender's z up
    return Vector((p[0], -p[2], p[1]))


TOL = 1e-4  # m and radians: the manifest carries 9 significant digits, Blender floats 7
check(scene.frame_start == ex["frame_start"] and scene.frame_end == ex["frame_end"],
      "frame range %d-%d (expected %d-%d)" % (scene.frame_start, scene.frame_end, ex["frame_start"], ex["frame_end"]))
fps = scene.render.fps / scene.render.fps_base
check(abs(fps - ex["fps"]) < 1e-6, "frame rate %.6f (expected %g)" % (fps, ex["fps"]))
check(scene.render.engine == "CYCLES", "render engine " + scene.render.engine)
check((scene.render.resolution_x, scene.render.resolution_y, scene.cycles.samples) == tuple(ex["image"]),
      "image %dx%d, %d samples (expected %s)" % (scene.render.resolution_x, scene.render.resolution_y, scene.cycles.samples, ex["image"]))
rel = [v.filepath for v in bpy.data.volumes if not v.filepath.startswith("//")]
check(not rel, "volume paths relative to the .blend (%s)" % rel)

cam = scene.camera
check(cam is not None, "a scene camera")
if cam:
    pos = cam.matrix_world.translation
    ctol = ex.get("camera_tolerance", TOL)
    check(close(pos, to_blender(ex["camera_position"]), ctol), "camera at %s (expected %s)" % (tuple(pos), ex["camera_position"]))
    view = cam.matrix_world.to_3x3() @ Vector((0, 0, -1))
    want = (to_blender(ex["look_at"]) - to_blender(ex["camera_position"])).normalized()
    check(view.angle(want) < 2 * ctol, "camera looks at %s (off by %.2e rad)" % (ex["look_at"], view.angle(want)))
    check(abs(cam.data.angle_y - math.radians(ex["fov"])) < TOL,
          "vertical field of view %.4f deg (expected %g)" % (math.degrees(cam.data.angle_y), ex["fov"]))
# A moving camera: the pose the renderer uses at each listed frame (the keys' own frames).
for k in ex.get("camera_frames", []):
    scene.frame_set(k["frame"])
    pos = cam.matrix_world.translation
    check(close(pos, to_blender(k["position"]), TOL), "frame %d: camera at %s (expected %s)" % (k["frame"], tuple(pos), k["position"]))
    view = cam.matrix_world.to_3x3() @ Vector((0, 0, -1))
    want = (to_blender(k["look_at"]) - to_blender(k["position"])).normalized()
    check(view.angle(want) < 2 * TOL, "frame %d: camera looks at %s (off by %.2e rad)" % (k["frame"], k["look_at"], view.angle(want)))
    check(abs(cam.data.angle_y - math.radians(k["fov"])) < TOL,
          "frame %d: vertical field of view %.4f deg (expected %g)" % (k["frame"], math.degrees(cam.data.angle_y), k["fov"]))
if ex.get("camera_frames"):
    scene.frame_set(ex["frame_start"])
lights = [o for o in scene.objects if o.type == "LIGHT"]
check(len(lights) == 1, "one light (found %d)" % len(lights))
if lights:
    l = lights[0]
    check(close(l.matrix_world.translation, to_blender(ex["light_position"]), TOL), "light at %s" % (tuple(l.matrix_world.translation),))
    check(abs(l.data.shadow_soft_size - ex["light_radius"]) < TOL, "light radius %.4f (expected %g)" % (l.data.shadow_soft_size, ex["light_radius"]))

for c in ex["containers"]:
    o = scene.objects.get(c)
    check(o is not None and o.type == "MESH" and len(o.data.polygons) > 0, "container %s is a mesh" % c)
    if o:
        p = o.active_material.node_tree.nodes.get("Principled BSDF")
        check(p is not None and p.inputs["Transmission"].default_value == 1.0, "container %s is glass" % c)

deps = bpy.context.evaluated_depsgraph_get()
fluid_objects = []
for f in ex["fluids"]:
    o = scene.objects.get(f["name"])
    if ex["meshes"] == "vdb":
        check(o is not None and o.type == "MESH", "fluid %s is a mesh object" % f["name"])
        if not o:
            continue
        mods = [m for m in o.modifiers if m.type == "VOLUME_TO_MESH"]
        check(len(mods) == 1 and mods[0].grid_name == f["name"] and mods[0].object and mods[0].object.type == "VOLUME",
              "fluid %s has a Volume to Mesh modifier on grid %s of a volume object" % (f["name"], f["name"]))
        vol = mods[0].object.data
        verts = {}
        for frame in (scene.frame_start, scene.frame_end):
            scene.frame_set(frame)
            deps = bpy.context.evaluated_depsgraph_get()
            vol_eval = mods[0].object.evaluated_get(deps).data
            want = "surface.%04d.vdb" % frame
            check(vol_eval.grids.frame_filepath.endswith(want), "frame %d reads %s (%s)" % (frame, want, vol_eval.grids.frame_filepath))
            verts[frame] = len(o.evaluated_get(deps).data.vertices)
            check(verts[frame] > 100, "fluid %s meshed at frame %d: %d vertices" % (f["name"], frame, verts[frame]))
        check(verts[scene.frame_start] != verts[scene.frame_end], "fluid %s changes over the sequence" % f["name"])
        mats = [m.name for m in o.evaluated_get(deps).data.materials]
        check(mats == [f["name"]], "the meshed fluid %s carries its material (%s)" % (f["name"], mats))
        # At the last frame the mesh lies where the project's own mesher puts it (the run's PLY).
        me = o.evaluated_get(deps).data
        got = [o.matrix_world @ v.co for v in me.vertices]
        bpy.ops.import_mesh.ply(filepath=f["reference_ply"])
        ref_obj = bpy.context.selected_objects[0]
        ref_obj.parent = o.parent
        bpy.context.view_layer.update()
        ref = [ref_obj.matrix_world @ v.co for v in ref_obj.data.vertices]
        box = lambda pts: [min(p[i] for p in pts) for i in range(3)] + [max(p[i] for p in pts) for i in range(3)]
        check(len(got) == len(ref) and close(box(got), box(ref), 1e-5),
              "fluid %s at frame %d: %d vertices in %s, the run's PLY mesh %d in %s" % (f["name"], scene.frame_end, len(got),
              [round(x, 5) for x in box(got)], len(ref), [round(x, 5) for x in box(ref)]))
        bpy.data.objects.remove(ref_obj)
        scene.frame_set(scene.frame_start)
        fluid_objects.append(o)
    else:
        frames = [x for x in scene.objects if x.name.startswith(f["name"] + ".") and x.type == "MESH"]
        check(len(frames) == ex["frame_end"] - ex["frame_start"] + 1, "fluid %s: one PLY mesh per frame (%d)" % (f["name"], len(frames)))
        scene.frame_set(scene.frame_start + 1)
        shown = [x.name for x in frames if not x.hide_render]
        want = "%s.%04d" % (f["name"], scene.frame_start + 1)
        check(shown == [want], "at frame %d only %s renders (%s)" % (scene.frame_current, want, shown))
        check(all(len(x.data.vertices) > 100 for x in frames), "fluid %s: every frame's mesh has vertices" % f["name"])
        scene.frame_set(scene.frame_start)
        fluid_objects += [x for x in frames if not x.hide_render]
        o = frames[0] if frames else None
    if o:
        mat = o.active_material
        p = mat.node_tree.nodes.get("Principled BSDF") if mat else None
        check(p is not None, "fluid %s has a Principled BSDF" % f["name"])
        if p:
            check(p.inputs["Transmission"].default_value == 1.0, "fluid %s transmits" % f["name"])
            check(abs(p.inputs["IOR"].default_value - f["ior"]) < 1e-6, "fluid %s IOR %.4f (expected %g)" % (f["name"], p.inputs["IOR"].default_value, f["ior"]))
            a = mat.node_tree.nodes.get("Volume Absorption")
            sigma = [a.inputs["Density"].default_value * (1 - c) for c in a.inputs["Color"].default_value[:3]] if a else None
            check(sigma is not None and close(sigma, f["absorption"], 1e-3 * max(f["absorption"])),
                  "fluid %s absorbs %s per m (expected %s)" % (f["name"], sigma, f["absorption"]))

# One small Cycles frame with the fluid, one without: the fluid must change some pixels.
scene.render.resolution_x, scene.render.resolution_y = 64, 48
scene.cycles.samples = 4
scene.cycles.device = "CPU"
scene.render.image_settings.file_format = "PNG"


def render(path):
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    img = bpy.data.images.load(path)
    px = list(img.pixels)
    bpy.data.images.remove(img)
    return px


with_fluid = render(png)
for o in fluid_objects:
    o.animation_data_clear()  # PLY frames: their visibility is keyframed
    o.hide_render = True
without = render(png.replace(".png", "_nofluid.png"))
changed = sum(1 for k in range(0, len(with_fluid), 4) if max(abs(with_fluid[k + c] - without[k + c]) for c in range(3)) > 0.05)
check(changed >= ex["min_changed_pixels"], "the fluid changes %d of %d pixels (at least %d)" % (changed, 64 * 48, ex["min_changed_pixels"]))

if failures:
    raise RuntimeError("%d check(s) failed: %s" % (len(failures), "; ".join(failures)))
print("blender_check: all checks passed")
