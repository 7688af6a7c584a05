#!/bin/bash
# Linear parametrizations at 1M triangles: direct (CHOLMOD / UMFPACK) against the hierarchical
# solve (--solver hierarchical), and CGAL 5.5's mean value parametrizer on the same mesh (when
# scripts/setup.sh --peers installed it). One process per row, so that the peak memory is that
# row's; wall seconds of the method, CPU seconds (user + sys) and peak RSS of the whole process,
# and for hierarchical the largest uv difference to the direct result relative to the layout.
# The load average is printed before and after (the machine is shared).
#
#   bench/linear.sh [SCRATCH_DIR]
# env: BUILD (default build-bench), SHARED (default ../shared), METHODS (default all five),
#      ORDERING (passed to bench_linear: default, auto, amd, metis, nesdis, geometric),
#      CGAL=0 (skip the peer)
set -eu
SRC=$(cd "$(dirname "$0")/.." && pwd)
BUILD=${BUILD:-$SRC/build-bench}
SHARED=${SHARED:-$SRC/../shared}
SCRATCH=${1:-$(mktemp -d /tmp/sk-bench-linear.XXXXXX)}
METHODS=${METHODS:-tutte floater mvc harmonic lscm}
mkdir -p "$SCRATCH"
cmake -S "$SRC" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DSK_BUILD_TESTS=OFF > /dev/null
cmake --build "$BUILD" -j2 --target surfkit bench_linear bench_param $( ninja -C "$BUILD" -t targets all 2>/dev/null | grep -q '^cgal_param:' && echo cgal_param ) > /dev/null
SK=$BUILD/surfkit
BL=$BUILD/bench/bench_linear
BP=$BUILD/bench/bench_param
CG=$BUILD/bench/cgal_param
[ -x "$CG" ] && [ "${CGAL:-1}" != 0 ] || CG=
BIG=$SCRATCH/lion-head-s3.off
[ -e "$BIG" ] || "$SK" subdivide "$SHARED/data/meshes/lion-head.off" -o "$BIG" -n 3 -q
echo "# $(uptime | sed 's/.*load/load/') (start)"
ROWS=$SCRATCH/linear-rows.txt
: > "$ROWS"
TIMEF="%U %S %M"
for me in $METHODS; do
    for solver in direct hierarchical; do
        if [ $solver = direct ]; then
            args=(--write "$BIG" "$me" direct "$SCRATCH/$me-direct.bin")
        else
            args=("$BIG" "$me" hierarchical "$SCRATCH/$me-direct.bin")
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
