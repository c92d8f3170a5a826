"""Renders draped garments side by side with Blender (the picture in docs/garments.md).

    blender -b -P bench/render_garments.py -- OUT.png DIR [DIR...]

Each DIR is a scenario's output (its cloth.obj and body.obj, metres, Y up, facing +Z);
the figures stand side by side, seen from the front (orthographic), the floor to 1.9 m.
Cycles on the CPU, 32 samples, 250 pixels for every 0.95 m. Needs Debian's `blender` package; not part of `cargo test`.
"""

import math
import sys

import bpy
from mathutils import Vector

argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
if len(argv) < 2:
    sys.exit("usage: blender -b -P bench/render_garments.py -- OUT.png DIR [DIR...]")
out, dirs = argv[0], argv[1:]

bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene


def material(name, rgb, roughness):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    bsdf = m.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*rgb, 1.0)
    bsdf.inputs["Roughness"].default_value = roughness
    return m


body_mat = material("body", (0.55, 0.55, 0.55), 0.5)
cloth_mat = material("cloth", (0.55, 0.16, 0.09), 0.9)


def load(path, mat, dx):
    before = set(bpy.data.objects)
    bpy.ops.import_scene.obj(filepath=path, axis_forward="-Z", axis_up="Y")
    for ob in set(bpy.data.objects) - before:
        ob.location.x += dx
        ob.data.materials.clear()
        ob.data.materials.append(mat)
        for p in ob.data.polygons:
            p.use_smooth = True


def x_extent(path):
    xs = [float(l.split()[1]) for l in open(path) if l.startswith("v ")]
    return max(xs) - min(xs)


# Figures 15 cm apart at their widest (arms held out reach further).
spacing = max(0.95, max(x_extent(f"{d}/body.obj") for d in dirs) + 0.15)
for i, d in enumerate(dirs):
    load(f"{d}/body.obj", body_mat, i * spacing)
    load(f"{d}/cloth.obj", cloth_mat, i * spacing)

mid = 0.5 * (len(dirs) - 1) * spacing
cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
cam.data.type = "ORTHO"
# The floor to 1.9 m, every figure across; 250 pixels for every 0.95 m.
width, height = max(len(dirs), 2) * spacing, 1.9
cam.data.ortho_scale = max(width, height)
cam.location = Vector((mid, -6.0, 0.95))
cam.rotation_euler = (math.radians(90), 0, 0)
scene.collection.objects.link(cam)
scene.camera = cam
for name, rot, energy in (("key", (50, 10, -30), 3.0), ("fill", (70, 0, 40), 1.0)):
    light = bpy.data.objects.new(name, bpy.data.lights.new(name, "SUN"))
    light.data.energy = energy
    light.rotation_euler = tuple(math.radians(a) for a in rot)
    scene.collection.objects.link(light)
world = bpy.data.worlds.new("world")
world.use_nodes = True
world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
scene.world = world
scene.render.engine = "CYCLES"
scene.cycles.samples = 32
scene.cycles.device = "CPU"
scene.cycles.use_denoising = False
scene.render.resolution_x = round(250 * width / 0.95)
scene.render.resolution_y = round(250 * height / 0.95)
scene.render.filepath = out
bpy.ops.render.render(write_still=True)
