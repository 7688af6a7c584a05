#!/usr/bin/env bash
# How far the edge deletion is from its optimum (issue 12, near-minimal deletions): per mesh the
# even interior vertices of the input, the bound ceil(#even / 2), the exact minimum T-join of the
# input (bench/tjoin_lemon.cpp, LEMON; a lower bound on any edge deletion of the input, tighter
# than #even / 2), the T-join avoiding the forbidden edges (quad corner > 160 degrees; a reference,
# not a bound: the library allows some), and surfkit's deleted edges with --keep-triangulation (on the input's edges, so
# against the same bounds) and by default (after the edge flips: the library's own #even and bound
# beside it), with the CPU seconds of the deletion stage.
# Usage: bench/tjoin.sh [BUILD_DIR]   (default build/; needs liblemon-dev: scripts/setup.sh --peers)
#        SK_BENCH_MESHES="cow pig" picks meshes; SK_BENCH_BEFORE=OLD_SURFKIT adds its deleted edges.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2 --target surfkit tjoin_lemon >/dev/null
scratch="$build/bench-tjoin"; mkdir -p "$scratch"
meshes=${SK_BENCH_MESHES-"cow armadillo lion-head pig mushroom three_peaks bunny00 fandisk nefertiti knot1"}
echo "load $(cut -d' ' -f1-3 /proc/loadavg)"
for name in $meshes; do
  in=../shared/data/meshes/$name.off
  read -r _ even bound tj av _ < <("$build/bench/tjoin_lemon" "$in" | tail -1)
  for bin in ${SK_BENCH_BEFORE:+$SK_BENCH_BEFORE} "$build/surfkit"; do
    for args in --keep-triangulation ""; do
      out="$scratch/$name.json"
      "$bin" smooth "$in" $args --json --allow-fail -q > "$out" 2>/dev/null ||
        "$bin" smooth "$in" $args --json --allow-fail --allow-split -q > "$out" 2>/dev/null || true
      python3 - "$out" "$name" "$even" "$bound" "$tj" "$av" "$bin" "${args:-default}" <<'PY'
import json, sys
out, name, even, bound, tj, av, binary, args = sys.argv[1:]
try:
    r = json.load(open(out))
except Exception:
    print(f"{name:12} {args:20} failed"); sys.exit(0)
d, lb = r['deleted_edges'], r['deleted_edges_lower_bound']
b = int(bound)
tjs = f"{int(tj) / b:.3f}" if tj.isdigit() else "none"
print(f"{name:12} {args:20} #even {even:>6} bound {bound:>6} T-join {tj:>6} ({tjs}) avoiding {av:>6} "
      f"deleted {d:>6} "
      f"({d / b:.3f}; library #even {r['even_vertices']} bound {lb}: {d / max(lb, 1):.3f}) "
      f"deletion cpu {r['stage_cpu_seconds']['edge_deletion']:.4f} s  [{binary}]")
PY
    done
  done
done
