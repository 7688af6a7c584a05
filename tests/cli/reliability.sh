#!/usr/bin/env bash
# Issue 17 (reliability) from the command line: inputs that are not regular files are refused at
# once with one line, ... (each block names the defect it guards against).
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

echo "reliability CLI: ok"
