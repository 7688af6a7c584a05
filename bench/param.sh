#!/bin/bash
# Linear parametrization benchmark: surfkit vs CGAL 5.5 (when installed) on the shared disk
# meshes and on lion-head Loop-subdivided 3 times (1.07M triangles). Circle boundary with
# chord-length (= arc-length) spacing for the fixed-border methods, two pinned vertices for
# LSCM. MIPS and flips of both are measured by surfkit's metrics on the uv each one produced.
#
#   bench/param.sh [SCRATCH_DIR]
# env: BUILD (build folder, default build-bench), SHARED (default ../shared),
#      CGAL_BIG (CGAL methods on the 1M mesh; default "mvc"; e.g. "tutte mvc harmonic lscm"),
#      SKIP_BIG=1 (original meshes only)
set -eu
SRC=$(cd "$(dirname "$0")/.." && pwd)
BUILD=${BUILD:-$SRC/build-bench}
SHARED=${SHARED:-$SRC/../shared}
SCRATCH=${1:-$(mktemp -d /tmp/sk-bench-param.XXXXXX)}
CGAL_BIG=${CGAL_BIG:-mvc}
mkdir -p "$SCRATCH"
cmake -S "$SRC" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DSK_BUILD_TESTS=OFF > /dev/null
cmake --build "$BUILD" -j2 --target surfkit bench_param $( [ -e "$SRC/bench/peers/cgal_param.cpp" ] && ninja -C "$BUILD" -t targets all 2>/dev/null | grep -q '^bench/cgal_param:' && echo cgal_param ) > /dev/null
SK=$BUILD/surfkit
BP=$BUILD/bench/bench_param
CG=$BUILD/bench/cgal_param
[ -x "$CG" ] || { echo "# CGAL not installed: surfkit rows only"; CG=; }

MESHES=""
for m in nefertiti patch-01 paraboloid-patch three_peaks mushroom lion-head; do
    MESHES="$MESHES $SHARED/data/meshes/$m.off"
done
if [ "${SKIP_BIG:-0}" != 1 ]; then
    BIG=$SCRATCH/lion-head-s3.off
    [ -e "$BIG" ] || "$SK" subdivide "$SHARED/data/meshes/lion-head.off" -o "$BIG" -n 3 -q
    MESHES="$MESHES $BIG"
fi

ROWS=$SCRATCH/rows.txt
: > "$ROWS"
for mesh in $MESHES; do
    "$BP" "$mesh" tutte floater mvc harmonic lscm >> "$ROWS" 2>/dev/null
    if [ -n "$CG" ]; then
        name=$(basename "$mesh")
        methods="tutte mvc harmonic lscm"
        [ "$name" = lion-head-s3.off ] && methods=$CGAL_BIG
        for me in $methods; do
            secs=$("$CG" "$mesh" "$me" "$SCRATCH/uv.bin") || { echo "$name cgal-$me failed" >&2; continue; }
            read -r ms mm fl < <("$BP" --uv "$mesh" "$SCRATCH/uv.bin")
            faces=$(awk -v n="$name" '$1 == n {print $2; exit}' "$ROWS")
            echo "$name $faces cgal-$me - - - - - - $secs $ms $mm $fl -" >> "$ROWS"
        done
    fi
done

printf '\n| mesh | faces | method | check | boundary | weights+assembly | analyse | factor | solve | total s | MIPS sum | MIPS mean | flips |\n'
printf '|---|---|---|---|---|---|---|---|---|---|---|---|---|\n'
awk '{ printf "| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %.6f | %.6f | %s |\n", $1, $2, $3, $4, $5, $6, $7, $8, $9, $10, $11, $12, $13 }' "$ROWS"
echo
echo "# rows in $ROWS"
