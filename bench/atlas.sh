#!/usr/bin/env bash
# Atlases side by side: surfkit param (automatic charts, per-chart hierarchical MIPS, packing)
# against Blender's Smart UV Project + Pack Islands (Debian `blender`, headless), on every closed
# or holed mesh of ../shared/data/meshes and a ~0.8M-triangle closed mesh (armadillo, two Loop
# subdivisions). One independent script (bench/atlas_metrics.py) computes every figure from the
# OBJ files of both; seconds are each program's own (surfkit: atlas build; Blender: unwrap +
# pack, not import / export). xatlas is not compared (xatlas-web needs a browser: not done).
# Usage: bench/atlas.sh [MESH.off ...]   (default: the list below)
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j2 --target surfkit >/dev/null
sk=./build/surfkit
M=../shared/data/meshes
T=build/bench_atlas
mkdir -p "$T"
command -v blender >/dev/null || { echo "blender not installed (apt-get install blender)"; exit 1; }
meshes=("$@")
if [ ${#meshes[@]} -eq 0 ]; then
    meshes=(sphere cube icosahedron eight knot1 elephant cow pig blobby fandisk holes lion
            mech-holes-shark mask_cone bunny00 armadillo)
    meshes=("${meshes[@]/#/$M/}")
    meshes=("${meshes[@]/%/.off}")
    [ -f "$T/armadillo-1m.ply" ] || $sk subdivide "$M/armadillo.off" -o "$T/armadillo-1m.ply" --scheme loop -n 2 -q
    meshes+=("$T/armadillo-1m.ply")
fi
margin=$(awk 'BEGIN { print 2 / 1024 }') # the same gutter as surfkit's default (2 texels at 1024)
row() { # name program json seconds
    python3 - "$@" <<'PY'
import json, sys
name, prog, js, sec = sys.argv[1], sys.argv[2], json.loads(sys.argv[3]), float(sys.argv[4])
print("%-22s %-8s %7d %6d %8.2f %8.4f %8.4f %6d %8d %6.3f %8.2f" % (name, prog, js["faces"],
      js["charts"], js["seam_length_rel"], js["mips_mean"], js["area_log_mean"], js["flipped"],
      js["overlaps"], js["utilization"], sec))
PY
}
printf '%-22s %-8s %7s %6s %8s %8s %8s %6s %8s %6s %8s\n' mesh program faces charts seam_rel \
    mips area_log flips overlaps util seconds
for f in "${meshes[@]}"; do
    n=$(basename "${f%.*}")
    $sk convert "$f" "$T/$n.obj" >/dev/null
    $sk param "$f" -o "$T/$n-surfkit.obj" --atlas --report "$T/$n-surfkit.json" -q
    s_sec=$(python3 -c "import json; print(json.load(open('$T/$n-surfkit.json'))['seconds'])")
    b_sec=$(blender -b -P bench/peers/blender_smart_project.py -- "$T/$n.obj" "$T/$n-blender.obj" \
            "$margin" 2>/dev/null | sed -n 's/^BLENDER_SECONDS //p')
    row "$n" surfkit "$(python3 bench/atlas_metrics.py "$T/$n-surfkit.obj")" "$s_sec"
    row "$n" blender "$(python3 bench/atlas_metrics.py "$T/$n-blender.obj")" "${b_sec:-nan}"
done
