#!/usr/bin/env bash
# The main job on the bundled samples: installs what is needed, builds, and runs surfkit.
# Outputs go to out/. Usage: scripts/demo.sh
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh >/dev/null
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc 2>/dev/null || echo 2)" --target surfkit >/dev/null
sk=./build/surfkit
mkdir -p out
echo "== 1. surfkit info data/nefertiti.off"
$sk info data/nefertiti.off
echo
echo "== 2. hierarchical MIPS parametrization (free boundary) -> out/nefertiti_uv.obj + PNGs"
$sk param data/nefertiti.off -o out/nefertiti_uv.obj --method mips \
  --png out/nefertiti_uv.png --checker out/nefertiti_checker.png --report out/nefertiti_param.json
echo "== 2b. atlas of the closed data/sphere.off: charts, per-chart MIPS, packing -> out/sphere_atlas.obj"
$sk param data/sphere.off -o out/sphere_atlas.obj --png out/sphere_atlas.png \
  --checker out/sphere_atlas_checker.png --report out/sphere_atlas.json
echo
echo "== 3. VC1 smooth surface of data/sphere.off: continuity report, tessellation, STEP, IGES"
$sk smooth data/sphere.off -o out/sphere_smooth.obj --tess 6 --report out/sphere_report.json \
  --layout out/sphere_layout.png --render out/sphere_shaded.png -q
$sk smooth data/sphere.off -o out/sphere.step
$sk smooth data/sphere.off -o out/sphere.igs -q
grep -E '"(triangles|quads|deleted_edges|max_gap|max_normal_jump_deg|max_vertex_error|max_normal_error_deg|singular_patches)"' \
  out/sphere_report.json | sed 's/^ */  /'
echo
echo "== 4. how far the smooth surface is from the mesh, both ways -> out/sphere_deviation*.png"
$sk deviation out/sphere_smooth.obj data/sphere.off --png out/sphere_deviation.png \
  --png-surface out/sphere_deviation_surface.png --report out/sphere_deviation.json
echo
echo "== 4b. as few patches as a tolerance allows: VC1 over a coarse level of the progressive mesh,"
echo "       within 1e-2 of the diagonal -> out/nefertiti_tol.step, out/nefertiti_tol_deviation*.png"
$sk smooth data/nefertiti.off -o out/nefertiti_tol.step --tolerance-rel 1e-2 \
  --report out/nefertiti_tol.json
$sk smooth data/nefertiti.off -o out/nefertiti_tol.obj --tolerance-rel 1e-2 -q
$sk deviation out/nefertiti_tol.obj data/nefertiti.off --tolerance-rel 1e-2 \
  --png out/nefertiti_tol_deviation.png --png-surface out/nefertiti_tol_deviation_surface.png
echo
echo "== 5. interactive viewer (one self-contained HTML file): out/sphere.html, out/nefertiti.html"
$sk view data/sphere.off --smooth -o out/sphere.html
$sk view out/nefertiti_uv.obj -o out/nefertiti.html
echo
echo "== 6. surfkit convert / subdivide"
$sk convert data/nefertiti.off out/nefertiti.ply
$sk subdivide -q data/sphere.off -o out/sphere-loop2.obj --scheme loop -n 2
echo
echo "demo outputs in out/: $(cd out && ls | tr '\n' ' ')"
