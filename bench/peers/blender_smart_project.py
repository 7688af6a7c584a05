# Blender peer for bench/atlas.sh: import an OBJ, Smart UV Project (its defaults: angle limit 66
# degrees, island margin 0), Pack Islands (rotation on, margin = the gutter), export the OBJ with
# its uvs, print the seconds of unwrap + pack. Run: blender -b -P this.py -- IN.obj OUT.obj MARGIN
import sys
import time

import bpy

argv = sys.argv[sys.argv.index("--") + 1:]
src, dst, margin = argv[0], argv[1], float(argv[2])
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.wm.obj_import(filepath=src)
obj = bpy.context.selected_objects[0]
bpy.context.view_layer.objects.active = obj
bpy.ops.object.mode_set(mode="EDIT")
bpy.ops.mesh.select_all(action="SELECT")
t0 = time.perf_counter()
bpy.ops.uv.smart_project()
bpy.ops.uv.select_all(action="SELECT")
bpy.ops.uv.pack_islands(rotate=True, margin=margin)
t1 = time.perf_counter()
bpy.ops.object.mode_set(mode="OBJECT")
bpy.ops.wm.obj_export(filepath=dst, export_selected_objects=True, export_uv=True,
                      export_normals=False, export_materials=False, export_triangulated_mesh=True,
                      apply_modifiers=False, forward_axis="Y", up_axis="Z")
print("BLENDER_SECONDS %.6f" % (t1 - t0))
