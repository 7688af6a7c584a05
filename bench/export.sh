#!/usr/bin/env bash
# CAD export of the VC1 surface.
# 1. Size and speed (sphere, nefertiti, cow, bunny00 x STEP, IGES): file size, size per input
#    triangle, the writer alone (bench_export: best of 3, CPU seconds of the writing thread and
#    wall seconds; MB/s by CPU time, as the machine is shared), and FreeCAD opening the file with
#    its default importer (tests/interop/freecad_open.py: CPU seconds, shape, faces, isValid).
# 2. Open CASCADE reads the files back (occt_check) on the closed even-vertex meshes and the disks
#    of ../shared/data/meshes: faces written, file sizes, worst deviation between Open CASCADE's
#    and surfkit's evaluation (relative to the model size), worst normal jump across shared STEP
#    edges measured on Open CASCADE's surfaces.
# Usage: bench/export.sh [BUILD_DIR] [--no-freecad] [--no-occt]
set -u
cd "$(dirname "$0")/.."
build=build freecad=1 occt=1
for a in "$@"; do
  case $a in --no-freecad) freecad=0;; --no-occt) occt=0;; *) build=$a;; esac
done
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2 --target bench_export >/dev/null || exit 1
out="$build/bench-export"; mkdir -p "$out"
m=../shared/data/meshes
export OMP_WAIT_POLICY=passive # idle OpenMP threads of the surface build must not spin meanwhile
command -v freecadcmd >/dev/null || freecad=0
echo "| mesh       | fmt  | triangles |   faces |       KB | KB/tri | write CPU s | write wall s | MB/s (CPU) | FreeCAD CPU s | FreeCAD result |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
for mesh in sphere nefertiti cow bunny00; do
  "$build/bench/bench_export" "$m/$mesh.off" "$out" 3 | while IFS='|' read -r _ name fmt tris faces kb kbt cpu wall mbs _; do
    f="$out/$(echo $name).$(echo $fmt)"
    fc="-" res="-"
    if [ $freecad = 1 ]; then
      HOME="$out/home" SK_IN=$f SK_OUT=$f.json timeout 1800 freecadcmd tests/interop/freecad_open.py >"$f.fc.log" 2>&1
      read -r fc res < <(python3 -c '
import json, sys
try:
    r = json.load(open(sys.argv[1]))
    print("%.2f" % r["cpu_seconds"], "/".join(r["types"]) + ",%d,%s" % (r["faces"], "valid" if r["valid"] else "INVALID"))
except Exception:
    print("-", "crashed")' "$f.json")
    fi
    printf '|%s|%s|%s|%s|%s|%s|%s|%s|%s| %13s | %s |\n' "$name" "$fmt" "$tris" "$faces" "$kb" "$kbt" "$cpu" "$wall" "$mbs" "$fc" "$res"
  done
done
[ $occt = 1 ] || exit 0
cmake --build "$build" -j2 --target occt_check >/dev/null || { echo "occt_check needs Open CASCADE (scripts/setup.sh)"; exit 1; }
echo
echo "| mesh               | file             |  faces |       KiB | deviation  | normal jump   | STEP edges   | result |"
echo "|---|---|---|---|---|---|---|---|"
# bunny00, armadillo and lion-head (60k+ patches) give STEP files of 100+ MB: the table covers the
# meshes up to about 6k triangles.
for mesh in icosahedron sphere cube cow knot1 nefertiti paraboloid-patch patch-01 three_peaks mushroom; do
  closed=""; case $mesh in icosahedron|sphere|cube|cow|knot1) closed=--closed;; esac
  "$build/tests/occt_check" "$out" "$m/$mesh.off" $closed --max-jump 1e-6 | grep -v "^\*\*\*\|loaded entities\|^.\[0m$"
done
