#!/usr/bin/env bash
# `surfkit deviation`: a mesh against itself and against its midpoint subdivision (the same
# surface) is at distance 0 (to rounding); against its Loop subdivision (a shrunk surface) the distance is
# positive and the same both ways round for the Hausdorff figure; --tolerance says within /
# EXCEEDED; JSON keys; pictures are PNGs; bad input exits 1 with one line naming the file,
# usage errors exit 2.
set -u
bin=$1 shared=$3 tmp=$4
rm -rf "$tmp"; mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
val() { grep "\"$1\": " "$2" | head -1 | sed 's/.*: //; s/,$//'; }
m=$shared/data/meshes

"$bin" deviation "$m/bunny00.off" "$m/bunny00.off" --json -q > "$tmp/self.json" || fail "self"
awk -v h="$(val hausdorff "$tmp/self.json")" -v d="$(val diagonal "$tmp/self.json")" \
  'BEGIN { exit !(h <= 1e-12 * d) }' || fail "bunny00 against itself is not at distance 0"
for key in input surface hausdorff hausdorff_rel diagonal mesh_to_surface surface_to_mesh \
           samples max mean rms max_at histogram seconds; do
  grep -q "\"$key\": " "$tmp/self.json" || fail "key $key"
done

"$bin" subdivide "$m/lion-head.off" -o "$tmp/mid.off" --scheme midpoint -q || fail "midpoint"
"$bin" deviation "$tmp/mid.off" "$m/lion-head.off" --json -q > "$tmp/mid.json" || fail "mid"
awk -v h="$(val hausdorff "$tmp/mid.json")" -v d="$(val diagonal "$tmp/mid.json")" \
  'BEGIN { exit !(h <= 1e-12 * d) }' || fail "midpoint subdivision moved the surface"

"$bin" subdivide "$m/lion-head.off" -o "$tmp/loop.off" -q || fail "loop"
"$bin" deviation "$tmp/loop.off" "$m/lion-head.off" --report "$tmp/a.json" -q > /dev/null || fail "a"
"$bin" deviation "$m/lion-head.off" "$tmp/loop.off" --report "$tmp/b.json" -q > /dev/null || fail "b"
ha=$(val hausdorff "$tmp/a.json") hb=$(val hausdorff "$tmp/b.json")
awk -v a="$ha" -v b="$hb" 'BEGIN { exit !(a > 0 && a == b) }' || fail "hausdorff $ha vs $hb"
out=$("$bin" deviation "$tmp/loop.off" "$m/lion-head.off" --tolerance "$ha" -q) || fail "tol"
echo "$out" | grep -q "within" || fail "tolerance equal to the distance: $out"
out=$("$bin" deviation "$tmp/loop.off" "$m/lion-head.off" --tolerance-rel 1e-9 -q \
      --png "$tmp/m.png" --png-surface "$tmp/s.png") || fail "tol-rel"
echo "$out" | grep -q "EXCEEDED" || fail "tiny tolerance: $out"
for p in m s; do
  [ "$(head -c 4 "$tmp/$p.png" | od -An -c | tr -d ' ')" = "211PNG" ] || fail "$p.png is not a PNG"
done

# bad input: one line naming the file, exit 1, no picture
printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n' > "$tmp/bad.off"
"$bin" deviation "$tmp/bad.off" "$m/cow.off" --png "$tmp/bad.png" -q > /dev/null 2> "$tmp/err"
rc=$?
[ $rc = 1 ] || fail "bad input exit $rc"
[ "$(wc -l < "$tmp/err")" = 1 ] || fail "bad input: $(cat "$tmp/err")"
grep -q "bad.off" "$tmp/err" || fail "error does not name the file: $(cat "$tmp/err")"
[ -e "$tmp/bad.png" ] && fail "picture written after an error"
"$bin" deviation "$m/cow.off" -q > /dev/null 2>&1; [ $? = 2 ] || fail "one file: not a usage error"
"$bin" deviation "$m/cow.off" "$m/cow.off" --samples 0 > /dev/null 2>&1
[ $? = 2 ] || fail "--samples 0"
"$bin" deviation --help | grep -q "^Examples:" || fail "help"
echo "deviation: ok"
