#!/usr/bin/env bash
# Quad and polygon input (Blender's default cube and Suzanne as Blender 3.4 exports them, a
# hexagonal prism written by hand): param, simplify and smooth triangulate on the way in and say
# so on stdout; --keep-polygons refuses with the algorithms' own error (exit 1, no output).
set -u
bin=$1 src=$2 tmp=$4
rm -rf "$tmp"; mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
val() { grep "\"$1\": " "$2" | head -1 | sed 's/.*: //; s/,$//'; }
d=$src/tests/data/polygons

# the cube: 6 quads -> 12 triangles, a closed mesh of 8 vertices
"$bin" simplify "$d/blender_cube.obj" -o "$tmp/cube.off" > "$tmp/out" || fail "simplify cube"
grep -q 'blender_cube.obj: triangulated 6 quads into 12 triangles' "$tmp/out" || fail "simplify summary: $(cat "$tmp/out")"
grep -q '12 -> [0-9]* faces' "$tmp/out" || fail "simplify did not start from 12 triangles: $(cat "$tmp/out")"
"$bin" param "$d/blender_cube.obj" -o "$tmp/cube.obj" --report "$tmp/cube.json" > "$tmp/out" || fail "param cube"
grep -q 'triangulated 6 quads' "$tmp/out" || fail "param summary: $(cat "$tmp/out")"
[ "$(val faces "$tmp/cube.json")" = 12 ] && [ "$(val flipped "$tmp/cube.json")" = 0 ] || fail "param cube report"
[ "$(val triangulated_quads "$tmp/cube.json")" = 6 ] && [ "$(val triangulated_polygons "$tmp/cube.json")" = 0 ] ||
  fail "param cube report: triangulated_quads $(val triangulated_quads "$tmp/cube.json")"
[ "$(grep -c '^f ' "$tmp/cube.obj")" = 12 ] || fail "param cube: not 12 triangles"
# the file's per-corner normals are flat, one per face side: they differ at every cube edge, so
# those edges are G0 creases with the file's normals, and the surface is the cube (it failed with
# exit 1 before creases: one normal per vertex was opposite at some edges)
"$bin" smooth "$d/blender_cube.obj" -o "$tmp/cube.step" --json -q > "$tmp/cn.json" 2> "$tmp/err" ||
  fail "smooth cube with the file's normals: exit $?, $(cat "$tmp/err")"
python3 -c "import json; r = json.load(open('$tmp/cn.json')); assert r['g0_crease_edges'] == 12 and r['max_normal_jump_deg'] < 1e-7 and abs(r['max_crease_jump_deg'] - 90) < 1e-9 and r['max_normal_error_deg'] < 1e-7, r" ||
  fail "smooth cube with the file's normals: $(cat "$tmp/cn.json")"
# normals opposite at an edge's ends (one normal per vertex, no crease) are bad input: exit 1,
# one line naming the file, not an internal failure
printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nvn 0 0 -1\nf 1//1 2//1 3//1\nf 1//1 3//1 4//2\n' > "$tmp/opp.obj"
"$bin" smooth "$tmp/opp.obj" -o "$tmp/opp.step" > "$tmp/out" 2> "$tmp/err"; rc=$?
[ $rc -eq 1 ] && [ "$(wc -l < "$tmp/err")" -eq 1 ] && grep -q "opp.obj: .*normals at its ends are opposite" "$tmp/err" &&
  [ ! -e "$tmp/opp.step" ] || fail "smooth with opposite normals: exit $rc, $(cat "$tmp/err")"
# the smooth surface estimates them
"$bin" smooth "$d/blender_cube.obj" -o "$tmp/cube.step" --estimate-normals > "$tmp/out" || fail "smooth cube"
grep -q 'triangulated 6 quads' "$tmp/out" && grep -q 'report pass' "$tmp/out" || fail "smooth cube: $(cat "$tmp/out")"
# --json keeps stdout JSON
"$bin" smooth "$d/blender_cube.obj" --estimate-normals --json > "$tmp/s.json" || fail "smooth --json"
python3 -c "import json,sys; r=json.load(open('$tmp/s.json')); assert r['triangulated_quads'] == 6 and r['triangles'] + r['quads'] > 0" ||
  fail "smooth --json is not JSON: $(head -2 "$tmp/s.json")"

# the hexagonal prism: 6 quads and 2 hexagons -> 20 triangles, closed, genus 0
"$bin" smooth "$d/hex_prism.off" -o "$tmp/hex.obj" --report "$tmp/hex.json" > "$tmp/out" || fail "smooth prism"
grep -q 'hex_prism.off: triangulated 6 quads and 2 polygons into 20 triangles' "$tmp/out" || fail "prism summary: $(cat "$tmp/out")"
[ "$(val pass_g1 "$tmp/hex.json")" = true ] && [ "$(val singular_patches "$tmp/hex.json")" = 0 ] || fail "prism report"
"$bin" info "$tmp/hex.obj" > "$tmp/info" || fail "info of the prism's tessellation"
grep -Eq '^ +edges +[0-9]+ \(0 on the boundary\)' "$tmp/info" || fail "prism tessellation not closed"
"$bin" param "$d/hex_prism.off" -o "$tmp/hex-uv.obj" --report "$tmp/hexp.json" -q || fail "param prism"
[ "$(val faces "$tmp/hexp.json")" = 20 ] && [ "$(val overlaps "$tmp/hexp.json")" = 0 ] || fail "prism atlas"
[ "$(val triangulated_polygons "$tmp/hexp.json")" = 2 ] || fail "prism atlas report: triangulated_polygons"
"$bin" simplify "$d/hex_prism.off" -o "$tmp/hs.off" --report "$tmp/hs.json" -q || fail "simplify prism"
[ "$(val triangulated_quads "$tmp/hs.json")" = 6 ] || fail "simplify report: triangulated_quads"

# Suzanne: 468 quads and 32 triangles; two quads share two sides at the nose, which the
# triangulation must not split along the same diagonal (that edge would be non-manifold)
"$bin" param "$d/blender_monkey.obj" -o "$tmp/monkey.obj" --report "$tmp/m.json" > "$tmp/out" || fail "param monkey: $(cat "$tmp/out")"
grep -q 'triangulated 468 quads into 936 triangles' "$tmp/out" || fail "monkey summary: $(cat "$tmp/out")"
[ "$(val faces "$tmp/m.json")" = 968 ] && [ "$(val flipped "$tmp/m.json")" = 0 ] || fail "monkey report"
"$bin" info --json "$tmp/monkey.obj" > "$tmp/mi.json" || fail "info monkey"
[ "$(val manifold "$tmp/mi.json")" = true ] && [ "$(val triangles "$tmp/mi.json")" = 968 ] || fail "monkey output not a manifold triangle mesh"
[ "$(val euler_characteristic "$tmp/mi.json")" = 2 ] || fail "monkey euler characteristic"
"$bin" simplify "$d/blender_monkey.obj" -o "$tmp/m.off" -q || fail "simplify monkey"

# --keep-polygons: the old refusal (now naming the file), one line, exit 1, no output
for cmd in "simplify -o $tmp/k.off" "param -o $tmp/k.obj" "smooth -o $tmp/k.obj"; do
  set -- $cmd
  "$bin" "$1" "$d/blender_cube.obj" "$2" "$3" --keep-polygons > /dev/null 2> "$tmp/err"; rc=$?
  [ $rc = 1 ] || fail "$1 --keep-polygons: exit $rc"
  [ "$(wc -l < "$tmp/err")" = 1 ] && grep -qi 'triangle mesh' "$tmp/err" || fail "$1 --keep-polygons: $(cat "$tmp/err")"
  grep -q '^surfkit: .*blender_cube.obj: ' "$tmp/err" || fail "$1 --keep-polygons: the error does not name the file"
  [ -e "$3" ] && fail "$1 --keep-polygons wrote $3"
done
echo "polygons: ok"
