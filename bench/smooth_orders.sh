#!/usr/bin/env bash
# How the VC1 surface depends on the input's vertex and face order: each mesh renumbered at random
# (bench/renumber.py, seeds 1..N), smooth with the re-routed deletion off (--reroute-rounds 0) and
# on (the default): singular patches per order, their sum, the orders left with any, and the
# repair stage's seconds (mean and worst; the re-routed builds count there).
# Usage: bench/smooth_orders.sh [BUILD_DIR]   (default build/)
#        SK_BENCH_MESHES="cow pig" picks meshes, SK_BENCH_ORDERS=N the number of orders (8).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2 --target surfkit >/dev/null
scratch=$(mktemp -d /tmp/sk-bench-orders.XXXXXX)
trap 'rm -rf "$scratch"' EXIT
meshes=${SK_BENCH_MESHES-"cow armadillo lion-head pig mushroom three_peaks bunny00 mech-holes-shark"}
orders=${SK_BENCH_ORDERS:-8}
echo "machine: $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg); $orders random orders per mesh, the file's own order first"
echo
echo "| mesh | rounds | singular per order (file order first) | sum | orders with any | repair s mean | repair s max |"
echo "|---|---|---|---|---|---|---|"
for name in $meshes; do
  files=(../shared/data/meshes/$name.off)
  for seed in $(seq 1 "$orders"); do
    python3 bench/renumber.py ../shared/data/meshes/$name.off "$scratch/$name-$seed.off" "$seed"
    files+=("$scratch/$name-$seed.off")
  done
  for rounds in 0 6; do
    for f in "${files[@]}"; do
      "$build/surfkit" smooth "$f" --reroute-rounds $rounds --json 2>/dev/null || true
    done | python3 -c '
import json, sys
dec, text, runs = json.JSONDecoder(), sys.stdin.read(), []
i = 0
while i < len(text):
    if text[i].isspace():
        i += 1
        continue
    d, i = dec.raw_decode(text, i)
    runs.append(d)
s = [d["singular_patches"] for d in runs]
t = [d["stage_seconds"]["repair"] for d in runs]
print("| %s | %s | %s | %d | %d of %d | %.3f | %.3f |" % (sys.argv[1], sys.argv[2],
      " ".join(map(str, s)), sum(s), sum(x > 0 for x in s), len(s), sum(t) / len(t), max(t)))
' "$name" "$rounds"
  done
done
