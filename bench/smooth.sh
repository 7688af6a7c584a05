#!/usr/bin/env bash
# VC1 surface of a ~1M-triangle closed mesh: armadillo Loop-subdivided twice (832,000 triangles).
# Prints the table of stages and the deletion counts. Target (DESIGN.md): under 3 s.
# Usage: bench/smooth.sh [BUILD_DIR]   (default build/; scratch files in BUILD_DIR/bench-smooth)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2 --target surfkit bench_smooth >/dev/null
scratch="$build/bench-smooth"; mkdir -p "$scratch"
[ -f "$scratch/armadillo2.ply" ] ||
  "$build/surfkit" subdivide -q ../shared/data/meshes/armadillo.off -o "$scratch/armadillo2.ply" -n 2
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
"$build/bench/bench_smooth" "$scratch/armadillo2.ply"
