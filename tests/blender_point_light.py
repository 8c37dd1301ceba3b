# The measurement behind the light translation in docs/pipeline.md (by hand, not in CTest):
#   blender -b --factory-startup -P tests/blender_point_light.py
# A point light of radius r and power 4 pi^2 r^2 L (what build_blend.py gives the renderer's
# spherical light of radiance L) over a white diffuse plane at distance d, no sky, direct light
# only: prints the plane's radiance against a sphere's L (r/d)^2 and a facing disk's
# L r^2 / (r^2 + d^2).
import math

import bpy

L, r, d = 5.0, 0.5, 2.0
bpy.ops.wm.read_factory_settings(use_empty=True)
s = bpy.context.scene
s.render.engine = "CYCLES"
s.cycles.samples = 64
s.cycles.use_denoising = False
s.cycles.max_bounces = 0
s.render.resolution_x = s.render.resolution_y = 16
s.view_settings.view_transform = "Standard"
w = bpy.data.worlds.new("black")
s.world = w
w.use_nodes = True
w.node_tree.nodes["Background"].inputs["Strength"].default_value = 0
lamp = bpy.data.lights.new("light", "POINT")
lamp.shadow_soft_size = r
lamp.energy = 4 * math.pi ** 2 * r * r * L
lo = bpy.data.objects.new("light", lamp)
s.collection.objects.link(lo)
lo.location = (0, 0, d)
me = bpy.data.meshes.new("plane")
me.from_pydata([(-50, -50, 0), (50, -50, 0), (50, 50, 0), (-50, 50, 0)], [], [(0, 1, 2, 3)])
mat = bpy.data.materials.new("white")
mat.use_nodes = True
nt = mat.node_tree
nt.nodes.remove(nt.nodes["Principled BSDF"])
diffuse = nt.nodes.new("ShaderNodeBsdfDiffuse")
diffuse.inputs["Color"].default_value = (1, 1, 1, 1)
nt.links.new(diffuse.outputs[0], nt.nodes["Material Output"].inputs["Surface"])
me.materials.append(mat)
s.collection.objects.link(bpy.data.objects.new("plane", me))
cam = bpy.data.cameras.new("camera")
cam.angle = math.radians(2)  # looks straight down through the light at the plane below it
co = bpy.data.objects.new("camera", cam)
s.collection.objects.link(co)
co.location = (0, 0, 5)
s.camera = co
s.render.image_settings.file_format = "OPEN_EXR"
s.render.filepath = "/tmp/blender_point_light.exr"
bpy.ops.render.render(write_still=True)
px = bpy.data.images.load(s.render.filepath).pixels[:]
n = len(px) // 4
print("point light: plane radiance %.4f; a sphere would give %.4f, a facing disk %.4f" %
      (sum(px[4 * k] for k in range(n)) / n, L * (r / d) ** 2, L * r * r / (r * r + d * d)))
