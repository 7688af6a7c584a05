# Run by freecadcmd: opens one STEP or IGES file with FreeCAD's default importer (Import.insert,
# the one behind File > Import) and writes what it got as JSON. Environment: SK_IN, SK_OUT.
import json
import os
import time

import FreeCAD
import Import

path, out = os.environ["SK_IN"], os.environ["SK_OUT"]
doc = FreeCAD.newDocument("interop")
t0 = time.time()
Import.insert(path, doc.Name)
seconds = time.time() - t0
shapes = [o.Shape for o in doc.Objects if hasattr(o, "Shape") and not o.Shape.isNull()]
res = {
    "objects": len(shapes),
    "faces": sum(len(s.Faces) for s in shapes),
    "solids": sum(len(s.Solids) for s in shapes),
    "shells": sum(len(s.Shells) for s in shapes),
    "types": [s.ShapeType for s in shapes],
    "valid": all(s.isValid() for s in shapes) and len(shapes) > 0,
    "closed_solids": all(so.isClosed() for s in shapes for so in s.Solids),
    "seconds": seconds,
}
with open(out, "w") as f:
    json.dump(res, f)
