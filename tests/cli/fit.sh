#!/usr/bin/env bash
# `surfkit fit`: the paraboloid disk within 1e-3 of its diagonal as STEP (one
# B_SPLINE_SURFACE_WITH_KNOTS with the grid the summary names, in one face of an open shell) and
# IGES (one entity 128 whose K1, K2 are the grid's); the JSON figures are consistent (tolerance
# met, deviation within it); its tessellation read back by `surfkit deviation` gives the same
# deviation; --corners are used; not meeting the tolerance exits 4 and still writes; a closed
# mesh or several boundary loops exit 1 with one line pointing to param --atlas / smooth; usage
# errors exit 2.
set -u
bin=$1 shared=$3 tmp=$4
rm -rf "$tmp"; mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
val() { grep "\"$1\": " "$2" | head -1 | sed 's/.*: //; s/,$//'; }
m=$shared/data/meshes

"$bin" fit "$m/paraboloid-patch.off" -o "$tmp/p.step" --tessellation "$tmp/p.obj" --json \
  > "$tmp/p.json" || fail "paraboloid step"
nu=$(val nu "$tmp/p.json") nv=$(val nv "$tmp/p.json") tol=$(val tolerance "$tmp/p.json")
[ "$(val met "$tmp/p.json")" = true ] || fail "tolerance not met"
awk -v t="$tol" -v d="$(val diagonal "$tmp/p.json")" 'BEGIN { exit !(t > 0.99e-3 * d && t < 1.01e-3 * d) }' \
  || fail "default tolerance $tol is not 1e-3 of the diagonal"
awk -v h="$(val hausdorff "$tmp/p.json")" -v t="$tol" -v c="$(val tessellation_chord_bound "$tmp/p.json")" \
  'BEGIN { exit !(h > 0 && h <= t + c) }' || fail "deviation $(val hausdorff "$tmp/p.json") beyond $tol"
[ "$(grep -c 'B_SPLINE_SURFACE_WITH_KNOTS' "$tmp/p.step")" = 1 ] || fail "not one B-spline surface"
for e in ADVANCED_FACE OPEN_SHELL SHELL_BASED_SURFACE_MODEL; do
  [ "$(grep -c "=$e(" "$tmp/p.step")" = 1 ] || fail "STEP has not one $e"
done
[ "$(grep -c '=EDGE_CURVE(' "$tmp/p.step")" = 4 ] || fail "STEP face has not 4 edges"
rows=$(grep 'B_SPLINE_SURFACE_WITH_KNOTS' "$tmp/p.step" | sed 's/.*,3,3,((//; s/)),.*//' | awk -F'),\\(' '{print NF}')
[ "$rows" = "$nu" ] || fail "STEP surface has $rows rows of control points, summary $nu"
"$bin" deviation "$tmp/p.obj" "$m/paraboloid-patch.off" --json -q > "$tmp/pd.json" || fail "deviation"
[ "$(val hausdorff "$tmp/pd.json")" = "$(val hausdorff "$tmp/p.json")" ] \
  || fail "deviation of the tessellation $(val hausdorff "$tmp/pd.json"), fit said $(val hausdorff "$tmp/p.json")"

out=$("$bin" fit "$m/paraboloid-patch.off" -o "$tmp/p.igs") || fail "paraboloid iges"
echo "$out" | grep -q "control points" || fail "summary: $out"
head -c 80 "$tmp/p.igs" | grep -q "S      1$" || fail "IGES start record"
p1=$(grep -m1 'P      1$' "$tmp/p.igs" | cut -c1-64)
[ "${p1%%,*}" = 128 ] || fail "IGES entity is not 128: $p1"
k=$(echo "$p1" | cut -d, -f2,3)
[ "$k" = "$((nu - 1)),$((nv - 1))" ] || fail "IGES K1,K2 $k, grid $nu x $nv"
[ "$(grep -c 'D      [0-9]*$' "$tmp/p.igs")" = 2 ] || fail "IGES has not one entity"

# corners given: the ones found, given back, are used and give the same surface (at 1e-2: at the
# default 1e-3 patch-01 refines up to the cap, twice the vertices, over three maps)
"$bin" fit "$m/patch-01.off" -o "$tmp/c.step" --tolerance-rel 1e-2 --json > "$tmp/auto.json" 2> /dev/null
rc=$?
[ $rc = 0 ] || [ $rc = 4 ] || fail "patch-01 exit $rc"
corners=$(tr -d ' \n' < "$tmp/auto.json" | sed 's/.*"corners":\[\([0-9,]*\)\].*/\1/')
"$bin" fit "$m/patch-01.off" -o "$tmp/c2.step" --tolerance-rel 1e-2 --corners "$corners" --json > "$tmp/given.json" 2> /dev/null
[ "$(tr -d ' \n' < "$tmp/given.json" | sed 's/.*"corners":\[\([0-9,]*\)\].*/\1/')" = "$corners" ] \
  || fail "--corners $corners not used"
[ "$(val control_points "$tmp/given.json")" = "$(val control_points "$tmp/auto.json")" ] \
  || fail "the same corners gave another surface"

# a ragged disk (cut from bunny00): the dividing edges are split, the square map flips nothing;
# --method mips runs too and flips nothing (the maps themselves: --area-theta 0, no balance;
# the fit over them capped at 100 control points: its refinement is tested elsewhere)
python3 "$2/tests/cli/cut_disk.py" "$m/bunny00.off" "$tmp/rag.off" 4000 0 || fail "cut"
for meth in floater mips; do
  "$bin" fit "$tmp/rag.off" -o "$tmp/rag.step" --method $meth --area-theta 0 --max-control-points 100 \
    --json > "$tmp/rag.json" 2> /dev/null
  rc=$?
  [ $rc = 0 ] || [ $rc = 4 ] || fail "ragged $meth: exit $rc"
  [ "$(val flipped "$tmp/rag.json")" = 0 ] || fail "ragged $meth: $(val flipped "$tmp/rag.json") flipped"
  [ "$(val split_edges "$tmp/rag.json")" -gt 0 ] || fail "ragged $meth: no edge split"
  [ "$(val method "$tmp/rag.json")" = "\"$meth\"" ] || fail "ragged: method $(val method "$tmp/rag.json")"
done

# the cone of mask_cone, cut open along a line (the bench's disk): its map crowds the data near
# the cut, where the surface can wiggle between the points of the fit's coarse check. With the
# map's areas balanced (--area-theta 1) it is met at 1e-2 with fewer control points than
# without; "met" (and exit 0) holds for the deviation the summary reports, not only for the
# fit's own grid (it claimed 1e-2 at a Hausdorff distance of 0.029 before the dense check);
# the default (the map chosen among theta 1, 0.5 and none) needs no more than theta 1
in=$m/mask_cone.off
python3 "$2/tests/cli/cut_disk.py" "$in" "$tmp/cone.off" "$(sed -n 2p "$in" | cut -d' ' -f2)" \
  "$(( $(sed -n 2p "$in" | cut -d' ' -f1) - 1 ))" || fail "cut cone"
for th in 0 1 auto; do
  args=(--area-theta "$th"); [ $th = auto ] && args=()
  "$bin" fit "$tmp/cone.off" -o "$tmp/cone.step" --tolerance-rel 1e-2 "${args[@]}" --json \
    > "$tmp/cone$th.json" 2> /dev/null
  rc=$?
  met=$(val met "$tmp/cone$th.json")
  { [ $rc = 0 ] && [ "$met" = true ]; } || { [ $rc = 4 ] && [ "$met" = false ]; } \
    || fail "cone theta $th: exit $rc with met $met"
  awk -v h="$(val hausdorff_rel "$tmp/cone$th.json")" -v met="$met" \
    'BEGIN { exit !((met == "true") == (h <= 1e-2)) }' \
    || fail "cone theta $th: met $met at Hausdorff $(val hausdorff_rel "$tmp/cone$th.json") of the diagonal"
done
[ "$(val met "$tmp/cone1.json")" = true ] || fail "balanced cone not within 1e-2"
# the default tries the maps (theta 1, 0.5, none) and keeps the fewest control points within T
[ "$(val met "$tmp/coneauto.json")" = true ] || fail "automatic map: cone not within 1e-2"
[ "$(val area_theta_auto "$tmp/coneauto.json")" = true ] || fail "automatic map not the default"
[ "$(val area_theta_auto "$tmp/cone1.json")" = false ] || fail "--area-theta 1 is not forced"
[ "$(val control_points "$tmp/coneauto.json")" -le "$(val control_points "$tmp/cone1.json")" ] \
  || fail "automatic map: $(val control_points "$tmp/coneauto.json") control points, theta 1 $(val control_points "$tmp/cone1.json")"
[ "$(val control_points "$tmp/cone1.json")" -lt "$(val control_points "$tmp/cone0.json")" ] \
  || fail "balanced cone: $(val control_points "$tmp/cone1.json") control points, unbalanced $(val control_points "$tmp/cone0.json")"
"$bin" fit "$tmp/cone.off" -o "$tmp/cone.step" --area-theta -1 > /dev/null 2>&1
[ $? = 2 ] || fail "--area-theta -1 is not a usage error"

# a tolerance that cannot be met: exit 4, the file is written, stderr says so
"$bin" fit "$m/nefertiti.off" -o "$tmp/n.step" --tolerance-rel 1e-6 --area-theta 0 -q 2> "$tmp/n.err"
[ $? = 4 ] || fail "unmet tolerance does not exit 4"
[ -s "$tmp/n.step" ] || fail "unmet tolerance wrote no file"
grep -q "not met" "$tmp/n.err" || fail "no 'not met' message: $(cat "$tmp/n.err")"

# --max-control-points caps the grid: the paraboloid within 1e-3 needs more than 49, so the
# capped fit exits 4 with at most 49; --smoothing fixes the thin-plate weight (one fit per round)
"$bin" fit "$m/paraboloid-patch.off" -o "$tmp/cap.step" --max-control-points 49 --json \
  > "$tmp/cap.json" 2> /dev/null
[ $? = 4 ] || fail "--max-control-points 49 does not exit 4"
[ "$(val control_points "$tmp/cap.json")" -le 49 ] || fail "cap 49: $(val control_points "$tmp/cap.json") control points"
"$bin" fit "$m/paraboloid-patch.off" -o "$tmp/w.step" --smoothing 1e-4 --area-theta 1 --json \
  > "$tmp/w.json" || fail "--smoothing 1e-4"
[ "$(val met "$tmp/w.json")" = true ] || fail "--smoothing 1e-4: not met"

for bad in sphere lion; do
  "$bin" fit "$m/$bad.off" -o "$tmp/b.step" 2> "$tmp/b.err"
  [ $? = 1 ] || fail "$bad: not exit 1"
  [ "$(wc -l < "$tmp/b.err")" = 1 ] || fail "$bad: not one line: $(cat "$tmp/b.err")"
  grep -q "param --atlas" "$tmp/b.err" && grep -q "surfkit smooth" "$tmp/b.err" \
    || fail "$bad: no pointer to the atlas / smooth: $(cat "$tmp/b.err")"
  [ ! -e "$tmp/b.step" ] || fail "$bad: wrote a file"
done

for args in "" "$m/nefertiti.off" "$m/nefertiti.off -o x.txt" "$m/nefertiti.off -o x.step --degree 9" \
            "$m/nefertiti.off -o x.step --corners 1,2,3" "$m/nefertiti.off -o x.step --tolerance -1" \
            "$m/nefertiti.off -o x.step --tolerance 1 --tolerance-rel 0.1" "$m/nefertiti.off -o x.step --bogus" \
            "$m/nefertiti.off -o x.step --smoothing 0" "$m/nefertiti.off -o x.step --max-control-points 3"; do
  # shellcheck disable=SC2086
  (cd "$tmp" && "$bin" fit $args > /dev/null 2>&1)
  [ $? = 2 ] || fail "usage error not exit 2: fit $args"
done
"$bin" fit --help | grep -q "usage: surfkit fit" || fail "--help"
echo ok
