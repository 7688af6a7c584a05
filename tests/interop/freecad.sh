#!/usr/bin/env bash
# FreeCAD (freecadcmd, its default importers Import.insert) opens surfkit's STEP and IGES of the
# VC1 surfaces: no crash, the face count surfkit wrote, a valid shape, one closed solid for a
# closed mesh (cube, sphere, the genus-2 eight) and one shell, no solid, for an open one (the disk
# nefertiti, pig with 7 holes). Prints a table row per file. Skips (77) when
# FreeCAD is not installed (scripts/setup.sh --interop installs it).
set -u
bin=$1 src=$2 shared=$3 tmp=$4
command -v freecadcmd >/dev/null || { echo "SKIP: freecadcmd not installed (scripts/setup.sh --interop)"; exit 77; }
rm -rf "$tmp"; mkdir -p "$tmp"
export HOME=$tmp/home; mkdir -p "$HOME" # FreeCAD writes its user config there
m=$shared/data/meshes fails=0
printf '| %-10s | %-4s | %6s | %9s | %7s | %7s | %-6s | %s\n' mesh fmt faces KiB smooth_s open_s shape result
# mesh:closed:smooth options (eight: genus 2, odd, so one edge split; pig: 7 boundary loops and
# singular patches (issue 12), so its report fails: --allow-fail writes the surface anyway; eight
# has 1 singular quad since the edge flips met the near-minimal deletion: 0 with --keep-triangulation)
for spec in cube:1 sphere:1 eight:1:--allow-split,--allow-fail nefertiti:0 pig:0:--allow-fail; do
  IFS=: read -r mesh closed opt <<< "$spec"; opt=${opt//,/ }
  for ext in step igs; do
    f=$tmp/$mesh.$ext
    t0=$(date +%s.%N)
    # shellcheck disable=SC2086
    "$bin" smooth "$m/$mesh.off" $opt -o "$f" > "$tmp/$mesh.$ext.log" 2>&1 || { echo "FAIL: surfkit smooth $mesh.$ext"; fails=1; continue; }
    t1=$(date +%s.%N)
    want=$(sed -n 's/.*wrote .*: \([0-9]*\) surfaces.*/\1/p' "$tmp/$mesh.$ext.log")
    SK_IN=$f SK_OUT=$tmp/$mesh.$ext.json timeout 300 freecadcmd "$src/tests/interop/freecad_open.py" \
      > "$tmp/$mesh.$ext.fc.log" 2>&1
    python3 - "$tmp/$mesh.$ext.json" "$want" "$closed" "$mesh" "$ext" "$f" "$t0" "$t1" <<'PY' || fails=1
import json, os, sys
res_path, want, closed, mesh, ext, f, t0, t1 = sys.argv[1:]
kib = os.path.getsize(f) / 1024
write = float(t1) - float(t0)
bad = []
try:
    r = json.load(open(res_path))
except (OSError, ValueError):
    r = None
    bad.append("FreeCAD crashed or wrote nothing (see %s.fc.log)" % f)
if r:
    if r["faces"] != int(want):
        bad.append("faces %d, surfkit wrote %s" % (r["faces"], want))
    if not r["valid"]:
        bad.append("invalid shape")
    if closed == "1" and (r["solids"] != 1 or not r["closed_solids"]):
        bad.append("closed mesh: %d solids, want 1 closed solid" % r["solids"])
    if closed == "0" and (r["solids"] != 0 or r["shells"] != 1):
        bad.append("open mesh: want one shell and no solid, got %d shells %d solids" % (r["shells"], r["solids"]))
shape = "/".join(r["types"]) if r else "-"
print("| %-10s | %-4s | %6s | %9.1f | %7.2f | %7s | %-6s | %s" % (
    mesh, ext, r["faces"] if r else "-", kib, write, "%.2f" % r["seconds"] if r else "-", shape,
    "ok" if not bad else "FAIL"))
for b in bad:
    print("    %s.%s: %s" % (mesh, ext, b))
sys.exit(1 if bad else 0)
PY
  done
done
exit $fails
