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
"$bin" smooth "$tmp/strip.off" -o "$tmp/strip.step" --report "$tmp/strip.json" >"$tmp/out" 2>"$tmp/err"; rc=$?
[ $rc -eq 4 ] || fail "smooth failing its report: exit $rc, want 4"
[ ! -e "$tmp/strip.step" ] || fail "smooth failing its report wrote the surface"
[ -s "$tmp/strip.json" ] || fail "smooth failing its report did not write the report"
grep -q "report FAIL" "$tmp/out" || fail "summary (stdout) does not say FAIL: $(cat "$tmp/out")"
grep -q "^surfkit: .*fails its continuity report.*singular patches 120" "$tmp/err" || fail "no error line: $(cat "$tmp/err")"
"$bin" smooth "$tmp/strip.off" -o "$tmp/strip.step" --allow-fail >"$tmp/out" 2>"$tmp/err"; rc=$?
[ $rc -eq 0 ] && [ -s "$tmp/strip.step" ] || fail "--allow-fail: exit $rc, no file"
grep -q "report FAIL" "$tmp/out" || fail "--allow-fail summary does not say FAIL"
"$bin" smooth "$shared/data/meshes/sphere.off" -o "$tmp/sphere.step" >"$tmp/out" 2>"$tmp/err"; rc=$?
[ $rc -eq 0 ] && grep -q "report pass" "$tmp/out" || fail "sphere: exit $rc, $(cat "$tmp/out" "$tmp/err")"
rm -f "$tmp"/strip.* "$tmp/sphere.step" "$tmp/err" "$tmp/out"

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
  # simplify exited 0 here with no level made (every collapse rejected)
  "$bin" simplify -q "$tmp/scaled.off" -o "$tmp/scaled.obj" 2>"$tmp/err"; rc=$?
  [ $rc -eq 1 ] && grep -q "supported" "$tmp/err" || fail "simplify at scale $s: exit $rc, $(cat "$tmp/err")"
done
for s in 1e40 1e-40; do
  scaled $s
  "$bin" simplify -q "$tmp/scaled.off" -o "$tmp/scaled.obj" --faces 1 --report "$tmp/r.json" || fail "simplify at scale $s"
  grep -q '"num_levels": 18' "$tmp/r.json" || fail "simplify at scale $s: $(grep num_levels "$tmp/r.json")"
  "$bin" param -q "$tmp/scaled.off" -o "$tmp/scaled.obj" --method mips --report "$tmp/r.json" \
    || fail "param mips at scale $s"
  grep -q '"flipped": 0' "$tmp/r.json" && ! grep -qi nan "$tmp/r.json" || fail "param mips at $s: $(head -c 300 "$tmp/r.json")"
done
rm -f "$tmp"/scaled.* "$tmp/r.json" "$tmp/err"

# output files: one writer for everything (core/atomic_file.c)
tet="$src/tests/data/good/quads.off"
# a symlinked output stays a link and its target is written
echo old >"$tmp/real.off"; ln -s real.off "$tmp/link.off"
"$bin" convert "$tet" "$tmp/link.off" || fail "convert to a symlink"
[ -L "$tmp/link.off" ] && head -1 "$tmp/real.off" | grep -q OFF || fail "symlink replaced or target not written"
# a hard-linked output is written in place: every name sees the new content (a rename gave only
# the named one the new content), same inode, mode kept; also inside a command's batch (param)
echo old >"$tmp/hard_a.off"; ln "$tmp/hard_a.off" "$tmp/hard_b.off"; chmod 0640 "$tmp/hard_a.off"
ino=$(stat -c %i "$tmp/hard_a.off")
"$bin" convert "$tet" "$tmp/hard_a.off" || fail "convert to a hard-linked file"
cmp -s "$tmp/hard_a.off" "$tmp/hard_b.off" && head -1 "$tmp/hard_b.off" | grep -q OFF \
  || fail "hard link: the other name kept the old content"
[ "$(stat -c %i:%h:%a "$tmp/hard_a.off")" = "$ino:2:640" ] || fail "hard link: $(stat -c %i:%h:%a "$tmp/hard_a.off"), want $ino:2:640"
"$bin" convert "$tet" "$tmp/hard_ref.off" || fail "convert reference"
cmp -s "$tmp/hard_ref.off" "$tmp/hard_b.off" || fail "hard link: content differs from a plain write"
printf 'old longer content than the new file will have %.0s\n' $(seq 1 2000) >"$tmp/hard_c.obj"
ln "$tmp/hard_c.obj" "$tmp/hard_d.obj"
"$bin" param -q "$shared/data/meshes/nefertiti.off" -o "$tmp/hard_c.obj" --report "$tmp/hard_r.json" || fail "param to a hard link"
"$bin" param -q "$shared/data/meshes/nefertiti.off" -o "$tmp/hard_ref.obj" || fail "param reference"
cmp -s "$tmp/hard_ref.obj" "$tmp/hard_d.obj" || fail "hard link in a batch: other name not rewritten (or not truncated)"
ls "$tmp" | grep -q tmp && fail "hard-link writes left temporaries: $(ls "$tmp" | grep tmp)"
rm -f "$tmp"/hard_*
# an existing file keeps its mode; a new one gets 0666 minus the umask (mkstemp made 0600)
chmod 0664 "$tmp/real.off"
"$bin" convert "$tet" "$tmp/real.off" || fail "convert over a 0664 file"
[ "$(stat -c %a "$tmp/real.off")" = 664 ] || fail "existing mode lost: $(stat -c %a "$tmp/real.off")"
( umask 022; "$bin" convert "$tet" "$tmp/new1.off" ) && [ "$(stat -c %a "$tmp/new1.off")" = 644 ] \
  || fail "umask 022: mode $(stat -c %a "$tmp/new1.off")"
( umask 007; "$bin" convert "$tet" "$tmp/new2.off" ) && [ "$(stat -c %a "$tmp/new2.off")" = 660 ] \
  || fail "umask 007: mode $(stat -c %a "$tmp/new2.off")"
# devices and pipes are written directly: a link to /proc/self/fd/1 writes to stdout
ln -s /proc/self/fd/1 "$tmp/stdout.off"
"$bin" convert "$tet" "$tmp/stdout.off" >"$tmp/captured" || fail "convert to /proc/self/fd/1"
[ -L "$tmp/stdout.off" ] && head -1 "$tmp/captured" | grep -q OFF || fail "stdout link replaced or nothing written"
# a full disk says why, even behind a path longer than the 256-byte message field
long="$tmp/$(printf 'd%.0s' $(seq 1 200))"; mkdir -p "$long"; ln -s /dev/full "$long/full.off"
"$bin" convert "$tet" "$long/full.off" 2>"$tmp/err"; rc=$?
[ $rc -eq 1 ] && grep -q "No space left on device" "$tmp/err" || fail "/dev/full: exit $rc, $(cat "$tmp/err")"
[ -L "$long/full.off" ] || fail "/dev/full link replaced"
# ... also when the disk fills in the middle of a large write (the buffer's flush lost errno)
"$bin" convert "$shared/data/meshes/nefertiti.off" "$long/full.off" 2>"$tmp/err"; rc=$?
[ $rc -eq 1 ] && grep -q "write failed: No space left on device" "$tmp/err" || fail "/dev/full, large: exit $rc, $(cat "$tmp/err")"
rm -rf "$long"
# a command that fails leaves none of its outputs (param wrote uv.obj before the --png failed)
"$bin" param -q "$shared/data/meshes/nefertiti.off" -o "$tmp/uv.obj" --png "$tmp/nodir/uv.png" 2>/dev/null
[ $? -eq 1 ] || fail "param with an unwritable --png should exit 1"
[ ! -e "$tmp/uv.obj" ] || fail "param left uv.obj behind after its --png failed"
# interrupted writes leave no temporary (O_TMPFILE; named fallback removed by the handler)
"$bin" subdivide -q "$shared/data/meshes/sphere.off" -n 5 -o "$tmp/base.ply" || fail "subdivide"
for sig in KILL TERM INT HUP; do
  "$bin" convert "$tmp/base.ply" "$tmp/big_$sig.obj" & pid=$!
  sleep 0.3; kill -$sig $pid 2>/dev/null; wait $pid 2>/dev/null
done
left=$(ls "$tmp" | grep -c 'tmp' || true)
[ "$left" -eq 0 ] || fail "interrupted writes left temporaries: $(ls "$tmp" | grep tmp)"
# two processes writing the same report at once never share a temporary name
ok=0
for k in 1 2 3 4 5; do
  "$bin" simplify -q "$shared/data/meshes/nefertiti.off" -o "$tmp/s1.obj" --report "$tmp/r.json" & p1=$!
  "$bin" simplify -q "$shared/data/meshes/nefertiti.off" -o "$tmp/s2.obj" --report "$tmp/r.json" & p2=$!
  wait $p1 && wait $p2 && ok=$((ok + 1))
done
[ $ok -eq 5 ] || fail "concurrent simplify runs with one --report: $ok of 5 pairs succeeded"
python3 -c "import json,sys; json.load(open(sys.argv[1]))" "$tmp/r.json" || fail "report not valid JSON"
rm -f "$tmp"/*.off "$tmp"/*.obj "$tmp"/*.ply "$tmp/r.json" "$tmp/captured" "$tmp/err"

echo "reliability CLI: ok"
