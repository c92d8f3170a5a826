"""Makes sim-core/assets/human.obj from GarmentCode's average body, with Blender.

    git clone https://github.com/maria-korosteleva/GarmentCode
    blender -b -P bench/make_human_body.py -- GarmentCode/assets/bodies/mean_all.obj \
        sim-core/assets/human.obj

GarmentCode's `mean_all.obj` (MIT License, (c) 2024 Maria Korosteleva; the licence is in
sim-core/assets/LICENSE-GarmentCode) is 47,500 triangles in metres, Y up, facing +Z,
feet at 0, arms held out 45 degrees below the horizontal. This keeps a quarter of its
triangles (Blender's collapse decimation, symmetric in x), then smooths the few places
where the surface passes through itself (the lips and the crotch: 103 crossing pairs in
the original, 26 after decimation) until Blender's BVH finds none, and writes 0.1 mm
coordinates. `cloth-sim crossings sim-core/assets/human.obj` checks the result exactly.
Not part of `cargo test`.
"""

import sys

import bmesh
import bpy
from mathutils import Vector
from mathutils.bvhtree import BVHTree

argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
if len(argv) != 2:
    sys.exit("usage: blender -b -P bench/make_human_body.py -- mean_all.obj human.obj")
src, out = argv

bpy.ops.wm.read_factory_settings(use_empty=True)
verts, faces = [], []
for line in open(src):
    if line.startswith("v "):
        verts.append(tuple(float(x) for x in line.split()[1:4]))
    elif line.startswith("f "):
        faces.append(tuple(int(t.split("/")[0]) - 1 for t in line.split()[1:]))
mesh = bpy.data.meshes.new("body")
mesh.from_pydata(verts, [], faces)
mesh.update()
obj = bpy.data.objects.new("body", mesh)
bpy.context.scene.collection.objects.link(obj)
bpy.context.view_layer.objects.active = obj
dec = obj.modifiers.new("decimate", "DECIMATE")
dec.decimate_type = "COLLAPSE"
dec.ratio = 0.25
dec.use_symmetry = True
dec.symmetry_axis = "X"
bpy.ops.object.modifier_apply(modifier="decimate")

bm = bmesh.new()
bm.from_mesh(obj.data)
bmesh.ops.triangulate(bm, faces=bm.faces[:])
bm.verts.index_update()
if any(not e.is_manifold for e in bm.edges):
    sys.exit("decimation left a non-manifold edge")
V = [v.co.copy() for v in bm.verts]
F = [tuple(v.index for v in f.verts) for f in bm.faces]

ring = [set() for _ in V]
for f in F:
    for i in f:
        ring[i].update(f)
for i, r in enumerate(ring):
    r.discard(i)


def crossing():
    tree = BVHTree.FromPolygons(V, F, epsilon=0.0)
    return [(a, b) for a, b in tree.overlap(tree) if a < b and not set(F[a]) & set(F[b])]


for _ in range(20):
    pairs = crossing()
    print(f"{len(pairs)} crossing pairs")
    if not pairs:
        break
    near = {i for a, b in pairs for i in F[a] + F[b]}
    for _ in range(2):
        near |= {j for i in near for j in ring[i]}
    for _ in range(3):
        moved = {i: V[i] * 0.5 + sum((V[j] for j in ring[i]), Vector()) / len(ring[i]) * 0.5 for i in near}
        for i, p in moved.items():
            V[i] = p
else:
    sys.exit("the surface still crosses itself")

with open(out, "w") as f:
    f.write(
        "# Saiho's `human` body: GarmentCode's average body (assets/bodies/mean_all.obj,\n"
        "# MIT License, (c) 2024 Maria Korosteleva; see LICENSE-GarmentCode), decimated to\n"
        f"# {len(F)} triangles by bench/make_human_body.py. Metres, Y up, facing +Z.\n"
    )
    for p in V:
        f.write("v %.4f %.4f %.4f\n" % tuple(p))
    for t in F:
        f.write("f %d %d %d\n" % tuple(i + 1 for i in t))
print(f"wrote {out}: {len(V)} vertices, {len(F)} triangles")
