#!/bin/bash
# Linear parametrizations at 1M triangles: direct (CHOLMOD / UMFPACK) against the hierarchical
# solve (--solver hierarchical) and the algebraic multigrid (--solver amg), and CGAL 5.5's mean value parametrizer on the same mesh (when
# scripts/setup.sh --peers installed it). One process per row, so that the peak memory is that
# row's; wall seconds of the method, CPU seconds (user + sys) and peak RSS of the whole process,
# and for hierarchical the largest uv difference to the direct result relative to the layout.
# The load average is printed before and after (the machine is shared).
#
#   bench/linear.sh [SCRATCH_DIR]
# env: BUILD (default build-bench), SHARED (default ../shared), METHODS (default all five),
#      SOLVERS (default "direct hierarchical amg"; direct first, the others compared with it),
#      ORDERING (passed to bench_linear: default, auto, amd, metis, nesdis, geometric),
#      CGAL=0 (skip the peer)
#
#   STAGES=1 bench/linear.sh [SCRATCH_DIR]
# instead: where the seconds go, as whole processes: one `surfkit param --json` run per row, the
# report's stage_seconds (wall: read with the mesh build, check + boundary, assembly, analyse
# with the ordering, factor, solve, metrics, write) beside wall, user and sys CPU and peak RSS
# from /usr/bin/time and the load average at the start of the row; each method once per BLAS
# setting, the settings of one method next to each other in time.
# env: SOLVER (direct, hierarchical, amg or auto, default direct; several: interleaved per method),
#      BLAS (OPENBLAS_NUM_THREADS values,
#      default "default 1"; default leaves it unset)
#
#   CROSSOVER=1 MESHES="a.off b.off ..." bench/linear.sh [SCRATCH_DIR]
# instead: where --solver auto should switch from direct to amg: per mesh and method, REPEAT
# (default 3) interleaved pairs of whole `surfkit param --json` processes (direct, then amg as
# --solver auto runs it: --amg-from 1),
# the solve stage (analyse + factor + solve, wall) and the process's user + sys CPU, medians;
# amg's iterations and residual, the load average at the start of the row.
# env: MESHES (default the lion head Loop x1 and x2), METHODS, REPEAT
set -eu
SRC=$(cd "$(dirname "$0")/.." && pwd)
BUILD=${BUILD:-$SRC/build-bench}
SHARED=${SHARED:-$SRC/../shared}
SCRATCH=${1:-$(mktemp -d /tmp/sk-bench-linear.XXXXXX)}
METHODS=${METHODS:-tutte floater mvc harmonic lscm}
mkdir -p "$SCRATCH"
if [ "${NOBUILD:-0}" != 1 ]; then # NOBUILD=1: BUILD is built already (keeps its configuration)
cmake -S "$SRC" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DSK_BUILD_TESTS=OFF > /dev/null
cmake --build "$BUILD" -j2 --target surfkit bench_linear bench_param $( ninja -C "$BUILD" -t targets all 2>/dev/null | grep -q '^cgal_param:' && echo cgal_param ) > /dev/null
fi
SK=$BUILD/surfkit
BL=$BUILD/bench/bench_linear
BP=$BUILD/bench/bench_param
CG=$BUILD/bench/cgal_param
[ -x "$CG" ] && [ "${CGAL:-1}" != 0 ] || CG=
BIG=$SCRATCH/lion-head-s3.off
[ -e "$BIG" ] || "$SK" subdivide "$SHARED/data/meshes/lion-head.off" -o "$BIG" -n 3 -q
if [ "${CROSSOVER:-0}" = 1 ]; then
    if [ -z "${MESHES:-}" ]; then
        for k in 1 2; do
            [ -e "$SCRATCH/lion-head-s$k.off" ] ||
                "$SK" subdivide "$SHARED/data/meshes/lion-head.off" -o "$SCRATCH/lion-head-s$k.off" -n $k -q
        done
        MESHES="$SCRATCH/lion-head-s1.off $SCRATCH/lion-head-s2.off"
    fi
    printf '| mesh | free vertices | method | direct solve s | amg solve s | direct CPU s | amg CPU s | amg iterations | amg residual | load |\n'
    printf '|---|---|---|---|---|---|---|---|---|---|\n'
    for mesh in $MESHES; do
        for me in $METHODS; do
            load=$(cut -d' ' -f1 /proc/loadavg)
            : > "$SCRATCH/pairs.txt"
            for r in $(seq "${REPEAT:-3}"); do
                for so in direct amg; do
                    # amg as auto runs it (its tolerance), the crossover set below every mesh
                    args=(--solver direct)
                    [ $so = direct ] || args=(--solver auto --amg-from 1)
                    /usr/bin/time -f '%U %S' -o "$SCRATCH/time.txt" "$SK" param "$mesh" \
                        -o "$SCRATCH/uv.obj" --method "$me" "${args[@]}" --json > "$SCRATCH/report.json" 2> /dev/null ||
                        { echo "$mesh $me $so failed" >&2; continue; }
                    echo "$so $(cat "$SCRATCH/time.txt") $(python3 -c 'import json, sys
d = json.load(open(sys.argv[1])); s = d["stage_seconds"]; v = d["solver"]
print(s["analyse"] + s["factor"] + s["solve"], v["iterations"], v["residual"], d["interior"])' "$SCRATCH/report.json")" >> "$SCRATCH/pairs.txt"
                done
            done
            python3 - "$SCRATCH/pairs.txt" "$(basename "$mesh")" "$me" "$load" <<'PY'
import statistics as st, sys
rows = [l.split() for l in open(sys.argv[1])]
def med(so, k):
    return st.median(float(r[k]) if k != 1 else float(r[1]) + float(r[2]) for r in rows if r[0] == so)
amg = [r for r in rows if r[0] == "amg"]
print("| %s | %s | %s | %.3f | %.3f | %.2f | %.2f | %s | %.1e | %s |" % (
    sys.argv[2], rows[0][6], sys.argv[3], med("direct", 3), med("amg", 3), med("direct", 1),
    med("amg", 1), amg[-1][4], float(amg[-1][5]), sys.argv[4]))
PY
        done
    done
    exit 0
fi
if [ "${STAGES:-0}" = 1 ]; then
    printf '| method | solver | ran | BLAS threads | triangles | read | check+boundary | assemble | analyse | factor | solve | metrics | write | wall s | user s | sys s | peak MB | flips | iterations | residual | load |\n'
    printf '|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n'
    for me in $METHODS; do
        for so in ${SOLVER:-direct}; do
        for b in ${BLAS:-default 1}; do
            load=$(cut -d' ' -f1 /proc/loadavg)
            envs=()
            [ "$b" = default ] || envs=(OPENBLAS_NUM_THREADS="$b")
            env "${envs[@]}" /usr/bin/time -f '%e %U %S %M' -o "$SCRATCH/time.txt" \
                "$SK" param "$BIG" -o "$SCRATCH/uv-$me.obj" --method "$me" --solver "$so" --json \
                > "$SCRATCH/report.json" 2> /dev/null || { echo "$me $so BLAS $b failed" >&2; continue; }
            python3 - "$SCRATCH/report.json" "$SCRATCH/time.txt" "$me" "$so" "$b" "$load" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
s = d["stage_seconds"]
wall, user, sys_s, kb = open(sys.argv[2]).read().split()
cols = [s["read"], s["check"] + s["boundary"], s["weights_and_assembly"], s["analyse"],
        s["factor"], s["solve"], s["metrics"], s["write"]]
v = d["solver"]
print("| %s | %s | %s | %s | %d | %s | %s | %s | %s | %d | %d | %d | %.1e | %s |" % (
    sys.argv[3], sys.argv[4], v["route"], sys.argv[5], d["faces"],
    " | ".join("%.2f" % c for c in cols), wall, user, sys_s, int(kb) // 1024, d["flipped"],
    v["iterations"], v["residual"], sys.argv[6]))
PY
        done
        done
    done
    exit 0
fi
echo "# $(uptime | sed 's/.*load/load/') (start)"
ROWS=$SCRATCH/linear-rows.txt
: > "$ROWS"
TIMEF="%U %S %M"
for me in $METHODS; do
    for solver in ${SOLVERS:-direct hierarchical amg}; do
        if [ $solver = direct ]; then
            args=(--write "$BIG" "$me" direct "$SCRATCH/$me-direct.bin")
        else
            args=("$BIG" "$me" "$solver" "$SCRATCH/$me-direct.bin")
        fi
        row=$( { /usr/bin/time -f "$TIMEF" -o "$SCRATCH/time.txt" "$BL" "${args[@]}"; } ) || { echo "$me $solver failed" >&2; continue; }
        read -r us sy kb < "$SCRATCH/time.txt"
        echo "$row $(awk -v u="$us" -v s="$sy" 'BEGIN { printf "%.2f", u + s }')" >> "$ROWS"
    done
done
if [ -n "$CG" ]; then
    secs=$(/usr/bin/time -f "$TIMEF" -o "$SCRATCH/time.txt" "$CG" "$BIG" mvc "$SCRATCH/cgal.bin") && {
        read -r us sy kb < "$SCRATCH/time.txt"
        read -r ms mm fl < <("$BP" --uv "$BIG" "$SCRATCH/cgal.bin")
        faces=$(awk 'NR == 1 {print $2}' "$ROWS")
        echo "lion-head-s3.off $faces cgal-mvc eigen - - - - - - $secs - - - - $(printf %.6f "$mm") $fl $((kb / 1024)) - $(awk -v u="$us" -v s="$sy" 'BEGIN { printf "%.2f", u + s }')" >> "$ROWS"
    } || echo "cgal mvc failed" >&2
fi
echo "# $(uptime | sed 's/.*load/load/') (end)"
printf '\n| method | solver | weights+assembly | analyse (hierarchy) | factor (setup) | solve (Krylov) | total s | CPU s | levels | iterations | rel. residual | factor nnz | MIPS mean | flips | peak MB | uv diff / layout |\n'
printf '|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n'
awk '{ printf "| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", $3, $4, $7, $8, $9, $10, $11, $20, $12, $13, $14, $15, $16, $17, $18, $19 }' "$ROWS"
mvc=$(awk '$3 == "mvc" && $4 == "direct" {print $11}' "$ROWS")
cg=$(awk '$3 == "cgal-mvc" {print $11}' "$ROWS")
[ -n "$mvc" ] && [ -n "$cg" ] && awk -v a="$cg" -v b="$mvc" 'BEGIN { printf "\nCGAL mean value / surfkit mvc direct: %.1fx\n", a / b }'
echo "# rows in $ROWS"
