#!/usr/bin/env bash
# Smooth surfaces on the shared meshes, VC1 with the least-squares free points (vc1-lsq, before),
# VC1 with the fair free points (vc1, the default), the same with --parity-flips (vc1-parity) and
# the PN-triangle baseline: singular patches,
# singular patches before the regularity repair, shape
# (max_overshoot with its patch, patches over 0.5, fairness worst / mean), deleted edges against
# the lower bound (#even interior vertices / 2, counted here from the input file and by the
# library), max normal jump, seconds per stage. Then the VC1 surface of a ~1M-triangle closed
# mesh (armadillo Loop-subdivided twice, 832,000 triangles) by stage; target (DESIGN.md) under 3 s.
# Usage: bench/smooth.sh [BUILD_DIR]   (default build/; scratch files in BUILD_DIR/bench-smooth)
#        SK_BENCH_LARGE=0 skips the 1M-triangle part; SK_BENCH_MESHES="cow pig" picks meshes.
#        SK_BENCH_BEFORE=OLD_SURFKIT adds a vc1-before row per mesh (the old build's default VC1)
#        to the shape table and the per-stage CPU table, old build against this one
#        (SK_BENCH_STAGE_MESHES, SK_BENCH_RUNS); SK_BENCH_MESHES="" skips the shape table.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2 --target surfkit bench_smooth >/dev/null
scratch="$build/bench-smooth"; mkdir -p "$scratch"
meshes=${SK_BENCH_MESHES-"cow armadillo lion-head pig mushroom three_peaks bunny00 fandisk nefertiti knot1 eight"}
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "surfkit $("$build/surfkit" --version 2>/dev/null | head -1), $(git rev-parse --short HEAD 2>/dev/null)"
echo
for name in $meshes; do
  in=../shared/data/meshes/$name.off
  # vc1-lsq: the free points by least squares to the wire frame alone (before the fair points)
  # vc1-before: the default VC1 of SK_BENCH_BEFORE (an earlier build), beside this build's vc1
  # vc1-parity: the default VC1 with --parity-flips (fewer even vertices, fewer deletions)
  for scheme in vc1-lsq ${SK_BENCH_BEFORE:+vc1-before} vc1 vc1-parity pn; do
    out="$scratch/$name-$scheme.json" note="" args="--scheme ${scheme%-*}" bin="$build/surfkit"
    [ "$scheme" = vc1-lsq ] && args="$args --free-points lsq"
    [ "$scheme" = vc1-parity ] && args="$args --parity-flips"
    [ "$scheme" = vc1-before ] && bin=$SK_BENCH_BEFORE
    # exit 1: an odd closed component (no edge deletion exists): split an edge as the CLI offers
    if ! "$bin" smooth "$in" $args --json --allow-fail -q > "$out" 2> "$out.err"; then
      note=split
      "$bin" smooth "$in" $args --json --allow-fail --allow-split -q \
        > "$out" 2> "$out.err" || note="failed: $(head -1 "$out.err")"
    fi
    echo "$name $scheme $in $out $note"
  done
done | python3 bench/smooth_table.py
if [ -n "${SK_BENCH_BEFORE:-}" ]; then
  # before/after: SK_BENCH_BEFORE=OLD_SURFKIT (a copy of an earlier build/surfkit) against this
  # build, interleaved (old, new, old, new, ...), stage seconds as CPU seconds (bench/cpu_clock.c
  # preloaded; OpenMP workers wait passively so that spinning is not counted), the least of
  # SK_BENCH_RUNS (3) runs, us per input triangle; the shape figures beside them
  cc -O2 -shared -fPIC -o "$scratch/cpu_clock.so" bench/cpu_clock.c -ldl
  echo
  echo "before: $SK_BENCH_BEFORE, after: $build/surfkit; CPU us / input triangle; load $(cut -d' ' -f1-3 /proc/loadavg)"
  echo
  stage_meshes=${SK_BENCH_STAGE_MESHES:-cow armadillo lion-head pig bunny00 sphere fandisk}
  for name in $stage_meshes; do
    in=../shared/data/meshes/$name.off
    nf=$(awk 'NR == 1 && $1 == "OFF" { next } { print $2; exit }' "$in")
    for run in $(seq "${SK_BENCH_RUNS:-3}"); do
      for label in before after; do
        bin="$build/surfkit"; [ "$label" = before ] && bin=$SK_BENCH_BEFORE
        out="$scratch/$name-$label-$run.json"
        OMP_WAIT_POLICY=passive LD_PRELOAD="$(cd "$scratch" && pwd)/cpu_clock.so" "$bin" smooth "$in" \
          --json --allow-fail --allow-split -q > "$out" 2>/dev/null || true
        echo "$name $nf $label $out"
      done
    done
  done | python3 bench/smooth_stages.py
  echo "(load after: $(cut -d' ' -f1-3 /proc/loadavg))"
fi
[ "${SK_BENCH_LARGE:-1}" = 0 ] && exit 0
echo
[ -f "$scratch/armadillo2.ply" ] ||
  "$build/surfkit" subdivide -q ../shared/data/meshes/armadillo.off -o "$scratch/armadillo2.ply" -n 2
"$build/bench/bench_smooth" "$scratch/armadillo2.ply"
