#!/usr/bin/env bash
# Full progressive-mesh hierarchy of ~1M-triangle closed meshes (bunny00 Loop-subdivided twice:
# 1,206,528 triangles; armadillo twice: 832,000), surfkit (random independent sets of half-edge
# collapses, Hormann et al. section 3) side by side with OpenMesh's decimater + ModIndependentSetsT
# (bench/peers/openmesh_hierarchy.cpp, built when libopenmesh-dev is installed) on the same files,
# then the level table of the bunny (like the paper's Figure 4).
# Usage: bench/hierarchy.sh [BUILD_DIR]   (default build/; scratch files in BUILD_DIR/bench-hierarchy)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2 --target surfkit bench_hierarchy >/dev/null
have_om=0
if cmake --build "$build" -j2 --target openmesh_hierarchy >/dev/null 2>&1; then have_om=1; fi
scratch="$build/bench-hierarchy"; mkdir -p "$scratch"
sk="$build/surfkit"
for m in bunny00 armadillo; do
  [ -f "$scratch/$m-2.ply" ] || $sk subdivide -q ../shared/data/meshes/$m.off -o "$scratch/$m-2.ply" -n 2
done
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), load $(cut -d' ' -f1-3 /proc/loadavg)"
echo
echo "| mesh | tool | levels | faces finest -> coarsest | build seconds (best of 3) |"
echo "|---|---|---:|---|---:|"
for m in bunny00 armadillo; do
  f="$scratch/$m-2.ply"
  row=$("$build/bench/bench_hierarchy" "$f" --repeat 3 | grep '^surfkit')
  lv=$(echo "$row" | sed 's/.*: \([0-9]*\) levels.*/\1/')
  fc=$(echo "$row" | sed 's/.*levels, \([0-9]* -> [0-9]*\) faces.*/\1/')
  t=$(echo "$row" | sed 's/.*build \([0-9.]*\) s.*/\1/')
  echo "| $m x2 | surfkit | $lv | $fc | $t |"
  if [ $have_om = 1 ]; then
    best=""
    for rep in 1 2 3; do
      r=$("$build/bench/openmesh_hierarchy" "$f")
      tt=$(echo "$r" | sed 's/.*build \([0-9.]*\) s.*/\1/')
      if [ -z "$best" ] || awk "BEGIN{exit !($tt < $best)}"; then best=$tt; orow=$r; fi
    done
    lv=$(echo "$orow" | sed 's/.*: \([0-9]*\) levels.*/\1/')
    fc=$(echo "$orow" | sed 's/.*levels, \([0-9]* -> [0-9]*\) faces.*/\1/')
    echo "| $m x2 | OpenMesh DecimaterT + ModIndependentSetsT | $lv | $fc | $best |"
  else
    echo "| $m x2 | OpenMesh | (libopenmesh-dev not installed: peer not built) | | |"
  fi
done
echo
echo "surfkit levels of bunny00 x2 (closed, genus 0; cf. Figure 4: 1,087,716 -> 3,774 triangles):"
"$build/bench/bench_hierarchy" "$scratch/bunny00-2.ply" --repeat 1 --levels-table | tail -n +3
if [ $have_om = 1 ]; then
  echo
  echo "OpenMesh levels of bunny00 x2:"
  "$build/bench/openmesh_hierarchy" "$scratch/bunny00-2.ply" --levels-table | tail -n +2
fi
