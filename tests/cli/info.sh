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
# round trip through every format and back
prev="$shared/data/meshes/mask_cone.off"
for ext in obj ply stl off; do
  "$bin" convert "$prev" "$tmp/m.$ext" || fail "convert to $ext"
  "$bin" info --json "$tmp/m.$ext" >"$tmp/m.json" || fail "info $ext"
  [ "$(val faces "$tmp/m.json")" = 2332 ] || fail "$ext faces"
  [ "$(val vertices "$tmp/m.json")" = 1230 ] || fail "$ext vertices"
  [ "$(val components "$tmp/m.json")" = 2 ] || fail "$ext components"
  prev="$tmp/m.$ext"
done
# subdivision from the CLI
"$bin" subdivide -q "$shared/data/meshes/sphere.off" -o "$tmp/s.ply" -n 2 || fail "subdivide"
"$bin" info --json "$tmp/s.ply" >"$tmp/s.json"
[ "$(val faces "$tmp/s.json")" = 5120 ] || fail "subdivided faces"
[ "$(val euler_characteristic "$tmp/s.json")" = 2 ] || fail "subdivided chi"
"$bin" subdivide "$shared/data/meshes/sphere.off" -o "$tmp/s.xyz" >/dev/null 2>&1
[ $? -eq 2 ] || fail "unknown output extension should exit 2"
echo "info/convert/subdivide CLI: ok"
