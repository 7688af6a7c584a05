#!/usr/bin/env bash
# STEP and IGES of the VC1 surfaces in FreeCAD 0.20: for each surfkit binary given (e.g. an old
# build and the current one), mesh and format: file size, CPU seconds to write (smooth -o FILE
# minus smooth alone, one thread), and what FreeCAD's default importer (Import.insert) and, for
# IGES, its legacy reader (Part.read) get, with their CPU and wall seconds. Needs freecadcmd
# (scripts/setup.sh --interop). Usage: bench/interop.sh [SURFKIT...]   (default build/surfkit)
set -u
here=$(cd "$(dirname "$0")/.." && pwd)
bins=("$@"); [ ${#bins[@]} -gt 0 ] || bins=("$here/build/surfkit")
meshes=${SK_BENCH_MESHES:-cube sphere nefertiti cow}
m=$here/../shared/data/meshes tmp=$(mktemp -d)
export HOME=$tmp OMP_NUM_THREADS=1
cpu() { /usr/bin/time -f "%U %S" "$@" 2>&1 >/dev/null | tail -1 | awk '{print $1 + $2}'; }
printf '| %-7s | %-8s | %-9s | %-4s | %-13s | %-34s | %9s | %7s | %15s |\n' build client mesh fmt reader result KiB write_s "open cpu/wall s"
for b in "${bins[@]}"; do
  label=$(basename "$(dirname "$(dirname "$(readlink -f "$b")")")")
  for mesh in $meshes; do
    base=$(cpu "$b" smooth "$m/$mesh.off" --json -q)
    for ext in step igs; do
      f=$tmp/$mesh.$ext
      tot=$(cpu "$b" smooth "$m/$mesh.off" -o "$f" -q)
      w=$(echo "$tot $base" | awk '{printf "%.2f", $1 - $2}')
      readers="insert"; [ $ext = igs ] && readers="insert part"
      for r in $readers; do
        rm -f "$tmp/r.json"
        { SK_IN=$f SK_OUT=$tmp/r.json SK_READER=$r timeout 600 freecadcmd \
          "$here/tests/interop/freecad_open.py" > "$tmp/fc.log" 2>&1; } 2>/dev/null
        python3 - "$tmp/r.json" "$f" "$label" "$mesh" "$ext" "$r" "$w" "$tmp/fc.log" <<'PY'
import json, os, sys
res, f, label, mesh, ext, reader, w, log = sys.argv[1:]
try:
    r = json.load(open(res))
    result = "%s, %d faces, %s" % ("/".join(sorted(set(r["types"]))) or "nothing", r["faces"],
                                   "valid" if r["valid"] else "INVALID")
    t = "%.2f/%.2f" % (r["cpu_seconds"], r["seconds"])
except (OSError, ValueError):
    crashed = "SIGSEGV" in open(log, errors="replace").read()
    result, t = ("segfault" if crashed else "no result"), "-"
print("| %-7s | %-8s | %-9s | %-4s | %-13s | %-34s | %9.1f | %7s | %15s |" % (
    label[:7], "FreeCAD", mesh, ext, "Import.insert" if reader == "insert" else "Part.read",
    result, os.path.getsize(f) / 1024, w, t))
PY
      done
    done
  done
done
rm -rf "$tmp"
