"""Blender's cloth on the scene `cloth-sim scenario` builds, for the side-by-side in
bench/side-by-side. Runs inside Blender:

    blender -b --factory-startup -P bench/blender_cloth.py -- \
        --body DIR/body.obj --grid 64 --frames 300 --out DIR/blender [--no-self-collision]

The scene: the body from the OBJ (metres, Y up, as cloth-sim writes it), a square cloth
of `--size` m with `--grid` cells a side, centred over the body with its lowest point
5 cm above the body's top, Blender's Cotton preset at quality 5, self collision on,
collision distances equal to our contact thickness, 60 frames a second, 2 threads.
Writes DIR/blender/cloth.obj (Y up, triangles, the same axes as ours) and
DIR/blender/timing.json (seconds per frame).
"""

import argparse
import json
import os
import sys
import time

import bpy
from mathutils import Vector


def args():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="blender_cloth.py")
    p.add_argument("--body", required=True, help="body OBJ (Y up, metres)")
    p.add_argument("--grid", type=int, default=64)
    p.add_argument("--size", type=float, default=1.0)
    p.add_argument("--frames", type=int, default=300)
    p.add_argument("--thickness", type=float, default=0.004)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--quality", type=int, default=5)
    p.add_argument("--no-self-collision", action="store_true")
    p.add_argument("--out", required=True)
    return p.parse_args(argv)


def read_obj(path):
    """Vertices (converted to Blender's Z up) and triangles of a Y-up OBJ."""
    verts, faces = [], []
    with open(path) as f:
        for line in f:
            s = line.split()
            if not s:
                continue
            if s[0] == "v":
                x, y, z = map(float, s[1:4])
                verts.append((x, -z, y))
            elif s[0] == "f":
                idx = [int(t.split("/")[0]) for t in s[1:]]
                idx = [i - 1 if i > 0 else len(verts) + i for i in idx]
                for k in range(1, len(idx) - 1):
                    faces.append((idx[0], idx[k], idx[k + 1]))
    return verts, faces


def mesh_object(name, verts, faces):
    me = bpy.data.meshes.new(name)
    me.from_pydata(verts, [], faces)
    me.update()
    ob = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(ob)
    return ob


def cotton(cloth, a):
    """Blender's Cotton preset (presets/cloth/Cotton.py), at the asked quality."""
    s = cloth.settings
    s.quality = a.quality
    s.mass = 0.3
    s.tension_stiffness = 15
    s.compression_stiffness = 15
    s.shear_stiffness = 15
    s.bending_stiffness = 0.5
    s.tension_damping = 5
    s.compression_damping = 5
    s.shear_damping = 5
    s.air_damping = 1
    c = cloth.collision_settings
    c.use_collision = True
    c.distance_min = a.thickness
    c.use_self_collision = not a.no_self_collision
    c.self_distance_min = a.thickness


def main():
    a = args()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.fps = 60
    scene.render.threads_mode = "FIXED"
    scene.render.threads = a.threads
    scene.frame_start = 1
    scene.frame_end = a.frames + 1

    bv, bf = read_obj(a.body)
    body = mesh_object("body", bv, bf)
    col = body.modifiers.new("Collision", "COLLISION")
    del col
    body.collision.thickness_outer = a.thickness
    lo = Vector([min(v[i] for v in bv) for i in range(3)])
    hi = Vector([max(v[i] for v in bv) for i in range(3)])
    cx, cy, top = (lo.x + hi.x) / 2, (lo.y + hi.y) / 2, hi.z

    n = a.grid
    verts = [
        (cx + (i / n - 0.5) * a.size, cy + (j / n - 0.5) * a.size, top + 0.05)
        for j in range(n + 1)
        for i in range(n + 1)
    ]
    faces = [
        (j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i + 1, (j + 1) * (n + 1) + i)
        for j in range(n)
        for i in range(n)
    ]
    cloth_ob = mesh_object("cloth", verts, faces)
    cloth = cloth_ob.modifiers.new("Cloth", "CLOTH")
    cotton(cloth, a)
    cloth.point_cache.frame_start = 1
    cloth.point_cache.frame_end = a.frames + 1

    per_frame = []
    scene.frame_set(1)
    for f in range(2, a.frames + 2):
        t0 = time.perf_counter()
        scene.frame_set(f)
        per_frame.append(time.perf_counter() - t0)
        if (f - 1) % 50 == 0:
            print(f"blender: frame {f - 1}/{a.frames}", flush=True)

    os.makedirs(a.out, exist_ok=True)
    dg = bpy.context.evaluated_depsgraph_get()
    ev = cloth_ob.evaluated_get(dg)
    me = ev.to_mesh()
    mw = cloth_ob.matrix_world
    with open(os.path.join(a.out, "cloth.obj"), "w") as f:
        f.write("# Blender cloth, Y up\n")
        for v in me.vertices:
            p = mw @ v.co
            f.write(f"v {p.x:.6f} {p.z:.6f} {-p.y:.6f}\n")
        for poly in me.polygons:
            idx = list(poly.vertices)
            for k in range(1, len(idx) - 1):
                f.write(f"f {idx[0] + 1} {idx[k] + 1} {idx[k + 1] + 1}\n")
    ev.to_mesh_clear()
    with open(os.path.join(a.out, "timing.json"), "w") as f:
        json.dump(
            {
                "blender": bpy.app.version_string,
                "grid": n,
                "frames": a.frames,
                "quality": a.quality,
                "self_collision": not a.no_self_collision,
                "threads": a.threads,
                "frame_s": per_frame,
            },
            f,
        )


main()
