#!/usr/bin/env bash
# Hostile-input campaign (issue 17): crafted inputs over info / convert / param / smooth /
# simplify, outputs on hostile paths, signals during a large write, a failing --png after the
# main output. Prints the figures (inputs tried, clean errors, crashes, hangs, wrong successes,
# leftover files) and each defect found; exits 1 if there is any defect.
#
# usage: campaign.sh BIN SRC SHARED WORKDIR
#   clean error : non-zero exit (1, or 3 for out of memory) with exactly one stderr line
#                 "surfkit: ..." that names the file at fault
#   unnamed     : the same one line, but it does not name the file (listed, not a defect:
#                 messages about the mesh as a whole, e.g. its scale)
#   unclear     : anything else on a failure (several lines, no "surfkit:" prefix)
#   crash       : killed by a signal (exit >= 128, not one we sent)
#   hang        : still running after 60 s
#   wrong success: exit 0 where the input must be refused
#   leftover    : an output or temporary left behind by a run that failed or was killed
set -u
bin=$1 src=$2 shared=$3 w=$4
rm -rf "$w"; mkdir -p "$w/in" "$w/out"
cd "$w" || exit 2
tried=0 clean=0 unnamed=0 unclear=0 crash=0 hang=0 wrong=0 refused=0 left=0
log() { echo "  $*" >>"$w/defects"; }
: >"$w/defects"; : >"$w/unnamed"

# one EXPECT NAME OUT cmd...: EXPECT ok|err|any; NAME the file an error line must name; OUT the
# output the command writes ("" if none), which must not exist after a failure
one() {
  local expect=$1 name=$2 out=$3; shift 3
  tried=$((tried + 1))
  [ -n "$out" ] && rm -f "$out"
  timeout 60 "$@" >"$w/o.txt" 2>"$w/e.txt"; local rc=$?
  if [ $rc -eq 124 ]; then hang=$((hang + 1)); log "HANG: $*"; return; fi
  if [ $rc -ge 128 ]; then crash=$((crash + 1)); log "CRASH ($rc): $*"; return; fi
  if [ $rc -eq 0 ]; then
    if [ "$expect" = err ]; then wrong=$((wrong + 1)); log "WRONG SUCCESS: $*"; fi
    [ "$expect" = ok ] || [ "$expect" = any ] || true
    return
  fi
  if [ "$expect" = ok ]; then refused=$((refused + 1)); log "REFUSED GOOD INPUT ($rc): $* : $(head -c 200 "$w/e.txt")"; fi
  if [ -n "$out" ] && [ -e "$out" ]; then left=$((left + 1)); log "LEFTOVER $out: $*"; fi
  if [ "$(wc -l <"$w/e.txt")" -eq 1 ] && grep -q "^surfkit: " "$w/e.txt" &&
     grep -qF "$(basename "$name")" "$w/e.txt"; then
    clean=$((clean + 1))
  elif [ "$(wc -l <"$w/e.txt")" -eq 1 ] && grep -q "^surfkit: " "$w/e.txt"; then
    unnamed=$((unnamed + 1)); echo "  $(head -c 160 "$w/e.txt") [$*]" >>"$w/unnamed"
  else
    unclear=$((unclear + 1)); log "UNCLEAR ERROR ($rc): $* : $(head -c 300 "$w/e.txt" | tr '\n' '|')"
  fi
}

# every command over one input that must be refused (or, for info, reported)
all_cmds() {
  local info_expect=$1 f=$2 rest=${3:-err}
  one "$info_expect" "$f" "" "$bin" info "$f"
  one "$rest" "$f" out/c.ply "$bin" convert "$f" out/c.ply
  one "$rest" "$f" out/uv.obj "$bin" param -q "$f" -o out/uv.obj
  one "$rest" "$f" out/s.step "$bin" smooth -q "$f" -o out/s.step
  one "$rest" "$f" out/simp.obj "$bin" simplify -q "$f" -o out/simp.obj
}

# --- the bad-input corpus: every reader must refuse each file ---
for f in "$src"/tests/data/bad/*; do all_cmds err "$f"; done
# --- the good corpus: info and convert must accept each file ---
for f in "$src"/tests/data/good/*; do
  one ok "$f" "" "$bin" info "$f"
  one ok "$f" out/c.ply "$bin" convert "$f" out/c.ply
done

# --- crafted inputs ---
nef="$shared/data/meshes/nefertiti.off"
size=$(stat -c %s "$nef")
for pct in 1 10 50 90 99; do # truncated text
  head -c $((size * pct / 100)) "$nef" >in/trunc_$pct.off
  all_cmds err in/trunc_$pct.off
done
"$bin" convert "$nef" in/nef_bin.stl >/dev/null 2>&1
"$bin" convert "$nef" in/nef.ply >/dev/null 2>&1
for f in "$src"/tests/data/good/tet_binary_le.ply "$src"/tests/data/good/tet_binary.stl in/nef_bin.stl in/nef.ply; do
  s=$(stat -c %s "$f"); b=$(basename "$f"); ext=${b##*.}
  for cut in 7 $((s / 2)) $((s - 1)); do # truncated binary (and the last byte missing)
    head -c $cut "$f" >"in/trunc_${cut}_${b%.*}.$ext"
    all_cmds err "in/trunc_${cut}_${b%.*}.$ext"
  done
done
# bad counts: more and fewer vertices / faces than declared
awk 'NR == 2 { $1 = $1 + 5 } { print }' "$nef" >in/count_more_v.off
awk 'NR == 2 { $2 = $2 + 1 } { print }' "$nef" >in/count_more_f.off
awk 'NR == 2 { $1 = $1 - 5 } { print }' "$nef" >in/count_less_v.off
awk 'NR == 2 { $2 = $2 - 1 } { print }' "$nef" >in/count_less_f.off
for f in in/count_*.off; do all_cmds err "$f"; done
# NaN and inf coordinates
for v in nan inf -inf 1e999 NaN; do
  awk -v v=$v 'NR == 10 { $2 = v } { print }' "$nef" >in/value_$v.off
  all_cmds err in/value_$v.off
done
# huge headers
printf 'OFF\n4000000000 4000000000 0\n0 0 0\n' >in/huge.off
printf 'OFF\n3 1000000000000000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' >in/huge_overflow.off
printf 'ply\nformat binary_little_endian 1.0\nelement vertex 99999999999\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n' >in/huge.ply
printf 'solid x\n' >in/huge_ascii.stl
{ printf '%-80s' "binary"; printf '\xff\xff\xff\x7f'; } >in/huge_bin.stl
printf 'OFF\n3 1\n0 0 0\n1 0 0\n0 1 0\n4000000000 0 1 2\n' >in/huge_face.off
for f in in/huge*; do all_cmds err "$f"; done
# repeated vertices (the 38-byte crash) and a disk plus a face with a repeated vertex: info
# reports them, the geometry commands refuse them (convert copies the soup: either is fine)
printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2 0\n' >in/repeated4.off
printf 'OFF\n4 3 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n3 1 3 2\n3 0 0 1\n' >in/repeated_disk.off
printf 'OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 2\n' >in/duplicate_face.off
for f in in/repeated4.off in/repeated_disk.off in/duplicate_face.off; do
  one ok "$f" "" "$bin" info "$f"
  one any "$f" out/c.ply "$bin" convert "$f" out/c.ply
  one err "$f" out/uv.obj "$bin" param -q "$f" -o out/uv.obj
  one err "$f" out/s.step "$bin" smooth -q "$f" -o out/s.step
  one any "$f" out/simp.obj "$bin" simplify -q "$f" -o out/simp.obj
done
# not regular files: a FIFO (used to hang in open) and a directory
mkfifo in/fifo.off; mkdir -p in/dir.off
all_cmds err in/fifo.off
all_cmds err in/dir.off
one err in/missing.off "" "$bin" info in/missing.off
# outputs on hostile paths: /dev/full through a symlink (the reason must be given), a missing
# directory, a directory as output
ln -s /dev/full out/full.obj
one err out/full.obj "" "$bin" convert "$nef" out/full.obj
grep -q "No space left on device" "$w/e.txt" || { unclear=$((unclear + 1)); log "NO REASON on /dev/full: $(cat "$w/e.txt")"; }
[ -L out/full.obj ] || { left=$((left + 1)); log "/dev/full link replaced"; }
for e in step igs obj; do # the CAD writers and the tessellation, and the side outputs
  ln -s /dev/full out/full_s.$e
  one err out/full_s.$e "" "$bin" smooth -q "$shared/data/meshes/sphere.off" -o out/full_s.$e
  grep -q "No space left on device" "$w/e.txt" || { unclear=$((unclear + 1)); log "NO REASON on /dev/full ($e): $(cat "$w/e.txt")"; }
done
ln -s /dev/full out/full_r.json
one err out/full_r.json out/ok.step "$bin" smooth -q "$shared/data/meshes/sphere.off" -o out/ok.step --report out/full_r.json
grep -q "No space left on device" "$w/e.txt" || { unclear=$((unclear + 1)); log "NO REASON on /dev/full (report): $(cat "$w/e.txt")"; }
ln -s /dev/full out/full.png
one err out/full.png out/uv.obj "$bin" param -q "$nef" -o out/uv.obj --png out/full.png
one err out/nodir/x.obj out/nodir/x.obj "$bin" convert "$nef" out/nodir/x.obj
mkdir -p out/isdir.obj
one err out/isdir.obj "" "$bin" convert "$nef" out/isdir.obj
# scale: outside the supported range every algorithm refuses naming it; info still reports
for sc in 1e100 1e-100 1e80 1e-80; do
  awk -v s=$sc 'NR == 1 { print; next } NR == 2 { split($0, h, " "); nv = h[1]; print; next }
    NR <= nv + 2 { printf "%.17g %.17g %.17g\n", $1 * s, $2 * s, $3 * s; next } { print }' "$nef" >in/scale_$sc.off
  f=in/scale_$sc.off
  one ok "$f" "" "$bin" info "$f"
  for m in mips lscm floater; do
    one err "$f" out/uv.obj "$bin" param -q "$f" -o out/uv.obj --method $m
    grep -q "supported" "$w/e.txt" || log "scale $sc param $m: message does not name the range: $(cat "$w/e.txt")"
  done
  one err "$f" out/s.step "$bin" smooth -q "$f" -o out/s.step
  one err "$f" out/simp.obj "$bin" simplify -q "$f" -o out/simp.obj --report out/simp.json
done
# a failing --png after the main output: nothing of the command may remain
one err out/nodir/uv.png out/uv.obj "$bin" param -q "$nef" -o out/uv.obj --png out/nodir/uv.png
one err out/nodir/l.png out/s.step "$bin" smooth -q "$shared/data/meshes/sphere.off" -o out/s.step --layout out/nodir/l.png
one err out/nodir/r.json out/simp.obj "$bin" simplify -q "$nef" -o out/simp.obj --report out/nodir/r.json
# signals during a large write: no temporary, no partial output; the older file intact, or the
# whole new one when the signal came after the output was committed (renamed into place) but
# before the process ended (its cleanup is slow under ASan)
"$bin" subdivide -q "$shared/data/meshes/sphere.off" -n 5 -o in/base.ply
"$bin" convert in/base.ply "$w/complete.obj"
echo "old content" >out/keep.obj
for sig in KILL TERM INT HUP; do
  for delay in 0.1 0.3 0.6; do
    tried=$((tried + 1))
    cp out/keep.obj out/big.obj
    "$bin" convert in/base.ply out/big.obj & pid=$!
    sleep $delay; kill -$sig $pid 2>/dev/null; wait $pid 2>/dev/null; rc=$?
    if [ $rc -eq 0 ]; then # finished before the signal: must be complete
      tail -1 out/big.obj | grep -q '^f ' || { wrong=$((wrong + 1)); log "signal $sig after $delay s: exit 0 with a partial file"; }
    else
      cmp -s out/keep.obj out/big.obj || cmp -s "$w/complete.obj" out/big.obj ||
        { left=$((left + 1)); log "signal $sig after $delay s: neither the old output nor the whole new one"; }
    fi
    n=$(ls out | grep -c tmp)
    [ "$n" -eq 0 ] || { left=$((left + n)); log "signal $sig after $delay s: temporaries $(ls out | grep tmp | tr '\n' ' ')"; rm -f out/*tmp*; }
  done
done
# debris anywhere from all of the above
n=$(find "$w/out" "$w/in" -name '*tmp*' | wc -l)
[ "$n" -eq 0 ] || { left=$((left + n)); log "temporaries left: $(find "$w" -name '*tmp*' | head -5)"; }

echo "campaign: inputs tried $tried, clean errors $clean, errors not naming the file $unnamed, unclear errors $unclear, crashes $crash, hangs $hang, wrong successes $wrong, good inputs refused $refused, leftover files $left"
cat "$w/defects"
[ $unnamed -eq 0 ] || { echo " errors not naming the file:"; sort -u "$w/unnamed" | head -20; }
bad=$((unclear + crash + hang + wrong + refused + left))
cd / && rm -rf "$w"
[ $bad -eq 0 ]
