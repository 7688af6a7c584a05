#!/usr/bin/env bash
# Issue 16, "A watertight tessellation": patch boundaries are tessellated once and shared
# (before, the cube's tessellation had 128 boundary edges in 10 regions, the sphere's 3240 in 245).
# The `surfkit smooth` tessellation (.ply and .obj) of closed meshes must be closed to VTK
# (vtkFeatureEdges on the file's own connectivity): no boundary edge, no non-manifold edge, one
# region. Prints the counts. Skips (77) without VTK's Python module (python3-vtk9).
set -u
bin=$1 src=$2 shared=$3 tmp=$4
py=
for p in python3 /usr/bin/python3; do
  if command -v "$p" >/dev/null && "$p" -c "import vtk" 2>/dev/null; then py=$p; break; fi
done
[ -n "$py" ] || { echo "SKIP: no python3 with VTK (scripts/setup.sh --interop installs python3-vtk9)"; exit 77; }
rm -rf "$tmp"; mkdir -p "$tmp"
fails=0
for mesh in cube sphere; do
  for ext in ply obj; do
    f=$tmp/$mesh.$ext
    "$bin" smooth "$shared/data/meshes/$mesh.off" -o "$f" -q > /dev/null || exit 2
    r=$("$py" "$src/tests/interop/vtk_edges.py" "$f") || exit 2
    ok=$(echo "$r" | python3 -c "import json,sys; r=json.load(sys.stdin); print(int(r['boundary_edges']==0 and r['non_manifold_edges']==0 and r['regions']==1))")
    echo "$mesh.$ext: $r: $([ "$ok" = 1 ] && echo watertight || echo NOT watertight)"
    [ "$ok" = 1 ] || fails=1
  done
done
exit $fails
