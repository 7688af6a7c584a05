#!/bin/bash
# surfkit param --solver direct|hierarchical: accepted for the linear methods, rejected with mips
# or an unknown value. The shared disks are under the size where the hierarchy starts (40000
# vertices), so both give the same file here; the multilevel path itself is compared with the
# direct one in tests/unit/test_param_linear_hierarchical.c.
set -u
BIN=$1; SRC=$2; SHARED=$3; TMP=$4
M=$SHARED/data/meshes
rm -rf "$TMP"; mkdir -p "$TMP"
fail() { echo "FAIL: $*"; exit 1; }

for me in tutte floater lscm; do
    "$BIN" param "$M/mushroom.off" -o "$TMP/d-$me.obj" --method $me --solver direct -q || fail "$me direct"
    "$BIN" param "$M/mushroom.off" -o "$TMP/h-$me.obj" --method $me --solver hierarchical -q || fail "$me hierarchical"
    [ "$(grep -c '^vt ' "$TMP/h-$me.obj")" = 2337 ] || fail "$me vt count"
    cmp -s "$TMP/d-$me.obj" "$TMP/h-$me.obj" || fail "$me: hierarchical (solved directly) differs"
done
"$BIN" param "$M/mushroom.off" -o "$TMP/j.obj" --method harmonic --solver hierarchical --json > "$TMP/j.json" || fail "json run"
grep -q '"factor_nnz"' "$TMP/j.json" || fail "json"
# the whole process's stages: read (and mesh build) through write, each a time >= 0
python3 - "$TMP/j.json" <<'PY' || fail "stage seconds"
import json, sys
s = json.load(open(sys.argv[1]))["stage_seconds"]
keys = ["read", "check", "boundary", "weights_and_assembly", "analyse", "factor", "solve", "metrics", "write"]
assert list(s) == keys, list(s)
assert all(s[k] >= 0 for k in keys) and s["read"] > 0 and s["write"] > 0, s
PY
"$BIN" param "$M/mushroom.off" -o "$TMP/x.obj" --solver nope 2> "$TMP/err"; [ $? = 2 ] || fail "bad solver exit"
grep -q 'solver takes direct or hierarchical' "$TMP/err" || fail "bad solver message: $(cat "$TMP/err")"
"$BIN" param "$M/mushroom.off" -o "$TMP/x.obj" --method mips --solver direct 2> "$TMP/err"; [ $? = 2 ] || fail "mips + solver exit"
"$BIN" param --help | grep -q -- '--solver direct|hierarchical' || fail "help"
echo ok
