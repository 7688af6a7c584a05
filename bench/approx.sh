#!/bin/bash
# B-spline fitting of disks (issue 13, the B-spline half): `surfkit fit` (its default: the square
# map chosen among area thetas 1, 0.5, none) against Open CASCADE's own approximation
# (GeomAPI_PointsToBSplineSurface, through FreeCAD's Part.BSplineSurface().approximate: degree 3
# to 8, C2) of the same mesh resampled on a G x G grid through our square parametrization
# (`surfkit param --method floater --boundary square`), at each T of RELS times the diagonal.
# Both surfaces are measured the same way inside FreeCAD (bench/approx_occt.py): mesh vertices
# and face centroids projected onto the surface by Open CASCADE (max), a 65 x 65 grid of the
# surface against the mesh (max); "max dev" is the larger. Open CASCADE's tolerance bounds its
# distance to the grid points only: it is run at T, T/2, T/4 and the first surface within T of
# the mesh is kept, else the closest. Each Open CASCADE approximation runs under a CPU limit
# (OCCT_CPU seconds, ulimit -t); one that hits it is reported as such and the disk is tried
# again on a grid half as fine (down to 20 x 20); the grid used is in the table.
# mask_cone has two components: the cone (the one holding its last vertex) is used; the other
# is the nefertiti mask again.
#
# Coarse-level G1 (issue 13, the coarse-level half): `surfkit smooth --tolerance-rel R` on
# bunny00, armadillo, cow and armadillo after two Loop subdivisions (832k triangles, closed), at
# R = 1e-3 and 1e-4: patches, STEP size, two-sided max / RMS deviation, normal jumps, singular
# patches, seconds per stage (wall: search, refinement, of both the VC1 builds and the checks,
# and the final deviation), wall and CPU seconds, peak MB, the load average before the run.
#   bench/approx.sh [SCRATCH_DIR]      env: BUILD (default build-bench), SHARED, GRID (default 60),
#                                      RELS (default "1e-2 5e-3 2e-3 1e-3"; REL: one of them),
#                                      OCCT_CPU (default 300), MESHES, PARTS (default "fit coarse"),
#                                      FIT_ARGS (more surfkit fit options, e.g. --area-theta 0),
#                                      SHARE (surfkit fit --refine-share; default its own),
#                                      COARSE_MESHES, COARSE_RELS (default "1e-3 1e-4"),
#                                      SMOOTH_ARGS (more surfkit smooth options, e.g. --full-search),
#                                      SK (a built surfkit to run instead of building one),
#                                      SK_BENCH_ROWS (a file: also one tab-separated row per
#                                      disk for bench/all.sh)
set -eu
SRC=$(cd "$(dirname "$0")/.." && pwd)
BUILD=${BUILD:-$SRC/build-bench}
SHARED=${SHARED:-$SRC/../shared}
SCRATCH=${1:-$(mktemp -d /tmp/sk-bench-approx.XXXXXX)}
GRID=${GRID:-60} RELS=${RELS:-${REL:-"1e-2 5e-3 2e-3 1e-3"}} OCCT_CPU=${OCCT_CPU:-300}
MESHES=${MESHES:-"paraboloid-patch nefertiti patch-01 mask_cone lion-head"}
PARTS=${PARTS:-"fit coarse"}
COARSE_MESHES=${COARSE_MESHES:-"cow armadillo bunny00 armadillo-loop2"}
COARSE_RELS=${COARSE_RELS:-"1e-3 1e-4"}
mkdir -p "$SCRATCH"
if [ -z "${SK:-}" ]; then
  cmake -S "$SRC" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DSK_BUILD_TESTS=OFF > /dev/null
  cmake --build "$BUILD" -j2 --target surfkit > /dev/null
  SK=$BUILD/surfkit
fi
M=$SHARED/data/meshes
export HOME=$SCRATCH/home; mkdir -p "$HOME"
if [[ " $PARTS " == *" fit "* ]]; then
command -v freecadcmd > /dev/null || { echo "freecadcmd not installed (scripts/setup.sh --interop)"; exit 1; }
occt() { # occt MODE OUT [VAR=VALUE...]: one approx_occt.py job
  local mode=$1 out=$2; shift 2
  env "$@" SK_MODE="$mode" SK_OUT="$out" freecadcmd "$SRC/bench/approx_occt.py" > "$out.log" 2>&1
}
echo "# load average: $(cut -d' ' -f1-3 /proc/loadavg), $(nproc) cores; OCCT grid ${GRID}x${GRID} (smaller where it hit the ${OCCT_CPU} CPU s limit)"
echo "| disk | T / diag | surfkit control points | max dev / diag | met | CPU s | area theta (maps tried: control points) | OCCT poles | max dev / diag | met | CPU s | OCCT grid, tolerance | OCCT tries |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for mesh in $MESHES; do
  in=$M/$mesh.off
  if [ "$mesh" = mask_cone ]; then
    python3 "$SRC/tests/cli/cut_disk.py" "$in" "$SCRATCH/$mesh.off" "$(sed -n 2p "$in" | cut -d' ' -f2)" \
      "$(( $(sed -n 2p "$in" | cut -d' ' -f1) - 1 ))"
    in=$SCRATCH/$mesh.off
  fi
  uvmesh=$SCRATCH/$mesh-uv.obj
  "$SK" param "$in" -o "$uvmesh" --method floater --boundary square -q 2> /dev/null
  for rel in $RELS; do
    b=$SCRATCH/$mesh-$rel
    # shellcheck disable=SC2086
    /usr/bin/time -f '%U %S %M' -o "$b.fit.kb" "$SK" fit "$in" -o "$b.step" --tolerance-rel "$rel" \
      ${SHARE:+--refine-share "$SHARE"} ${FIT_ARGS:-} --json -q > "$b.json" 2> /dev/null || true
    tol=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["tolerance"])' "$b.json")
    occt measure "$b.ours.json" SK_MESH="$uvmesh" SK_SURF="$b.step" || true
    g=$GRID tries=""
    rm -f "$b.occt.json"
    for factor in 1 0.5 0.25; do
      while :; do
        t=$b.occt-$g-$factor
        rc=0
        ( ulimit -t "$OCCT_CPU"; occt approximate "$t.json" SK_MESH="$uvmesh" SK_TOL="$tol" \
            SK_FACTOR="$factor" SK_GRID="$g" SK_BREP="$t.brep" ) || rc=$?
        if [ -s "$t.brep" ] && [ $rc = 0 ]; then
          occt measure "$t.m.json" SK_MESH="$uvmesh" SK_SURF="$t.brep" || true
          break
        fi
        tries="$tries ${g}x${g} at ${factor}T: $([ $rc -gt 128 ] && echo "over ${OCCT_CPU} CPU s" || echo "failed");"
        [ $rc -gt 128 ] && [ $((g / 2)) -ge 20 ] || break
        g=$((g / 2))
      done
      [ -s "$t.m.json" ] || continue
      python3 - "$t.json" "$t.m.json" "$b.occt.json" "$tol" "$factor" <<'PY' && break
import json, sys
run, m, best_p, tol, factor = sys.argv[1:]
r, m = json.load(open(run)), json.load(open(m))
m.update(seconds=r["seconds"], grid=r["grid"], factor=float(factor))
dev = max(m["mesh_to_surface_max"], m["surface_to_mesh_max"])
try:
    b = json.load(open(best_p))
    keep = dev < max(b["mesh_to_surface_max"], b["surface_to_mesh_max"])
except (OSError, ValueError):
    keep = True
if keep:
    json.dump(m, open(best_p, "w"))
sys.exit(0 if dev <= float(tol) else 1)  # within T: no tighter try needed
PY
      tries="$tries ${g}x${g} at ${factor}T: not within T;"
    done
    python3 - "$mesh" "$rel" "$b" "$tries" <<'PY'
import json, os, sys
mesh, rel, base, tries = sys.argv[1:]
o = json.load(open(base + ".json"))
d, tol = o["deviation"]["diagonal"], o["tolerance"]
def load(p):
    try:
        return json.load(open(p))
    except (OSError, ValueError):
        return {}
ours, occ = load(base + ".ours.json"), load(base + ".occt.json")
def dev(m):
    return max(m["mesh_to_surface_max"], m["surface_to_mesh_max"])
try:  # CPU seconds of the whole `surfkit fit` run (all maps tried, STEP, its own deviation check)
    user, sys_ = map(float, open(base + ".fit.kb").read().split()[-3:-1])
    cpu = "%.1f" % (user + sys_)
except (OSError, ValueError):
    cpu = "-"
maps = ", ".join("%g: %d%s" % (t["area_theta"], t["control_points"], "" if t["met"] else " (not met)")
                 for t in o.get("maps_tried", []))
cols = [mesh, rel]
if "control_points" in ours:
    cols += ["%d" % ours["control_points"], "%.3g" % (dev(ours) / d), "yes" if dev(ours) <= tol else "no", cpu,
             "%g (%s)" % (o.get("area_theta", 0), maps)]
else:
    cols += ["-", "-", "-", cpu, ours.get("error", "not measured")]
if occ:
    cols += ["%d (%d x %d, degree %d x %d)" % (occ["control_points"], occ["poles"][0], occ["poles"][1],
             occ["degrees"][0], occ["degrees"][1]), "%.3g" % (dev(occ) / d),
             "yes" if dev(occ) <= tol else "no", "%.1f" % occ["seconds"],
             "%dx%d, %gT" % (occ["grid"], occ["grid"], occ["factor"])]
else:
    cols += ["-", "-", "-", "-", "-"]
cols.append(tries.strip() or "-")
print("| " + " | ".join(cols) + " |")
rows = os.environ.get("SK_BENCH_ROWS")
if rows:
    def mb(path):
        try:
            return "%d" % (int(open(path).read().split()[-1]) // 1024)
        except (OSError, ValueError, IndexError):
            return "-"
    def desc(m):
        if not m or "control_points" not in m:
            return "-"
        return "%d control points, max dev %.3g of diag%s" % (m["control_points"], dev(m) / d,
                                                              "" if dev(m) <= tol else " (NOT met)")
    with open(rows, "a") as fp:
        fp.write("fit (T=%s diag)\t%s.off\t%s\t%.3f\t%s\tOCCT PointsToBSplineSurface\t%s\t-\tsurfkit %s; OCCT %s\n" % (
            rel, mesh, o.get("faces", "-"), o["seconds_param"] + o["seconds_fit"], mb(base + ".fit.kb"),
            "%.3f" % occ["seconds"] if occ else "-", desc(ours), desc(occ) if occ else (tries.strip() or "failed")[:60]))
PY
  done
done
fi

if [[ " $PARTS " == *" coarse "* ]]; then
echo
echo "# coarse-level G1: load average $(cut -d' ' -f1-3 /proc/loadavg), $(nproc) cores"
echo "| mesh | triangles | T / diag | patches | triangles per patch | STEP MB | max / diag | RMS mesh->surface / diag | RMS surface->mesh / diag | max normal jump deg | singular | met | levels tried, rounds | patches paired / checked in the rounds | search / refine / vc1 / check / deviation s | wall s | CPU s | peak MB | load |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for mesh in $COARSE_MESHES; do
  in=$M/$mesh.off
  if [ "$mesh" = armadillo-loop2 ]; then
    in=$SCRATCH/armadillo-loop2.off
    [ -s "$in" ] || "$SK" subdivide -q "$M/armadillo.off" -o "$in" --scheme loop -n 2
  fi
  for rel in $COARSE_RELS; do
    out=$SCRATCH/$mesh-$rel
    cut -d' ' -f1 /proc/loadavg > "$out.load"
    # shellcheck disable=SC2086
    /usr/bin/time -f "%e %U %S %M" -o "$out.time" timeout 3600 "$SK" smooth "$in" -o "$out.step" \
      --tolerance-rel "$rel" ${SMOOTH_ARGS:-} --allow-fail --json -q > "$out.json" 2> "$out.err" || true
    python3 - "$mesh" "$rel" "$out" <<'PY'
import json, os, sys
mesh, rel, out = sys.argv[1:]
try:
    d = json.load(open(out + ".json"))
except (OSError, ValueError):
    print("| %s | | %s | failed: %s | | | | | | | | | | | | | | | |" % (mesh, rel, open(out + ".err").read().strip()[:80]))
    sys.exit(0)
wall, user, sys_, kb = map(float, open(out + ".time").read().split()[-4:])
ss = d["stage_seconds"]
dev, diag = d["deviation"], d["deviation"]["diagonal"]
step = os.path.getsize(out + ".step") / 1e6 if os.path.exists(out + ".step") else float("nan")
print("| %s | %d | %s | %d | %.1f | %.1f | %.3g | %.3g | %.3g | %.2g | %d | %s | %d%s, %d | %s / %s | %s | %.1f | %.1f | %d | %s |" % (
    mesh, d["input_faces"], rel, d["patches"], d["input_faces"] / d["patches"], step,
    dev["hausdorff"] / diag, dev["mesh_to_surface_rms"] / diag, dev["surface_to_mesh_rms"] / diag,
    d["max_normal_jump_deg"], d["singular_patches"], "yes" if d["met"] else "no",
    d["levels_tried"], " (estimate assumed)" if d.get("level_assumed") else "", d["refinement_rounds"], d.get("reused_patches", "-"), d.get("checked_patches", "-"),
    " / ".join("%.1f" % ss[k] for k in ("search", "refine", "vc1", "check", "deviation")),
    wall, user + sys_, kb / 1024, open(out + ".load").read().strip()))
PY
  done
done
fi
