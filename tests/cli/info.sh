#!/usr/bin/env bash
# `surfkit info --json` has every key the issue names, with the right values on two meshes; usage
# errors exit 2; convert + info round trip through every format keeps the counts.
set -u
bin=$1 src=$2 shared=$3 tmp=$4
rm -rf "$tmp"; mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
"$bin" info --json "$shared/data/meshes/eight.off" >"$tmp/eight.json" || fail "info eight.off"
for key in vertices faces edges boundary_loops components euler_characteristic genus \
           non_manifold_edges non_manifold_vertices degenerate_faces duplicate_faces \
           unreferenced_vertices angle_deficit_sum gauss_bonnet_error; do
  grep -q "\"$key\": " "$tmp/eight.json" || fail "key $key missing"
done
val() { grep "\"$1\": " "$2" | head -1 | sed 's/.*: //; s/,$//'; }
[ "$(val vertices "$tmp/eight.json")" = 315 ] || fail "eight vertices"
[ "$(val genus "$tmp/eight.json")" = 2 ] || fail "eight genus"
[ "$(val euler_characteristic "$tmp/eight.json")" = -2 ] || fail "eight chi"
python3 -c "import json,sys; json.load(open(sys.argv[1]))" "$tmp/eight.json" 2>/dev/null \
  || { command -v python3 >/dev/null && fail "invalid JSON"; }
"$bin" info >/dev/null 2>&1; [ $? -eq 2 ] || fail "no input should exit 2"
"$bin" info --bogus x.off >/dev/null 2>&1; [ $? -eq 2 ] || fail "unknown option should exit 2"
"$bin" frobnicate >/dev/null 2>&1; [ $? -eq 2 ] || fail "unknown subcommand should exit 2"
for cmd in info convert subdivide; do
  "$bin" $cmd --help | grep -q "usage: surfkit $cmd" || fail "$cmd --help"
done
# every format from the original and back: counts kept (STL merges vertices by position, and
# mask_cone has 30 seam vertices duplicated by position: STL gives 1200 distinct ones)
for ext in obj ply stl off; do
  "$bin" convert "$shared/data/meshes/mask_cone.off" "$tmp/m.$ext" || fail "convert to $ext"
  "$bin" convert "$tmp/m.$ext" "$tmp/back.off" || fail "convert back from $ext"
  "$bin" info --json "$tmp/back.off" >"$tmp/m.json" || fail "info $ext"
  want=1230; [ $ext = stl ] && want=1200
  [ "$(val faces "$tmp/m.json")" = 2332 ] || fail "$ext faces"
  [ "$(val vertices "$tmp/m.json")" = $want ] || fail "$ext vertices"
  [ "$(val components "$tmp/m.json")" = 2 ] || fail "$ext components"
  [ "$(val euler_characteristic "$tmp/m.json")" = 2 ] || fail "$ext chi"
done
# subdivision from the CLI
"$bin" subdivide -q "$shared/data/meshes/sphere.off" -o "$tmp/s.ply" -n 2 || fail "subdivide"
"$bin" info --json "$tmp/s.ply" >"$tmp/s.json"
[ "$(val faces "$tmp/s.json")" = 5120 ] || fail "subdivided faces"
[ "$(val euler_characteristic "$tmp/s.json")" = 2 ] || fail "subdivided chi"
"$bin" subdivide "$shared/data/meshes/sphere.off" -o "$tmp/s.xyz" >/dev/null 2>&1
[ $? -eq 2 ] || fail "unknown output extension should exit 2"
# self-intersections: the intruding triangle of the CGAL test mesh crosses face 2 only (CGAL's
# PMP::self_intersections finds the same single pair); a clean sphere has none
"$bin" info "$shared/data/meshes/tetra_intersected_by_triangle.off" --json > "$tmp/x.json" || fail "info tetra"
[ "$(val self_intersections "$tmp/x.json")" = 1 ] || fail "tetra self-intersections"
grep -q '"self_intersection_examples": \[\[2,4\]\]' "$tmp/x.json" || fail "tetra crossing pair"
"$bin" info "$shared/data/meshes/sphere.off" | grep -q "self-intersections    none" || fail "sphere crossings"
echo "info/convert/subdivide CLI: ok"
