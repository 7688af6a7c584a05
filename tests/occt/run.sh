#!/usr/bin/env bash
# Export verification with Open CASCADE.
# 1. Flat patch networks (exact shared boundaries): a planar mesh of triangles and quads (normal
#    jump 0 everywhere), and closed meshes (closed STEP shell).
# 2. The VC1 surface of real meshes: closed even-vertex meshes (closed shells) and disks, normal
#    jump across every shared STEP edge measured on the Open CASCADE surfaces below 1e-6 degrees.
set -u
check=$1 shared=$2 here=$3 tmp=$4
rm -rf "$tmp"; mkdir -p "$tmp"
fail=0
m=$shared/data/meshes
echo "| mesh               | file             |  faces |       KiB | deviation  | normal jump   | STEP edges   | result |"
"$check" "$tmp" "$here/planar_mixed.off" --flat --max-jump 1e-6 || fail=1
"$check" "$tmp" "$m/cube.off" --flat --closed || fail=1
for mesh in icosahedron sphere; do
  "$check" "$tmp" "$m/$mesh.off" --closed --max-jump 1e-6 || fail=1
done
for mesh in nefertiti; do
  "$check" "$tmp" "$m/$mesh.off" --max-jump 1e-6 || fail=1
done
exit $fail
