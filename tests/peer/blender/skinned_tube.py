"""A skinned, animated tube exported by Blender's own glTF exporter, and
where Blender's armature deform (linear blend skinning) puts its vertices.

Makes fixtures/mesh/skinned_tube.glb and fixtures/mesh/skinned_tube.poses.json,
which tests/mesh/skin.rs compares holo's skinning with. Run with Blender
(Debian's blender 3.4.1 made the committed files):

    blender -b --factory-startup --python tests/peer/blender/skinned_tube.py -- \
        fixtures/mesh/skinned_tube.glb fixtures/mesh/skinned_tube.poses.json
"""

import json
import math
import sys

import bmesh
import bpy

out_glb, out_json = sys.argv[sys.argv.index("--") + 1:]

bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
scene.render.fps = 24
scene.frame_start, scene.frame_end = 1, 25

# A tube 2 m long along +Z, 12 sides, cut into 8 rings of faces.
bpy.ops.mesh.primitive_cylinder_add(vertices=12, radius=0.2, depth=2.0, location=(0, 0, 1))
tube = bpy.context.active_object
tube.name = "tube"
bm = bmesh.new()
bm.from_mesh(tube.data)
long_edges = [e for e in bm.edges if abs(e.verts[0].co.z - e.verts[1].co.z) > 1e-6]
bmesh.ops.subdivide_edges(bm, edges=long_edges, cuts=7, use_grid_fill=True)
bm.to_mesh(tube.data)
bm.free()

# Three bones up the tube, the tube bound to them with automatic weights
# (each vertex weighted by up to several bones).
bpy.ops.object.armature_add(enter_editmode=True, location=(0, 0, 0))
armature = bpy.context.active_object
armature.name = "rig"
bones = armature.data.edit_bones
root = bones[0]
root.name, root.head, root.tail = "root", (0, 0, 0), (0, 0, 0.7)
mid = bones.new("mid")
mid.head, mid.tail, mid.parent, mid.use_connect = (0, 0, 0.7), (0, 0, 1.4), root, True
tip = bones.new("tip")
tip.head, tip.tail, tip.parent, tip.use_connect = (0, 0, 1.4), (0, 0, 2.0), mid, True
bpy.ops.object.mode_set(mode="OBJECT")
bpy.ops.object.select_all(action="DESELECT")
tube.select_set(True)
armature.select_set(True)
bpy.context.view_layer.objects.active = armature
bpy.ops.object.parent_set(type="ARMATURE_AUTO")

# Bend it: the middle and tip bones turn about X and Y over 25 frames.
for frame, mid_deg, tip_deg in [(1, (0, 0), (0, 0)), (13, (35, 10), (-20, 0)), (25, (-30, -15), (45, 20))]:
    for name, (ax, ay) in [("mid", mid_deg), ("tip", tip_deg)]:
        bone = armature.pose.bones[name]
        bone.rotation_mode = "XYZ"
        bone.rotation_euler = (math.radians(ax), math.radians(ay), 0.0)
        bone.keyframe_insert(data_path="rotation_euler", frame=frame)

bpy.ops.export_scene.gltf(
    filepath=out_glb, export_format="GLB", export_animations=True, export_skins=True, export_apply=False
)

# Where Blender's own deform puts each vertex, in glTF's axes (Blender's
# Z up, glTF's Y up: (x, y, z) -> (x, z, -y)).
poses = {"blender": bpy.app.version_string, "fps": 24, "frame_start": 1, "frames": []}
for frame in (1, 7, 13, 19, 25):
    scene.frame_set(frame)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = tube.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    world = evaluated.matrix_world
    points = []
    for v in mesh.vertices:
        p = world @ v.co
        points.append([p.x, p.z, -p.y])
    poses["frames"].append({"frame": frame, "positions": points})
    evaluated.to_mesh_clear()
with open(out_json, "w") as f:
    json.dump(poses, f, indent=0)
