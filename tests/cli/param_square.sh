#!/usr/bin/env bash
# `surfkit param --boundary square` on a disk with a ragged boundary (4,000 triangles cut from
# bunny00, tests/cli/cut_disk.py): no flipped triangle with tutte, floater and mvc (the
# dividing edges are split and reported on stderr, the output gains those vertices); a clean
# shared disk gets no split.
set -u
bin=$1 src=$2 shared=$3 tmp=$4
rm -rf "$tmp"; mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
val() { grep "\"$1\": " "$2" | head -1 | sed 's/.*: //; s/,$//'; }
python3 "$src/tests/cli/cut_disk.py" "$shared/data/meshes/bunny00.off" "$tmp/disk.off" 4000 0 || fail "cut"
for method in tutte floater mvc; do
  "$bin" param "$tmp/disk.off" -o "$tmp/uv.obj" --method $method --boundary square --json \
    > "$tmp/$method.json" 2> "$tmp/$method.err" || fail "$method: $(cat "$tmp/$method.err")"
  [ "$(val flipped "$tmp/$method.json")" = 0 ] || fail "$method: $(val flipped "$tmp/$method.json") flipped"
  n=$(sed -n 's/.*split \([0-9]*\) interior edges.*/\1/p' "$tmp/$method.err")
  [ -n "$n" ] && [ "$n" -gt 0 ] || fail "$method: no split reported: $(cat "$tmp/$method.err")"
  [ "$(grep -c '^v ' "$tmp/uv.obj")" = $(( $(sed -n 2p "$tmp/disk.off" | cut -d' ' -f1) + n )) ] \
    || fail "$method: output vertices are not input + $n"
done
"$bin" param "$shared/data/meshes/patch-01.off" -o "$tmp/p.obj" --method floater --boundary square \
  --json > "$tmp/p.json" 2> "$tmp/p.err" || fail "patch-01"
[ ! -s "$tmp/p.err" ] || fail "patch-01: $(cat "$tmp/p.err")"
[ "$(val flipped "$tmp/p.json")" = 0 ] || fail "patch-01 flipped"
echo ok
