#!/bin/bash
# Where the seconds of a linear parametrization go at 1M triangles, as whole processes: one
# `surfkit param --json` run per row (lion-head Loop-subdivided 3 times), the report's
# stage_seconds (wall: read with the mesh build, check + boundary, assembly, analyse with the
# ordering, factor, solve, metrics, write) beside wall, user and sys CPU and peak RSS of the
# process from /usr/bin/time, and the load average at the start of the row. Each method runs
# once per BLAS setting, the settings of one method next to each other in time.
#
#   bench/linear_stages.sh [SCRATCH_DIR]
# env: BUILD (default build-bench), SHARED (default ../shared), METHODS (default all five),
#      SOLVER (direct or hierarchical, default direct), BLAS (OPENBLAS_NUM_THREADS values,
#      default "default 1"; default leaves it unset)
set -eu
SRC=$(cd "$(dirname "$0")/.." && pwd)
BUILD=${BUILD:-$SRC/build-bench}
SHARED=${SHARED:-$SRC/../shared}
SCRATCH=${1:-$(mktemp -d /tmp/sk-bench-stages.XXXXXX)}
METHODS=${METHODS:-lscm floater mvc tutte harmonic}
SOLVER=${SOLVER:-direct}
BLAS=${BLAS:-default 1}
mkdir -p "$SCRATCH"
cmake -S "$SRC" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DSK_BUILD_TESTS=OFF > /dev/null
cmake --build "$BUILD" -j2 --target surfkit > /dev/null
SK=$BUILD/surfkit
BIG=$SCRATCH/lion-head-s3.off
[ -e "$BIG" ] || "$SK" subdivide "$SHARED/data/meshes/lion-head.off" -o "$BIG" -n 3 -q
printf '| method | solver | BLAS threads | triangles | read | check+boundary | assemble | analyse | factor | solve | metrics | write | wall s | user s | sys s | peak MB | flips | load |\n'
printf '|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n'
for me in $METHODS; do
    for b in $BLAS; do
        load=$(cut -d' ' -f1 /proc/loadavg)
        envs=()
        [ "$b" = default ] || envs=(OPENBLAS_NUM_THREADS="$b")
        env "${envs[@]}" /usr/bin/time -f '%e %U %S %M' -o "$SCRATCH/time.txt" \
            "$SK" param "$BIG" -o "$SCRATCH/uv-$me.obj" --method "$me" --solver "$SOLVER" --json \
            > "$SCRATCH/report.json" 2> /dev/null || { echo "$me $SOLVER BLAS $b failed" >&2; continue; }
        python3 - "$SCRATCH/report.json" "$SCRATCH/time.txt" "$me" "$SOLVER" "$b" "$load" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
s = d["stage_seconds"]
wall, user, sys_s, kb = open(sys.argv[2]).read().split()
cols = [s["read"], s["check"] + s["boundary"], s["weights_and_assembly"], s["analyse"],
        s["factor"], s["solve"], s["metrics"], s["write"]]
print("| %s | %s | %s | %d | %s | %s | %s | %s | %d | %d | %s |" % (
    sys.argv[3], sys.argv[4], sys.argv[5], d["faces"], " | ".join("%.2f" % c for c in cols),
    wall, user, sys_s, int(kb) // 1024, d["flipped"], sys.argv[6]))
PY
    done
done
