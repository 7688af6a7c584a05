#!/bin/bash
# Fill-reducing orderings of the direct solvers on the parametrization systems of a 1M-triangle
# disk (lion-head Loop-subdivided 3 times): Tutte (CHOLMOD) and Floater (UMFPACK), one process per
# ordering: factor nonzeros, analyse / factor / solve seconds, CPU seconds and peak memory of the
# process, and the relative residual reached. "auto" is the library's own default choice.
#
#   bench/solve.sh [SCRATCH_DIR]      env: BUILD (default build-bench), SHARED, ORDERINGS
set -eu
SRC=$(cd "$(dirname "$0")/.." && pwd)
BUILD=${BUILD:-$SRC/build-bench}
SHARED=${SHARED:-$SRC/../shared}
SCRATCH=${1:-$(mktemp -d /tmp/sk-bench-solve.XXXXXX)}
ORDERINGS=${ORDERINGS:-auto amd metis nesdis}
mkdir -p "$SCRATCH"
cmake -S "$SRC" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DSK_BUILD_TESTS=OFF > /dev/null
cmake --build "$BUILD" -j2 --target surfkit bench_solve > /dev/null
BIG=$SCRATCH/lion-head-s3.off
[ -e "$BIG" ] || "$BUILD/surfkit" subdivide "$SHARED/data/meshes/lion-head.off" -o "$BIG" -n 3 -q
echo "# $(uptime | sed 's/.*load/load/') (start)"
printf '\n| system | solver | ordering | n | nnz | factor nnz | analyse | factor | solve | total s | CPU s | peak MB | rel. residual |\n'
printf '|---|---|---|---|---|---|---|---|---|---|---|---|---|\n'
for me in tutte floater; do
    for o in $ORDERINGS; do
        row=$(/usr/bin/time -f "%U %S %M" -o "$SCRATCH/time.txt" "$BUILD/bench/bench_solve" "$BIG" "$me" "$o") || continue
        read -r us sy kb < "$SCRATCH/time.txt"
        echo "$row" | awk -v u="$us" -v s="$sy" -v kb="$kb" '{ printf "| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %.2f | %d | %s |\n", $2, $3, $4, $5, $6, $7, $8, $9, $10, $11, u + s, kb / 1024, $12 }'
    done
done
echo "# $(uptime | sed 's/.*load/load/') (end)"
