# Run by `blender -b --factory-startup --python blender_check.py -- MODE ARGS`:
#   import OBJ|PLY OUT.json : imports surfkit's file with Blender's own importer and writes the UV
#                             of every face corner, in Blender's face order, with the vertex count
#   export DIR              : exports Blender's default cube and a monkey as OBJ (with UVs, so
#                             with seams), PLY (with UVs) and STL, and writes their counts as JSON
import json
import sys

import bpy

args = sys.argv[sys.argv.index("--") + 1:]
mode = args[0]


def clear():
    bpy.ops.object.select_all(action="SELECT")
    bpy.ops.object.delete()


if mode == "import":
    path, out = args[1], args[2]
    clear()
    if path.endswith(".obj"):
        bpy.ops.wm.obj_import(filepath=path)
    else:
        bpy.ops.import_mesh.ply(filepath=path)
    obj = [o for o in bpy.context.scene.objects if o.type == "MESH"][0]
    me = obj.data
    res = {"vertices": len(me.vertices), "faces": len(me.polygons), "uv_layers": len(me.uv_layers),
           "faces_uv": []}
    if me.uv_layers:
        uv = me.uv_layers.active.data
        res["faces_uv"] = [[[uv[li].uv[0], uv[li].uv[1]] for li in p.loop_indices]
                           for p in me.polygons]
        # corners' vertex positions, to match faces whatever order the importer keeps
        res["faces_xyz"] = [[list(me.vertices[me.loops[li].vertex_index].co) for li in p.loop_indices]
                            for p in me.polygons]
    with open(out, "w") as f:
        json.dump(res, f)
elif mode == "export":
    d = args[1]
    clear()
    bpy.ops.mesh.primitive_cube_add()
    cube = bpy.context.active_object
    cube.name = "cube"
    bpy.ops.mesh.primitive_monkey_add(location=(3, 0, 0))
    monkey = bpy.context.active_object
    monkey.name = "monkey"
    counts = {}
    for o in (cube, monkey):
        bpy.ops.object.select_all(action="DESELECT")
        o.select_set(True)
        bpy.context.view_layer.objects.active = o
        me = o.data
        uvs = {(round(d.uv[0], 6), round(d.uv[1], 6)) for d in me.uv_layers.active.data}
        counts[o.name] = {"vertices": len(me.vertices), "faces": len(me.polygons),
                          "triangles": sum(len(p.vertices) - 2 for p in me.polygons),
                          "distinct_uvs": len(uvs)}
        base = d + "/" + o.name
        bpy.ops.wm.obj_export(filepath=base + ".obj", export_selected_objects=True, export_uv=True,
                              export_normals=True, export_materials=False)
        bpy.ops.export_mesh.ply(filepath=base + ".ply", use_selection=True, use_uv_coords=True)
        bpy.ops.export_mesh.stl(filepath=base + ".stl", use_selection=True)
    with open(d + "/counts.json", "w") as f:
        json.dump(counts, f)
