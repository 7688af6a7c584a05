#!/bin/bash
# surfkit param --solver auto|direct|hierarchical|amg: accepted for the linear methods, rejected with
# mips or an unknown value. The shared disks are under the size where the hierarchy starts (40000
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
# amg on the lion head Loop-subdivided once (about 33k vertices, coarsest level at most 3000
# unknowns): three or more levels, converged, the direct uv to 1e-8 and the same flips
"$BIN" subdivide "$M/lion-head.off" -o "$TMP/lion1.off" -n 1 -q || fail "subdivide"
for me in floater harmonic; do
    "$BIN" param "$TMP/lion1.off" -o "$TMP/d-$me.obj" --method $me --json > "$TMP/d.json" || fail "$me direct"
    "$BIN" param "$TMP/lion1.off" -o "$TMP/a-$me.obj" --method $me --solver amg --json > "$TMP/a.json" || fail "$me amg"
    python3 - "$TMP/d.json" "$TMP/a.json" "$TMP/d-$me.obj" "$TMP/a-$me.obj" <<'PY' || fail "$me amg against direct"
import json, sys
d, a = (json.load(open(p)) for p in sys.argv[1:3])
s = a["solver"]
assert s["levels"] >= 3 and s["iterations"] >= 1 and s["residual"] <= 1e-12, s
assert d["solver"]["levels"] == 0 and d["solver"]["iterations"] == 0, d["solver"]
assert a["flipped"] == d["flipped"], (a["flipped"], d["flipped"])
vt = [[tuple(map(float, l.split()[1:3])) for l in open(p) if l.startswith("vt ")] for p in sys.argv[3:5]]
assert len(vt[0]) == len(vt[1]) > 10000
diff = max(max(abs(x[0] - y[0]), abs(x[1] - y[1])) for x, y in zip(*vt))
assert diff <= 1e-8, diff  # the uv are normalized to the unit square
PY
done
# --solver auto (the default): amg from --amg-from free vertices up, direct below and for lscm
# by default (the lion head Loop x1: 33k vertices, under the default crossover); the report
# says which ran (solver.route), its iterations and residual
for me in floater lscm; do
    "$BIN" param "$TMP/lion1.off" -o "$TMP/d.obj" --method $me --json > "$TMP/d.json" || fail "$me auto"
    "$BIN" param "$TMP/lion1.off" -o "$TMP/a.obj" --method $me --amg-from 20000 --json > "$TMP/a.json" || fail "$me auto amg"
    "$BIN" param "$TMP/lion1.off" -o "$TMP/e.obj" --method $me --solver direct --amg-from 20000 --json > "$TMP/e.json" || fail "$me direct"
    python3 - "$TMP/d.json" "$TMP/a.json" "$TMP/e.json" "$TMP/d.obj" "$TMP/a.obj" <<'PY' || fail "$me auto route"
import json, sys
d, a, e = (json.load(open(p))["solver"] for p in sys.argv[1:4])
assert d["route"] == "direct" and d["iterations"] == 0 and 0 < d["residual"] <= 1e-12, d
assert e["route"] == "direct", e
assert a["route"] == "amg" and a["iterations"] >= 1 and a["residual"] <= 1e-10 and a["levels"] >= 2, a
vt = [[tuple(map(float, l.split()[1:3])) for l in open(p) if l.startswith("vt ")] for p in sys.argv[4:6]]
assert len(vt[0]) == len(vt[1]) > 30000
diff = max(max(abs(x[0] - y[0]), abs(x[1] - y[1])) for x, y in zip(*vt))
assert diff <= 1e-8, diff
PY
done
cmp -s "$TMP/d.obj" "$TMP/e.obj" || fail "auto below the crossover is not the direct solve"
"$BIN" param "$M/mushroom.off" -o "$TMP/x.obj" --method mips --amg-from 10 2> "$TMP/err"; [ $? = 2 ] || fail "mips + amg-from exit"
"$BIN" param "$M/mushroom.off" -o "$TMP/x.obj" --solver nope 2> "$TMP/err"; [ $? = 2 ] || fail "bad solver exit"
grep -q 'solver takes auto, direct, hierarchical or amg' "$TMP/err" || fail "bad solver message: $(cat "$TMP/err")"
"$BIN" param "$M/mushroom.off" -o "$TMP/x.obj" --method mips --solver direct 2> "$TMP/err"; [ $? = 2 ] || fail "mips + solver exit"
"$BIN" param --help | grep -q -- '--solver auto|direct|hierarchical|amg' || fail "help"
echo ok
