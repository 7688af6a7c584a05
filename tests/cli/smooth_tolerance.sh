#!/usr/bin/env bash
# `surfkit smooth --tolerance-rel/--tolerance`: the sphere within 1e-2 of its diagonal with fewer
# patches than triangles (STEP and a tessellation written; JSON figures consistent: met, the
# deviation within T, G1, what each tried surface's max_deviation is); `surfkit deviation` of
# the written tessellation gives the same two-sided deviation; an absolute tolerance gives the
# same run; an unreachable tolerance exits 4 and still writes the file; usage errors exit 2.
set -u
bin=$1 src=$2 tmp=$4
rm -rf "$tmp"; mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
val() { grep "\"$1\": " "$2" | head -1 | sed 's/.*: //; s/,$//'; }
sphere=$src/data/sphere.off

"$bin" smooth "$sphere" -o "$tmp/s.step" --tolerance-rel 1e-2 --json -q > "$tmp/s.json" \
  || fail "sphere 1e-2 exit $?"
[ "$(val met "$tmp/s.json")" = true ] || fail "tolerance not met"
[ -s "$tmp/s.step" ] || fail "no STEP"
p=$(val patches "$tmp/s.json") tol=$(val tolerance "$tmp/s.json") d=$(val diagonal "$tmp/s.json")
[ "$p" -lt 320 ] || fail "$p patches for 320 triangles"
[ "$(grep -c '=ADVANCED_FACE(' "$tmp/s.step")" = "$p" ] || fail "STEP faces != $p patches"
awk -v t="$tol" -v d="$d" 'BEGIN { exit !(t > 0.999e-2 * d && t < 1.001e-2 * d) }' \
  || fail "tolerance $tol is not 1e-2 of the diagonal $d"
awk -v h="$(val hausdorff "$tmp/s.json")" -v t="$tol" 'BEGIN { exit !(h > 0 && h <= t) }' \
  || fail "deviation $(val hausdorff "$tmp/s.json") beyond $tol"
awk -v g="$(val max_normal_jump_deg "$tmp/s.json")" 'BEGIN { exit !(g < 0.5) }' || fail "not G1"
[ "$(val pass_g1 "$tmp/s.json")" = true ] || fail "pass_g1"
tried=$(val levels_tried "$tmp/s.json") levels=$(val hierarchy_levels "$tmp/s.json")
[ "$tried" -lt "$levels" ] || fail "$tried of $levels levels tried: a scan, not a search"
grep -q '"stage_seconds": {' "$tmp/s.json" || fail "no stage_seconds"
# every surface tried says what its max_deviation is: within T an upper bound, a level the
# search left at its first distances beyond T a lower bound, a refinement round beyond T exact
python3 - "$tmp/s.json" <<'PY' || fail "tried[].max_deviation_is"
import json, sys
r = json.load(open(sys.argv[1]))
t = r["tolerance"]
assert r["crease_edges"] == r["g0_crease_edges"] == 0, "creases on the sphere"
for e in r["tried"]:
    if "vc1" in e:
        continue
    want = "upper_bound" if e["met"] else "exact" if e["kind"] == "round" else "lower_bound"
    assert e["max_deviation_is"] == want, e
    assert (e["max_deviation"] <= t) == e["met"], e
PY

# the tessellation, measured again by `surfkit deviation` (the same samples)
"$bin" smooth "$sphere" -o "$tmp/s.obj" --tolerance-rel 1e-2 -q || fail "obj"
"$bin" deviation "$tmp/s.obj" "$sphere" --json -q > "$tmp/d.json" || fail "deviation"
[ "$(val hausdorff "$tmp/d.json")" = "$(val hausdorff "$tmp/s.json")" ] \
  || fail "deviation of the tessellation $(val hausdorff "$tmp/d.json"), smooth said $(val hausdorff "$tmp/s.json")"

# absolute tolerance: the same surface
"$bin" smooth "$sphere" -o "$tmp/a.step" --tolerance "$tol" --json -q > "$tmp/a.json" || fail "absolute"
[ "$(val patches "$tmp/a.json")" = "$p" ] || fail "--tolerance $tol: $(val patches "$tmp/a.json") patches, not $p"

# --full-search (the sphere's estimate is too fine: the default searches fully too, no level assumed)
"$bin" smooth "$sphere" -o "$tmp/f.step" --tolerance-rel 1e-2 --full-search --json -q > "$tmp/f.json" \
  || fail "--full-search"
[ "$(val patches "$tmp/f.json")" = "$p" ] || fail "--full-search: $(val patches "$tmp/f.json") patches, not $p"
[ "$(val level_assumed "$tmp/s.json")" = false ] || fail "level assumed on the sphere"
[ "$(val level_assumed "$tmp/f.json")" = false ] || fail "level assumed with --full-search"
[ "$(val levels_tried "$tmp/f.json")" = "$tried" ] || fail "--full-search tried other levels"
grep -q '"stalled_refinements": 0,' "$tmp/s.json" || fail "stalled_refinements"
grep -q '"offending_vertices": ' "$tmp/s.json" || fail "no offending_vertices in the rounds"

# the text summary
out=$("$bin" smooth "$sphere" -o "$tmp/t.step" --tolerance-rel 1e-2) || fail "text"
echo "$out" | grep -q "^smooth: $p patches (vc1) for 320 triangles, tolerance .* met; deviation max" \
  || fail "summary: $out"

# unreachable: exit 4, the file still written, stderr says so
rm -f "$tmp/u.step"
"$bin" smooth "$sphere" -o "$tmp/u.step" --tolerance-rel 1e-7 --json -q > "$tmp/u.json" 2> "$tmp/u.err"
rc=$?
[ $rc = 4 ] || fail "unreachable tolerance: exit $rc, not 4"
[ -s "$tmp/u.step" ] || fail "unreachable tolerance: no file written"
[ "$(val met "$tmp/u.json")" = false ] || fail "met true for 1e-7"
grep -q "not met" "$tmp/u.err" || fail "stderr: $(cat "$tmp/u.err")"

# usage errors
for args in "--tolerance 1 --tolerance-rel 1e-3" "--tolerance-rel 1e-3 --scheme pn" \
            "--refine-levels 2" "--full-search" "--stall-rounds 2" \
            "--tolerance-rel 1e-3 --stall-rounds 0" "--tolerance -1" "--tolerance-rel 2"; do
  # shellcheck disable=SC2086
  "$bin" smooth "$sphere" -o "$tmp/x.step" $args 2> /dev/null
  rc=$?
  [ $rc = 2 ] || fail "'$args': exit $rc, not 2"
done
echo OK
