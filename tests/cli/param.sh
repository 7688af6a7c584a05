#!/bin/bash
# surfkit param: outputs, report, pictures, rejections, usage errors.
set -u
BIN=$1; SRC=$2; SHARED=$3; TMP=$4
M=$SHARED/data/meshes
rm -rf "$TMP"; mkdir -p "$TMP"
fail() { echo "FAIL: $*"; exit 1; }

"$BIN" param "$M/nefertiti.off" -o "$TMP/n.obj" --method floater --png "$TMP/n.png" \
    --svg "$TMP/n.svg" --checker "$TMP/c.png" --report "$TMP/r.json" -q || fail "floater run"
grep -q '^vt ' "$TMP/n.obj" || fail "no vt in OBJ"
grep -q '^f [0-9]*/[0-9]*' "$TMP/n.obj" || fail "faces are not v/vt"
[ "$(grep -c '^vt ' "$TMP/n.obj")" = 299 ] || fail "vt count"
head -c 8 "$TMP/n.png" | od -c | grep -q 'P   N   G' || fail "PNG signature"
head -c 8 "$TMP/c.png" | od -c | grep -q 'P   N   G' || fail "checker PNG signature"
grep -q '<svg' "$TMP/n.svg" || fail "SVG"
for k in faces flipped mips_sum mips_mean conformal_mean area_log_mean boundary_self_intersections seconds; do
    grep -q "\"$k\"" "$TMP/r.json" || fail "report lacks $k"
done
grep -q '"flipped": *0' "$TMP/r.json" || fail "flipped not 0"
"$BIN" param "$M/patch-01.off" -o "$TMP/p.ply" --method lscm --ascii -q || fail "lscm ply"
grep -q 'property double s' "$TMP/p.ply" || fail "PLY lacks s"
grep -q 'property double t' "$TMP/p.ply" || fail "PLY lacks t"
"$BIN" param "$M/patch-01.off" -o "$TMP/p.obj" --method harmonic --boundary square --json | grep -q '"boundary": "square"' || fail "json"

# the disk methods still refuse what is not a disk (without --method the atlas takes it: param_atlas.sh)
"$BIN" param "$M/eight.off" -o "$TMP/e.obj" --method floater 2> "$TMP/err"; rc=$?
[ $rc = 1 ] || fail "genus 2 exit code $rc"
grep -q 'closed surface of genus 2: cut it to a disk first' "$TMP/err" || fail "genus 2 message: $(cat "$TMP/err")"
[ -e "$TMP/e.obj" ] && fail "output left behind"
"$BIN" param "$M/holes.off" -o "$TMP/h.obj" --method floater 2> "$TMP/err"; [ $? = 1 ] || fail "holes exit"
grep -q '7 boundary loops' "$TMP/err" || fail "holes message"
"$BIN" param "$M/nefertiti.off" -o "$TMP/x.obj" --method nope 2>/dev/null; [ $? = 2 ] || fail "usage exit"
"$BIN" param "$M/nefertiti.off" 2>/dev/null; [ $? = 2 ] || fail "missing -o"
"$BIN" param --help | grep -q 'usage: surfkit param' || fail "help"
echo ok
