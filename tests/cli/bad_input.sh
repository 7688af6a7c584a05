#!/usr/bin/env bash
# Every file of tests/data/bad: `surfkit info` and `surfkit convert` exit 1 with one line on stderr
# that names the file, and convert leaves no output file (nor a temporary) behind.
set -u
bin=$1 src=$2 tmp=$4
rm -rf "$tmp"; mkdir -p "$tmp"
n=0 bad=0
for f in "$src"/tests/data/bad/*; do
  [ -f "$f" ] || continue
  n=$((n + 1))
  name=$(basename "$f")
  "$bin" info "$f" >/dev/null 2>"$tmp/err"; rc=$?
  lines=$(wc -l <"$tmp/err")
  if [ $rc -ne 1 ] || [ "$lines" -ne 1 ] || ! grep -q "^surfkit: $name" "$tmp/err"; then
    echo "FAIL info $name: exit $rc, $lines stderr lines: $(head -c 300 "$tmp/err")"; bad=$((bad + 1))
  fi
  "$bin" convert "$f" "$tmp/out.ply" >/dev/null 2>"$tmp/err"; rc=$?
  if [ $rc -ne 1 ] || [ -n "$(ls "$tmp" | grep -v '^err$')" ]; then
    echo "FAIL convert $name: exit $rc, left: $(ls "$tmp" | tr '\n' ' ')"; bad=$((bad + 1))
    rm -f "$tmp"/out.ply*
  fi
done
echo "bad-input corpus: $n files, $bad failures"
[ $n -ge 20 ] || { echo "FAIL: expected at least 20 bad files"; exit 1; }
[ $bad -eq 0 ]
