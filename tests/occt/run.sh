#!/usr/bin/env bash
# Export verification with Open CASCADE on flat patch networks (exact shared boundaries): a planar
# mesh of triangles and quads (normal jump 0 everywhere), and closed meshes (closed STEP shell).
set -u
check=$1 shared=$2 here=$3 tmp=$4
rm -rf "$tmp"; mkdir -p "$tmp"
fail=0
echo "| mesh               | file             |  faces |    KiB    | deviation  | normal jump    | STEP edges   |"
"$check" "$tmp" "$here/planar_mixed.off" --flat --max-jump 1e-6 || fail=1
"$check" "$tmp" "$shared/data/meshes/cube.off" --flat --closed || fail=1
"$check" "$tmp" "$shared/data/meshes/icosahedron.off" --flat --closed || fail=1
"$check" "$tmp" "$shared/data/meshes/nefertiti.off" --flat || fail=1
exit $fail
