#!/usr/bin/env bash
# surfkit smooth: VC1 on the sphere (report keys, jump at rounding level, outputs written, a closed
# tessellation), PN
# baseline with degree-level jumps, odd closed mesh refused (exit 1) and handled with --allow-split.
set -u
bin=$1 shared=$3 tmp=$4
rm -rf "$tmp"; mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
m=$shared/data/meshes
"$bin" smooth "$m/sphere.off" -o "$tmp/s.obj" --tess 3 --report "$tmp/r.json" \
  --patches "$tmp/p.json" --layout "$tmp/l.png" --render "$tmp/s.png" -q || fail "sphere exit $?"
for k in triangles quads even_vertices deleted_edges max_gap max_normal_jump_deg \
         mean_normal_jump_deg max_vertex_error max_normal_error_deg singular_patches seconds; do
  grep -q "\"$k\"" "$tmp/r.json" || fail "report key $k missing"
done
python3 - "$tmp/r.json" <<'PY' || fail "sphere report values"
import json, sys
r = json.load(open(sys.argv[1]))
assert r["max_normal_jump_deg"] < 1e-7, r
assert r["singular_patches"] == 0 and r["quads"] == r["deleted_edges"] == 75
assert r["crease_edges"] == 0, r
PY
"$bin" smooth "$m/cube.off" --crease-angle 60 --scheme pn --json -q > "$tmp/c.json" || fail "cube exit"
python3 -c "import json; assert json.load(open('$tmp/c.json'))['crease_edges'] == 12" || fail "cube creases"
"$bin" smooth "$m/cube.off" --no-creases -o "$tmp/c0.obj" --json -q > "$tmp/c0.json" || fail "cube --no-creases exit"
python3 -c "import json; r = json.load(open('$tmp/c0.json')); assert r['crease_edges'] == 0 and r['g0_crease_edges'] == 0, r" ||
  fail "cube --no-creases"
# vc1: the cube's edges are G0 creases (listed, normal jump 90 there, gap at rounding), the
# max normal jump skips them and says so; the tessellation stays closed; STEP export works
"$bin" smooth "$m/cube.off" -o "$tmp/cube.obj" --json -q > "$tmp/cv.json" || fail "cube vc1 exit"
python3 - "$tmp/cv.json" <<'PY' || fail "cube vc1 creases"
import json, sys
r = json.load(open(sys.argv[1]))
assert r["crease_edges"] == 12 and r["g0_crease_edges"] == 12, r
assert len(r["creases"]) == 12 and all(a != b for a, b in r["creases"]), r
assert abs(r["max_crease_jump_deg"] - 90) < 1e-9 and abs(r["min_crease_jump_deg"] - 90) < 1e-9, r
assert r["max_crease_gap"] < 1e-12 and r["max_normal_jump_deg"] < 1e-7, r
PY
"$bin" smooth "$m/cube.off" -o "$tmp/cube.step" | grep -q "off 12 crease edges (G0 there: normal jump 90..90 deg" ||
  fail "cube summary line"
"$bin" info "$tmp/cube.obj" | grep -Eq '^ +edges +[0-9]+ \(0 on the boundary\)' || fail "cube tessellation open"
"$bin" smooth "$m/cube.off" --crease-angle 200 -o "$tmp/c.obj" 2>/dev/null; [ $? -eq 2 ] || fail "--crease-angle 200 accepted"
grep -q '^vn ' "$tmp/s.obj" || fail "no normals in the OBJ"
# the tessellation of the closed sphere is watertight: one component, no boundary edge
"$bin" info "$tmp/s.obj" > "$tmp/info.txt" || fail "info on the tessellation"
grep -Eq '^ +edges +[0-9]+ \(0 on the boundary\)' "$tmp/info.txt" &&
  grep -Eq '^ +components +1$' "$tmp/info.txt" && grep -Eq '^ +defects +none' "$tmp/info.txt" ||
  fail "sphere tessellation not closed: $(cat "$tmp/info.txt")"
[ -s "$tmp/l.png" ] && [ -s "$tmp/s.png" ] && [ -s "$tmp/p.json" ] || fail "missing outputs"
"$bin" smooth "$m/sphere.off" --scheme pn --json -q > "$tmp/pn.json" || fail "pn exit"
python3 -c "import json,sys; r=json.load(open('$tmp/pn.json')); assert r['max_normal_jump_deg'] > 0.3" ||
  fail "pn jump"
"$bin" smooth "$m/blobby.off" -o "$tmp/b.obj" 2> "$tmp/err"; rc=$?
[ $rc -eq 1 ] && grep -q "odd" "$tmp/err" && [ ! -e "$tmp/b.obj" ] || fail "blobby not refused ($rc)"
"$bin" smooth "$m/blobby.off" --allow-split --json -q > "$tmp/b.json" || fail "allow-split exit"
python3 -c "import json; r=json.load(open('$tmp/b.json')); assert r['split_edges']==1 and r['max_normal_jump_deg']<1e-7" ||
  fail "allow-split report"
# the triangulation pass: cow's edges are flipped by default (reported), none with --keep-triangulation
"$bin" smooth "$m/cow.off" --json -q --allow-fail > "$tmp/cf.json"; rc=$?; [ $rc -le 4 ] || fail "cow exit $rc"
"$bin" smooth "$m/cow.off" --json -q --allow-fail --keep-triangulation > "$tmp/ck.json"; rc=$?
[ $rc -le 4 ] || fail "cow --keep-triangulation exit $rc"
python3 -c "import json; f=json.load(open('$tmp/cf.json')); k=json.load(open('$tmp/ck.json')); assert f['flipped_edges'] > 0 and k['flipped_edges'] == 0 and f['max_normal_jump_deg'] < 1e-7, (f['flipped_edges'], k['flipped_edges'])" ||
  fail "flipped_edges"
# --parity-flips: knot1 with flips that make even vertices odd, fewer deleted edges, still G1
"$bin" smooth "$m/knot1.off" --json -q > "$tmp/e0.json" || fail "knot1 exit $?"
"$bin" smooth "$m/knot1.off" --json -q --parity-flips > "$tmp/ep.json" || fail "knot1 --parity-flips exit $?"
python3 -c "import json; a=json.load(open('$tmp/e0.json')); b=json.load(open('$tmp/ep.json')); assert a['parity_flipped_edges'] == 0 < b['parity_flipped_edges'] and b['even_vertices'] < a['even_vertices'] and b['deleted_edges'] < a['deleted_edges'] and b['singular_patches'] == 0 and b['max_normal_jump_deg'] < 1e-7, (a['deleted_edges'], b['deleted_edges'])" ||
  fail "parity_flipped_edges"
# every figure is the same on one thread (the parallel stages are deterministic, the mean target
# deviation is summed in vertex order); CPU seconds per stage beside the wall seconds
OMP_NUM_THREADS=1 "$bin" smooth "$m/cow.off" --json -q --allow-fail > "$tmp/cf1.json"; rc=$?
[ $rc -le 4 ] || fail "cow one thread exit $rc"
python3 - "$tmp/cf.json" "$tmp/cf1.json" <<'PY' || fail "cow figures depend on the thread count"
import json, sys
a, b = (json.load(open(f)) for f in sys.argv[1:3])
cpu = a["stage_cpu_seconds"]
assert set(a["stage_seconds"]) <= set(cpu) and all(v >= 0 for v in cpu.values()), cpu
for r in (a, b):
    for k in ("seconds", "stage_seconds", "stage_cpu_seconds"):
        r.pop(k)
diff = [k for k in a if a[k] != b.get(k)]
assert not diff, [(k, a[k], b.get(k)) for k in diff]
PY
"$bin" smooth "$m/sphere.off" 2>/dev/null; [ $? -eq 2 ] || fail "no output should be a usage error"
echo ok
