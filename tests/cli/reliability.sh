#!/usr/bin/env bash
# Issue 17 (reliability) from the command line: inputs that are not regular files are refused at
# once with one line; smooth exits 4 when its own report fails (each block names the defect).
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

echo "reliability CLI: ok"
