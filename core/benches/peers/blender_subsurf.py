# Times Blender's Subdivision Surface modifier (OpenSubdiv on the CPU) on an OBJ cage, for the
# subdivision benchmark (`core/benches/subdiv.rs`), which runs it as
#   blender -b --factory-startup --python blender_subsurf.py -- CAGE.obj LEVELS REPEATS
# and reads the last line it prints: JSON with the shortest wall times in milliseconds of
#   fresh: the modifier added to the cage and the scene evaluated (topology, refinement and the
#          evaluated mesh: what a topology edit costs);
#   moved: one cage vertex moved and the scene evaluated again (what a drag step costs);
# and the evaluated mesh's vertex and face counts, so the caller checks it did the same work.
import json
import sys
import time

import bpy

args = sys.argv[sys.argv.index("--") + 1:]
path, levels, repeats = args[0], int(args[1]), int(args[2])

# An empty scene with just the cage, read as OBJ with its vertex order kept.
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.wm.obj_import(filepath=path, forward_axis="Y", up_axis="Z")
obj = bpy.context.selected_objects[0]
bpy.context.view_layer.objects.active = obj
layer = bpy.context.view_layer


def evaluated_counts():
    depsgraph = bpy.context.evaluated_depsgraph_get()
    mesh = obj.evaluated_get(depsgraph).data
    return len(mesh.vertices), len(mesh.polygons)


def add_modifier():
    m = obj.modifiers.new("subsurf", "SUBSURF")
    m.subdivision_type = "CATMULL_CLARK"
    m.levels = levels
    m.render_levels = levels
    m.quality = 3
    m.uv_smooth = "NONE"
    return m


fresh = []
for _ in range(repeats):
    for m in list(obj.modifiers):
        obj.modifiers.remove(m)
    layer.update()
    t = time.perf_counter()
    add_modifier()
    layer.update()
    fresh.append(time.perf_counter() - t)

counts = evaluated_counts()
moved = []
co = obj.data.vertices[0].co
for k in range(repeats):
    obj.data.vertices[0].co.z += 1e-3 if k % 2 == 0 else -1e-3
    obj.data.update()
    t = time.perf_counter()
    layer.update()
    moved.append(time.perf_counter() - t)

print(json.dumps({
    "fresh_ms": 1e3 * min(fresh),
    "moved_ms": 1e3 * min(moved),
    "vertices": counts[0],
    "faces": counts[1],
    "blender": bpy.app.version_string,
}))
