#!/usr/bin/env bash
# CAD export of the VC1 surface, verified by Open CASCADE, on the closed even-vertex meshes and the
# disks of ../shared/data/meshes: faces written, file sizes, worst deviation between Open CASCADE's
# and surfkit's evaluation (relative to the model size), worst normal jump across shared STEP
# edges measured on Open CASCADE's surfaces.
# Usage: bench/export.sh [BUILD_DIR]
set -u
cd "$(dirname "$0")/.."
build=${1:-build}
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2 --target occt_check >/dev/null || { echo "occt_check needs Open CASCADE (scripts/setup.sh)"; exit 1; }
out="$build/bench-export"; mkdir -p "$out"
m=../shared/data/meshes
echo "| mesh               | file             |  faces |       KiB | deviation  | normal jump   | STEP edges   | result |"
echo "|---|---|---|---|---|---|---|---|"
# bunny00, armadillo and lion-head (60k+ patches) would give STEP files of hundreds of MB (about
# 4 KB per face): the table covers the meshes up to about 6k triangles.
for mesh in icosahedron sphere cube cow knot1 nefertiti paraboloid-patch patch-01 three_peaks mushroom; do
  closed=""; case $mesh in icosahedron|sphere|cube|cow|knot1) closed=--closed;; esac
  "$build/tests/occt_check" "$out" "$m/$mesh.off" $closed --max-jump 1e-6 | grep -v "^\*\*\*\|loaded entities\|^.\[0m$"
done
