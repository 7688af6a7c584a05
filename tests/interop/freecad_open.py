# Run by freecadcmd: opens one STEP or IGES file with FreeCAD's default importer (Import.insert,
# the one behind File > Import), or with SK_READER=part the legacy reader (Part.read), and writes
# what it got as JSON. Environment: SK_IN, SK_OUT, SK_READER.
import json
import os
import time

import FreeCAD
import Import
import Part

path, out = os.environ["SK_IN"], os.environ["SK_OUT"]
t0, c0 = time.time(), time.process_time()
if os.environ.get("SK_READER") == "part":
    shapes = [Part.read(path)]
else:
    doc = FreeCAD.newDocument("interop")
    Import.insert(path, doc.Name)
    shapes = [o.Shape for o in doc.Objects if hasattr(o, "Shape") and not o.Shape.isNull()]
seconds, cpu = time.time() - t0, time.process_time() - c0
res = {
    "objects": len(shapes),
    "faces": sum(len(s.Faces) for s in shapes),
    "solids": sum(len(s.Solids) for s in shapes),
    "shells": sum(len(s.Shells) for s in shapes),
    "types": [s.ShapeType for s in shapes],
    "valid": all(s.isValid() for s in shapes) and len(shapes) > 0,
    "closed_solids": all(so.isClosed() for s in shapes for so in s.Solids),
    "seconds": seconds,
    "cpu_seconds": cpu,
}
with open(out, "w") as f:
    json.dump(res, f)
