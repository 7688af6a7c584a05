#!/usr/bin/env bash
# The main job on the bundled samples: installs what is needed, builds, and runs surfkit.
# Outputs go to out/ (created). Usage: scripts/demo.sh
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh >/dev/null
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc 2>/dev/null || echo 2)" --target surfkit >/dev/null
sk=./build/surfkit
mkdir -p out
echo "== surfkit info data/nefertiti.off"
$sk info data/nefertiti.off
echo
echo "== surfkit convert data/nefertiti.off out/nefertiti.ply (binary PLY)"
$sk convert data/nefertiti.off out/nefertiti.ply
echo "== surfkit subdivide data/sphere.off -o out/sphere-loop2.obj --scheme loop -n 2"
$sk subdivide -q data/sphere.off -o out/sphere-loop2.obj --scheme loop -n 2
$sk info out/sphere-loop2.obj | sed -n '2,7p'
echo
echo "demo outputs are in out/: $(cd out && ls | tr '\n' ' ')"
