# Builds a .blend from a multifluid run: run by `multifluid export blender` as
#   blender -b --factory-startup --python-exit-code 1 -P build_blend.py -- MANIFEST.json OUT.blend
# The manifest (written by pipeline/export_blender.cpp) has the scene as run in its own
# coordinates (y up, metres); everything is parented to one empty turned +90 degrees about x, so
# that y up becomes Blender's z up and the files (VDB, PLY) load unchanged. Tested with Blender
# 3.4 (Debian 12). Any error raises, and Blender then exits 1 without writing OUT.
import json
import math
import os
import struct
import sys

import bpy
from mathutils import Matrix, Vector


def args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if len(argv) != 2:
        raise RuntimeError("usage: blender -b -P build_blend.py -- MANIFEST.json OUT.blend")
    return [os.path.abspath(a) for a in argv]


def node_tree(mat):
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    for n in list(nodes):
        nodes.remove(n)
    out = nodes.new("ShaderNodeOutputMaterial")
    return mat.node_tree, out


def add_absorption(tree, out, sigma, extra=None):
    """Beer-Lambert sigma_a per RGB channel (1/m). Cycles' Volume Absorption absorbs
    density * (1 - colour) per unit length, so density = max(sigma), colour = 1 - sigma / density."""
    density = max(sigma)
    shaders = []
    if density > 0:
        a = tree.nodes.new("ShaderNodeVolumeAbsorption")
        a.inputs["Density"].default_value = density
        a.inputs["Color"].default_value = [1 - s / density for s in sigma] + [1.0]
        shaders.append(a)
    if extra is not None:
        shaders.append(extra)
    if not shaders:
        return
    node = shaders[0]
    for s in shaders[1:]:
        add = tree.nodes.new("ShaderNodeAddShader")
        tree.links.new(node.outputs[0], add.inputs[0])
        tree.links.new(s.outputs[0], add.inputs[1])
        node = add
    tree.links.new(node.outputs[0], out.inputs["Volume"])


def make_material(name, m):
    """The renderer's material kinds (render/settings.h MaterialSpec) in Cycles nodes."""
    mat = bpy.data.materials.new(name)
    tree, out = node_tree(mat)
    mat["multifluid_kind"] = m["kind"]
    if m["kind"] in ("dielectric", "medium"):
        p = tree.nodes.new("ShaderNodeBsdfPrincipled")
        p.inputs["Base Color"].default_value = (1, 1, 1, 1)
        p.inputs["Transmission"].default_value = 1.0
        p.inputs["Roughness"].default_value = 0.0
        p.inputs["IOR"].default_value = m["ior"]
        tree.links.new(p.outputs[0], out.inputs["Surface"])
        extra = None
        if m["kind"] == "medium":  # isotropic scattering sigma_s
            scatter = tree.nodes.new("ShaderNodeVolumeScatter")
            scatter.inputs["Density"].default_value = m["scattering"]
            scatter.inputs["Color"].default_value = (1, 1, 1, 1)
            extra = scatter
        # Emission as radiance per metre, in any volume (the renderer's flames are dielectrics);
        # an emission ramp replaces it (ramp_volume).
        e = m["emission"]
        if max(e) > 0 and not m.get("emission_ramp"):
            em = tree.nodes.new("ShaderNodeEmission")
            em.inputs["Color"].default_value = [c / max(e) for c in e] + [1.0]
            em.inputs["Strength"].default_value = max(e)
            if extra is None:
                extra = em
            else:
                add = tree.nodes.new("ShaderNodeAddShader")
                tree.links.new(extra.outputs[0], add.inputs[0])
                tree.links.new(em.outputs[0], add.inputs[1])
                extra = add
        # An absorption ramp replaces the constant absorption (ramp_volume).
        add_absorption(tree, out, [0.0, 0.0, 0.0] if m.get("absorption_ramp") else m["absorption"], extra)
    elif m["kind"] == "diffuse":
        d = tree.nodes.new("ShaderNodeBsdfDiffuse")
        d.inputs["Color"].default_value = list(m["colour"]) + [1.0]
        tree.links.new(d.outputs[0], out.inputs["Surface"])
    else:  # emitter
        e = m["emission"]
        em = tree.nodes.new("ShaderNodeEmission")
        peak = max(max(e), 1e-12)
        em.inputs["Color"].default_value = [c / peak for c in e] + [1.0]
        em.inputs["Strength"].default_value = max(e)
        tree.links.new(em.outputs[0], out.inputs["Surface"])
    return mat


def link(obj, coll, root):
    coll.objects.link(obj)
    obj.parent = root
    return obj


def vdb_sequence(name, man):
    """The run's surface VDB files as a volume datablock, one file per frame."""
    vol = bpy.data.volumes.new(name)
    vol.filepath = man["surface_first_file"]
    n = man["frame_end"] - man["frame_start"] + 1
    vol.is_sequence = n > 1
    # The file number read at scene frame F is F - frame_start + 1 + frame_offset.
    vol.frame_start = man["frame_start"]
    vol.frame_duration = n
    vol.frame_offset = man["frame_start"] - 1
    vol.sequence_mode = "CLIP"
    return vol


def ramp_volume(f, man, coll, root, key):
    """A fluid's emission or absorption ramp (`key`; the renderer's coefficient from an attribute
    grid, inside the fluid) as a volume object of the VDB sequence: the grid mapped over the
    ramp's range through a Color Ramp of its colours (at most 32, Blender's limit), where the
    fluid's level set is negative. Emission is radiance per metre; absorption is sigma_a per
    metre, which Cycles' Volume Absorption takes as density * (1 - colour)."""
    r = f["material"].get(key + "_ramp")
    if not r:
        return None
    name = f["name"] + "_" + key
    obj = link(bpy.data.objects.new(name, vdb_sequence(name, man)), coll, root)
    mat = bpy.data.materials.new(name)
    tree, out = node_tree(mat)
    value = tree.nodes.new("ShaderNodeAttribute")
    value.attribute_name = r["grid"]
    span = tree.nodes.new("ShaderNodeMapRange")
    span.inputs["From Min"].default_value, span.inputs["From Max"].default_value = r["range"]
    tree.links.new(value.outputs["Fac"], span.inputs["Value"])
    colours = r["colours"]
    picks = sorted({round(k * (len(colours) - 1) / (min(32, len(colours)) - 1)) for k in range(min(32, len(colours)))})
    peak = max(max(max(c) for c in colours), 1e-12)
    ramp = tree.nodes.new("ShaderNodeValToRGB")
    elements = ramp.color_ramp.elements  # two to start with, at 0 and 1; kept sorted by position
    positions = [k / (len(colours) - 1) for k in picks]
    elements[0].position, elements[-1].position = 0.0, 1.0
    for pos in positions[1:-1]:
        elements.new(pos)
    for e in elements:
        i = min(range(len(picks)), key=lambda i: abs(positions[i] - e.position))
        scaled = [c / peak for c in colours[picks[i]]]
        e.color = (scaled if key == "emission" else [1 - c for c in scaled]) + [1.0]
    tree.links.new(span.outputs["Result"], ramp.inputs["Fac"])
    phi = tree.nodes.new("ShaderNodeAttribute")
    phi.attribute_name = f["grid"]
    inside = tree.nodes.new("ShaderNodeMath")
    inside.operation = "LESS_THAN"
    inside.inputs[1].default_value = 0.0
    tree.links.new(phi.outputs["Fac"], inside.inputs[0])
    strength = tree.nodes.new("ShaderNodeMath")
    strength.operation = "MULTIPLY"
    strength.inputs[1].default_value = peak
    tree.links.new(inside.outputs[0], strength.inputs[0])
    if key == "emission":
        shader = tree.nodes.new("ShaderNodeEmission")
        tree.links.new(strength.outputs[0], shader.inputs["Strength"])
    else:
        shader = tree.nodes.new("ShaderNodeVolumeAbsorption")
        tree.links.new(strength.outputs[0], shader.inputs["Density"])
    tree.links.new(ramp.outputs["Color"], shader.inputs["Color"])
    tree.links.new(shader.outputs[0], out.inputs["Volume"])
    obj.data.materials.append(mat)
    obj["multifluid_%s_grid" % key] = r["grid"]
    return obj


def fluid_from_vdb(f, man, coll, root):
    """The level-set sequence as a volume object (hidden) and a mesh object whose Volume to Mesh
    modifier meshes this fluid's grid at its zero crossing."""
    vol = vdb_sequence(f["name"] + "_levelset", man)
    vobj = link(bpy.data.objects.new(f["name"] + "_levelset", vol), coll, root)
    vobj.hide_render = True
    vobj.display_type = "WIRE"
    # Blender 3.4's Volume to Mesh moves its vertices by half a voxel (+x, +y, +z of the grid) from
    # OpenVDB's zero crossing; moving the volume back puts the mesh where the renderer's is
    # (measured: then it matches the run's PLY mesh of the same frame).
    h = 0.5 * man["voxel_size"]
    vobj.location = (-h, -h, -h)
    me = bpy.data.meshes.new(f["name"])
    obj = link(bpy.data.objects.new(f["name"], me), coll, root)
    mod = obj.modifiers.new("Volume to Mesh", "VOLUME_TO_MESH")
    mod.object = vobj
    mod.grid_name = f["grid"]
    mod.threshold = 0.0  # the level set's zero crossing (distances in metres)
    mod.resolution_mode = "GRID"
    mod.use_smooth_shade = True
    return obj


def ply_velocities(path, count):
    """The vertices' vx, vy, vz of one of surfacing's binary PLY meshes (mesh_io.cpp), or None.
    Blender's PLY importer drops properties it does not know."""
    with open(path, "rb") as fh:
        header = []
        while True:
            line = fh.readline()
            if not line:
                raise RuntimeError(path + ": no end_header")
            line = line.decode("ascii").strip()
            if line == "end_header":
                break
            header.append(line)
        props, in_vertex = [], False
        for line in header:
            words = line.split()
            if words[0] == "element":
                in_vertex = words[1] == "vertex"
                if in_vertex and int(words[2]) != count:
                    raise RuntimeError("%s: %s vertices, Blender imported %d" % (path, words[2], count))
            elif words[0] == "property" and in_vertex:
                if words[1] != "float":
                    raise RuntimeError(path + ": vertex property " + line + " is not float")
                props.append(words[2])
        if props[3:6] != ["vx", "vy", "vz"]:
            return None
        data = fh.read(4 * len(props) * count)
    values = struct.unpack("<%df" % (len(props) * count), data)
    n = len(props)
    return [values[k * n + 3 + c] for k in range(count) for c in range(3)]


def fluid_from_ply(f, man, coll, root):
    """One imported PLY mesh per frame, each visible on its frame only (keyframed visibility).
    Each vertex's velocity becomes the mesh's "velocity" attribute: Cycles blurs a mesh whose
    topology changes from frame to frame by it (in the object's space, the scene's m/s)."""
    sub = bpy.data.collections.new(f["name"] + "_frames")
    coll.children.link(sub)
    objs = []
    for k, path in enumerate(f["ply_meshes"]):
        frame = man["frame_start"] + k
        bpy.ops.import_mesh.ply(filepath=path)
        obj = bpy.context.selected_objects[0]
        for c in list(obj.users_collection):
            c.objects.unlink(obj)
        sub.objects.link(obj)
        obj.name = "%s.%04d" % (f["name"], frame)
        obj.parent = root
        vel = ply_velocities(path, len(obj.data.vertices))
        if vel is not None:
            obj.data.attributes.new("velocity", "FLOAT_VECTOR", "POINT").data.foreach_set("vector", vel)
        for fr, hidden in ((frame - 1, True), (frame, False), (frame + 1, True)):
            obj.hide_render = obj.hide_viewport = hidden
            obj.keyframe_insert("hide_render", frame=fr)
            obj.keyframe_insert("hide_viewport", frame=fr)
        for fc in obj.animation_data.action.fcurves:
            for kp in fc.keyframe_points:
                kp.interpolation = "CONSTANT"
        objs.append(obj)
    return objs


def world(man):
    """The renderer's sky: horizon to zenith by sqrt(up), ground below the horizon."""
    w = bpy.data.worlds.new("multifluid_sky")
    bpy.context.scene.world = w
    w.use_nodes = True
    t = w.node_tree
    for n in list(t.nodes):
        t.nodes.remove(n)
    coord = t.nodes.new("ShaderNodeTexCoord")
    sep = t.nodes.new("ShaderNodeSeparateXYZ")
    t.links.new(coord.outputs["Generated"], sep.inputs[0])
    sqrt = t.nodes.new("ShaderNodeMath")
    sqrt.operation = "SQRT"  # Blender's is 0 below 0
    t.links.new(sep.outputs["Z"], sqrt.inputs[0])
    sky = t.nodes.new("ShaderNodeMixRGB")
    t.links.new(sqrt.outputs[0], sky.inputs["Fac"])
    sky.inputs["Color1"].default_value = list(man["sky"]["horizon"]) + [1]
    sky.inputs["Color2"].default_value = list(man["sky"]["zenith"]) + [1]
    below = t.nodes.new("ShaderNodeMath")
    below.operation = "LESS_THAN"
    below.inputs[1].default_value = 0.0
    t.links.new(sep.outputs["Z"], below.inputs[0])
    ground = t.nodes.new("ShaderNodeMixRGB")
    t.links.new(below.outputs[0], ground.inputs["Fac"])
    t.links.new(sky.outputs[0], ground.inputs["Color1"])
    ground.inputs["Color2"].default_value = list(man["sky"]["ground"]) + [1]
    bg = t.nodes.new("ShaderNodeBackground")
    t.links.new(ground.outputs[0], bg.inputs["Color"])
    out = t.nodes.new("ShaderNodeOutputWorld")
    t.links.new(bg.outputs[0], out.inputs["Surface"])


def camera_matrix(position, look_at):
    pos, target = Vector(position), Vector(look_at)
    forward = (target - pos).normalized()
    right = forward.cross(Vector((0, 1, 0))).normalized()
    if right.length == 0:  # looking straight up or down: the renderer's choice of image x
        right = Vector((1, 0, 0))
    up = right.cross(forward)
    # Blender's camera looks down its -z with +y up.
    m = Matrix((right, up, -forward)).transposed().to_4x4()
    m.translation = pos
    return m


def camera(man, coll, root):
    c = man["camera"]
    cam = bpy.data.cameras.new("camera")
    cam.sensor_fit = "VERTICAL"
    cam.angle_y = math.radians(c["fov_vertical_degrees"])
    cam.clip_start, cam.clip_end = 0.01, 1000.0
    obj = link(bpy.data.objects.new("camera", cam), coll, root)
    obj.matrix_basis = camera_matrix(c["position"], c["look_at"])
    # A moving camera ([[render.camera_key]]): the renderer's pose keyed at every frame, so
    # that Blender's interpolation between keys never departs from it.
    for k in man.get("camera_frames", []):
        m = camera_matrix(k["position"], k["look_at"])
        obj.location = m.translation
        # Euler angles compatible with the previous key's: no 360-degree turn between frames.
        obj.rotation_euler = m.to_euler(obj.rotation_mode, obj.rotation_euler)
        obj.keyframe_insert("location", frame=k["frame"])
        obj.keyframe_insert("rotation_euler", frame=k["frame"])
        cam.angle_y = math.radians(k["fov_vertical_degrees"])
        cam.keyframe_insert("lens", frame=k["frame"])
    bpy.context.scene.camera = obj
    if c["framing"]:
        obj["multifluid_framing"] = c["framing"]


def light(man, coll, root):
    """The renderer's spherical area light of radiance L and radius r as a point light of that
    radius: Cycles gives a point light of power P the radiance P / (4 pi^2 r^2)."""
    l = man["light"]
    if l["radius"] <= 0:
        return
    e, r = l["emission"], l["radius"]
    peak = max(e)
    lamp = bpy.data.lights.new("light", "POINT")
    lamp.shadow_soft_size = r
    lamp.color = [c / peak for c in e] if peak > 0 else (1, 1, 1)
    lamp.energy = 4 * math.pi ** 2 * r * r * peak
    obj = link(bpy.data.objects.new("light", lamp), coll, root)
    obj.location = l["position"]


def floor(man, coll, root):
    f = man["floor"]
    if not f["enabled"]:
        return
    size = 50.0
    me = bpy.data.meshes.new("floor")
    h = f["height"]
    me.from_pydata([(-size, h, -size), (size, h, -size), (size, h, size), (-size, h, size)], [], [(0, 3, 2, 1)])
    obj = link(bpy.data.objects.new("floor", me), coll, root)
    mat = bpy.data.materials.new("floor")
    tree, out = node_tree(mat)
    d = tree.nodes.new("ShaderNodeBsdfDiffuse")
    tree.links.new(d.outputs[0], out.inputs["Surface"])
    if f["checker_size"] > 0:
        # The renderer's checks of that size (Cycles' checks are 1 / scale wide); in the object's
        # coordinates, which are the scene's.
        coord = tree.nodes.new("ShaderNodeTexCoord")
        chk = tree.nodes.new("ShaderNodeTexChecker")
        chk.inputs["Scale"].default_value = 1.0 / f["checker_size"]
        chk.inputs["Color1"].default_value = (0.75, 0.75, 0.75, 1)
        chk.inputs["Color2"].default_value = (0.15, 0.15, 0.15, 1)
        tree.links.new(coord.outputs["Object"], chk.inputs["Vector"])
        tree.links.new(chk.outputs["Color"], d.inputs["Color"])
    else:
        d.inputs["Color"].default_value = (0.6, 0.6, 0.6, 1)
    me.materials.append(mat)


def container(c, coll, root):
    v = c["vertices"]
    t = c["triangles"]
    me = bpy.data.meshes.new(c["name"])
    me.from_pydata([v[i:i + 3] for i in range(0, len(v), 3)], [], [t[i:i + 3] for i in range(0, len(t), 3)])
    me.validate()
    me.use_auto_smooth = True
    me.auto_smooth_angle = math.radians(30)
    me.polygons.foreach_set("use_smooth", [True] * len(me.polygons))
    me.materials.append(make_material(c["name"], c["material"]))
    obj = link(bpy.data.objects.new(c["name"], me), coll, root)
    obj.hide_render = not c["material"]["visible"]
    return obj


def main():
    manifest_path, out_path = args()
    with open(manifest_path) as fh:
        man = json.load(fh)
    if man.get("format") != "multifluid blender manifest 1":
        raise RuntimeError(manifest_path + ": not a multifluid manifest")
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.name = man["scene"]
    scene.render.engine = "CYCLES"
    scene.cycles.samples = man["image"]["samples"]
    scene.cycles.max_bounces = man["image"]["max_depth"]
    scene.cycles.transmission_bounces = man["image"]["max_depth"]
    scene.cycles.volume_bounces = 4
    # Debian's Blender is built without OpenImageDenoise, and the default would fail every render.
    scene.cycles.use_denoising = False
    scene.cycles.use_preview_denoising = False
    scene.render.resolution_x = man["image"]["width"]
    scene.render.resolution_y = man["image"]["height"]
    scene.render.resolution_percentage = 100
    # Frame rate as fps / fps_base (Blender keeps an integer fps).
    rate = man["fps"]
    scene.render.fps = max(1, round(rate))
    scene.render.fps_base = scene.render.fps / rate
    scene.frame_start, scene.frame_end = man["frame_start"], man["frame_end"]
    # render.shutter: open for that fraction of a frame, centred on it, as the renderer's.
    scene.render.use_motion_blur = man["shutter"] > 0
    if man["shutter"] > 0:
        scene.render.motion_blur_shutter = man["shutter"]
        scene.cycles.motion_blur_position = "CENTER"
    scene.frame_current = man["frame_start"]
    scene.unit_settings.system = "METRIC"

    coll = bpy.data.collections.new("multifluid")
    scene.collection.children.link(coll)
    root = bpy.data.objects.new("multifluid_y_up", None)
    coll.objects.link(root)
    root.rotation_euler = (math.pi / 2, 0, 0)  # the scene's y up to Blender's z up
    root["multifluid_run_folder"] = man["run_folder"]

    for f in man["fluids"]:
        mat = make_material(f["name"], f["material"])
        if man["meshes"] == "ply":
            for obj in fluid_from_ply(f, man, coll, root):
                obj.data.materials.clear()
                obj.data.materials.append(mat)
        else:
            fluid_from_vdb(f, man, coll, root).data.materials.append(mat)
        for key in ("emission", "absorption"):
            ramp_volume(f, man, coll, root, key)
    for c in man["containers"]:
        container(c, coll, root)
    camera(man, coll, root)
    light(man, coll, root)
    floor(man, coll, root)
    world(man)

    scene.frame_set(man["frame_start"])
    bpy.ops.wm.save_as_mainfile(filepath=out_path, relative_remap=True, compress=False)
    print("build_blend: wrote", out_path)


main()
