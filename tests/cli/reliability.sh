#!/usr/bin/env bash
# Issue 17 (reliability) from the command line: inputs that are not regular files are refused at
# once with one line; smooth exits 4 when its own report fails; out-of-range coordinates are
# refused naming the range (each block names the defect).
set -u
bin=$1 src=$2 shared=$3 tmp=$4
rm -rf "$tmp"; mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }

# a FIFO as input used to block forever in open(); a directory is refused the same way
mkfifo "$tmp/f.off"
timeout 20 "$bin" info "$tmp/f.off" >/dev/null 2>"$tmp/err"; rc=$?
[ $rc -eq 1 ] || fail "FIFO input: exit $rc (124 = hang)"
[ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -q "not a regular file" "$tmp/err" || fail "FIFO message: $(cat "$tmp/err")"
timeout 20 "$bin" info "$tmp" >/dev/null 2>"$tmp/err"; rc=$?
[ $rc -eq 1 ] && grep -q "not a regular file" "$tmp/err" || fail "directory input: exit $rc"
rm -f "$tmp/f.off" "$tmp/err"

# smooth exited 0 when its own report failed (here: a thin strip, every patch singular): exit 4,
# the report is written, the surface only with --allow-fail; the summary says FAIL
awk 'BEGIN { n = 60; print "OFF"; print 2 * (n + 1), 2 * n, 0
  for (i = 0; i <= n; ++i) for (j = 0; j < 2; ++j) printf "%.17g %.17g %.17g\n", i, j * 1e-3, 0.3 * sin(i * 0.9)
  for (i = 0; i < n; ++i) { a = 2 * i; print 3, a, a + 2, a + 3; print 3, a, a + 3, a + 1 } }' >"$tmp/strip.off"
"$bin" smooth "$tmp/strip.off" -o "$tmp/strip.step" --report "$tmp/strip.json" 2>"$tmp/err"; rc=$?
[ $rc -eq 4 ] || fail "smooth failing its report: exit $rc, want 4"
[ ! -e "$tmp/strip.step" ] || fail "smooth failing its report wrote the surface"
[ -s "$tmp/strip.json" ] || fail "smooth failing its report did not write the report"
grep -q "report FAIL" "$tmp/err" || fail "summary does not say FAIL: $(cat "$tmp/err")"
grep -q "^surfkit: .*fails its continuity report.*singular patches 120" "$tmp/err" || fail "no error line: $(cat "$tmp/err")"
"$bin" smooth "$tmp/strip.off" -o "$tmp/strip.step" --allow-fail 2>"$tmp/err"; rc=$?
[ $rc -eq 0 ] && [ -s "$tmp/strip.step" ] || fail "--allow-fail: exit $rc, no file"
grep -q "report FAIL" "$tmp/err" || fail "--allow-fail summary does not say FAIL"
"$bin" smooth "$shared/data/meshes/sphere.off" -o "$tmp/sphere.step" 2>"$tmp/err"; rc=$?
[ $rc -eq 0 ] && grep -q "report pass" "$tmp/err" || fail "sphere: exit $rc, $(cat "$tmp/err")"
rm -f "$tmp"/strip.* "$tmp/sphere.step" "$tmp/err"

# coordinates at 1e100 gave "MIPS sum -nan" with exit 0, at 1e+-80 misleading failures: outside
# the supported range param and smooth refuse naming it; inside (1e-40, 1e40) they work
scaled() { awk -v s="$1" 'NR == 1 { print; next } NR == 2 { split($0, h, " "); nv = h[1]; print; next }
  NR <= nv + 2 { printf "%.17g %.17g %.17g\n", $1 * s, $2 * s, $3 * s; next } { print }' \
  "$shared/data/meshes/nefertiti.off" >"$tmp/scaled.off"; }
for s in 1e100 1e-100 1e80 1e-80; do
  scaled $s
  for m in mips lscm floater; do
    "$bin" param -q "$tmp/scaled.off" -o "$tmp/scaled.obj" --method $m 2>"$tmp/err"; rc=$?
    [ $rc -eq 1 ] && grep -q "supported" "$tmp/err" || fail "param $m at scale $s: exit $rc, $(cat "$tmp/err")"
  done
  "$bin" smooth -q "$tmp/scaled.off" -o "$tmp/scaled.step" 2>"$tmp/err"; rc=$?
  [ $rc -eq 1 ] && grep -q "supported" "$tmp/err" || fail "smooth at scale $s: exit $rc, $(cat "$tmp/err")"
done
for s in 1e40 1e-40; do
  scaled $s
  "$bin" param -q "$tmp/scaled.off" -o "$tmp/scaled.obj" --method mips --report "$tmp/r.json" \
    || fail "param mips at scale $s"
  grep -q '"flipped": 0' "$tmp/r.json" && ! grep -qi nan "$tmp/r.json" || fail "param mips at $s: $(head -c 300 "$tmp/r.json")"
done
rm -f "$tmp"/scaled.* "$tmp/r.json" "$tmp/err"

echo "reliability CLI: ok"
