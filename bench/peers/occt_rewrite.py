# Peer for bench/all.sh (the export row), run by freecadcmd: Open CASCADE writes the same surfaces
# again. Reads surfkit's STEP or IGES (SK_IN) with Part.read (OCCT's reader, untimed), then times
# Open CASCADE's own writer of that shape in the same format (Shape.exportStep / exportIges, which
# call STEPControl_Writer / IGESControl_Writer) into SK_REWRITE; writes JSON to SK_OUT: faces,
# write CPU and wall seconds, bytes.
import json
import os
import time

import Part

src, dst, out = os.environ["SK_IN"], os.environ["SK_REWRITE"], os.environ["SK_OUT"]
shape = Part.read(src)
t0, c0 = time.time(), time.process_time()
if dst.lower().endswith((".igs", ".iges")):
    shape.exportIges(dst)
else:
    shape.exportStep(dst)
seconds, cpu = time.time() - t0, time.process_time() - c0
with open(out, "w") as f:
    json.dump({"faces": len(shape.Faces), "seconds": seconds, "cpu_seconds": cpu,
               "bytes": os.path.getsize(dst)}, f)
