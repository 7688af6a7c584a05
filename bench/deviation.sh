#!/bin/bash
# Closest-point queries and deviation: surfkit's BVH vs CGAL 5.5's AABB tree (when installed,
# `scripts/setup.sh --peers`) on the same surfaces and the same query points (every vertex and
# face centroid of the query mesh), single-threaded both; then surfkit's whole two-sided
# deviation (both directions, 4 samples per triangle, OpenMP). Pairs: cow's VC1 tessellation vs
# cow, and lion-head Loop-subdivided 3 times (1.07M triangles) vs lion-head and back.
#   bench/deviation.sh [SCRATCH_DIR]      env: BUILD (default build-bench), SHARED
set -eu
SRC=$(cd "$(dirname "$0")/.." && pwd)
BUILD=${BUILD:-$SRC/build-bench}
SHARED=${SHARED:-$SRC/../shared}
SCRATCH=${1:-$(mktemp -d /tmp/sk-bench-dev.XXXXXX)}
mkdir -p "$SCRATCH"
cmake -S "$SRC" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DSK_BUILD_TESTS=OFF > /dev/null
targets="surfkit bench_deviation"
ninja -C "$BUILD" -t targets all 2>/dev/null | grep -q '^bench/cgal_closest:' && targets="$targets cgal_closest"
cmake --build "$BUILD" -j2 --target $targets > /dev/null
SK=$BUILD/surfkit
CG=$BUILD/bench/cgal_closest
[ -x "$CG" ] || { echo "# CGAL not installed: surfkit rows only"; CG=; }
M=$SHARED/data/meshes
[ -e "$SCRATCH/cow-vc1.off" ] || { "$SK" smooth "$M/cow.off" -o "$SCRATCH/cow-vc1.ply" -q > /dev/null && "$SK" convert "$SCRATCH/cow-vc1.ply" "$SCRATCH/cow-vc1.off"; }
[ -e "$SCRATCH/lion-s3.off" ] || "$SK" subdivide "$M/lion-head.off" -o "$SCRATCH/lion-s3.off" -n 3 -q
echo "# load average: $(cut -d' ' -f1-3 /proc/loadavg), $(nproc) cores"
echo "| surface | queries from | tool | triangles | queries | build s | query s | us/query | max distance |"
echo "|---|---|---|---|---|---|---|---|---|"
row() { # surface query
    local s=$1 q=$2 nt
    nt=$(sed -n 2p "$s" | awk '{print $2}')
    for tool in sk cg; do
        local out
        if [ $tool = sk ]; then out=$("$BUILD/bench/bench_deviation" "$s" "$q" | head -1)
        elif [ -n "$CG" ]; then out=$("$CG" "$s" "$q")
        else continue; fi
        echo "$out" | awk -v s="$(basename "$s")" -v q="$(basename "$q")" -v nt="$nt" \
          '{ printf "| %s | %s | %s | %d | %d | %.3f | %.3f | %.2f | %.9g |\n", s, q, $1, nt, $4, $2, $3, 1e6 * $3 / $4, $5 }'
    done
}
row "$SCRATCH/cow-vc1.off" "$M/cow.off"
row "$M/cow.off" "$SCRATCH/cow-vc1.off"
row "$SCRATCH/lion-s3.off" "$M/lion-head.off"
row "$M/lion-head.off" "$SCRATCH/lion-s3.off"
echo
echo "| surface | mesh | two-sided samples | sk_deviation s | hausdorff |"
echo "|---|---|---|---|---|"
for pair in "$SCRATCH/cow-vc1.off $M/cow.off" "$SCRATCH/lion-s3.off $M/lion-head.off"; do
    set -- $pair
    "$BUILD/bench/bench_deviation" "$1" "$2" | tail -1 | awk -v s="$(basename "$1")" -v m="$(basename "$2")" \
      '{ printf "| %s | %s | %d | %.3f | %.9g |\n", s, m, $3, $2, $4 }'
done
