#!/usr/bin/env bash
# surfkit smooth: the shape measures in --json / --report and --patches (overshoot, fairness,
# worst patch ids), and the pictures --render (exact normals), --zebra, --patch-map.
set -u
bin=$1 shared=$3 tmp=$4
rm -rf "$tmp"; mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
m=$shared/data/meshes
"$bin" smooth "$m/sphere.off" --json --patches "$tmp/p.json" --render "$tmp/s.png" \
  --zebra "$tmp/z.png" --patch-map "$tmp/m.png" -q > "$tmp/r.json" || fail "sphere exit $?"
for f in s z m; do
  head -c 8 "$tmp/$f.png" | od -An -c | grep -q 'P   N   G' || fail "$f.png is not a PNG"
done
python3 - "$tmp/r.json" "$tmp/p.json" <<'PY' || fail "sphere shape values"
import json, sys
r = json.load(open(sys.argv[1]))
p = json.load(open(sys.argv[2]))["patches"]
assert len(p) == r["triangles"] + r["quads"], (len(p), r)
over = [q["overshoot"] for q in p]
fair = [q["fairness_deg"] for q in p]
# the report's worst values are those of the named patches; the sphere bulges a little, no spike
assert 0.01 < r["max_overshoot"] < 0.1, r
assert abs(over[r["max_overshoot_patch"]] - r["max_overshoot"]) <= 1e-5 * r["max_overshoot"], r
assert abs(max(over) - r["max_overshoot"]) <= 1e-5 * r["max_overshoot"], r
assert abs(fair[r["max_fairness_patch"]] - r["max_fairness_deg"]) <= 1e-5 * r["max_fairness_deg"]
assert 0 < r["max_fairness_deg"] < 5 and r["mean_fairness_deg"] <= r["max_fairness_deg"], r
assert r["overshoot_patches"] == 0 and r["overshoot_patch_examples"] == [], r
assert not any(q["singular"] for q in p)
PY
# a rough scan with the least-squares free points and the input's triangulation (the fair ones
# leave no spike on the cow, see below, nor since the flips of bad faces the least-squares ones
# over the flipped triangulation): spikes over 0.5 are listed worst first and flagged in --patches
"$bin" smooth "$m/cow.off" --json --allow-fail --free-points lsq --keep-triangulation \
  --patches "$tmp/cp.json" -q \
  > "$tmp/cow.json" || fail "cow exit $?"
python3 - "$tmp/cow.json" "$tmp/cp.json" <<'PY' || fail "cow shape values"
import json, sys
r = json.load(open(sys.argv[1]))
p = json.load(open(sys.argv[2]))["patches"]
ex = r["overshoot_patch_examples"]
assert r["overshoot_patches"] == sum(q["overshoot"] > 0.5 for q in p) > 0, r
assert ex and ex[0] == r["max_overshoot_patch"], r
assert all(p[i]["overshoot"] > 0.5 for i in ex)
assert all(p[a]["overshoot"] >= p[b]["overshoot"] for a, b in zip(ex, ex[1:]))
assert r["singular_patches"] == sum(q["singular"] for q in p), r
PY
# the default fair free points: no spike left, fewer singular patches
"$bin" smooth "$m/cow.off" --json --allow-fail -q > "$tmp/cowf.json" || fail "cow fair exit $?"
python3 - "$tmp/cow.json" "$tmp/cowf.json" <<'PY' || fail "cow fair shape values"
import json, sys
lsq, fair = (json.load(open(f)) for f in sys.argv[1:3])
assert fair["overshoot_patches"] == 0 and fair["overshoot_patch_examples"] == [], fair
assert fair["max_overshoot"] <= 0.5 < lsq["max_overshoot"], (fair, lsq)
assert fair["singular_patches"] < lsq["singular_patches"], (fair, lsq)
assert fair["fair_steps"] > 0 and lsq["fair_steps"] == 0, (fair, lsq)
PY
# the pig renumbered (bench/renumber.py, seed 1): without the re-routed rounds its repair leaves
# singular patches and the report fails (exit 4, nothing written); with them (the default) none
python3 "$(dirname "$0")/../../bench/renumber.py" "$m/pig.off" "$tmp/pig1.off" 1 || fail "renumber"
"$bin" smooth "$tmp/pig1.off" --reroute-rounds 0 --json -o "$tmp/p0.obj" -q > "$tmp/p0.json" 2>/dev/null
[ $? -eq 4 ] && [ ! -e "$tmp/p0.obj" ] || fail "pig1 without rounds: not a failed report"
"$bin" smooth "$tmp/pig1.off" --json -o "$tmp/p6.obj" -q > "$tmp/p6.json" || fail "pig1 exit $?"
python3 - "$tmp/p0.json" "$tmp/p6.json" <<'PY' || fail "pig1 re-routed rounds"
import json, sys
off, on = (json.load(open(f)) for f in sys.argv[1:3])
assert off["singular_patches"] > 0 and off["rerouted_rounds"] == 0, off
assert on["singular_patches"] == 0 and on["rerouted_rounds"] >= 1, on
assert on["max_normal_jump_deg"] < 1e-7 and on["max_vertex_error"] == 0, on
PY
"$bin" smooth "$m/sphere.off" --zebra 2>/dev/null; [ $? -eq 2 ] || fail "--zebra without a file"
echo ok
