#!/bin/bash
# B-spline fitting of disks (issue 13, the B-spline half): `surfkit fit` against Open CASCADE's
# own approximation (GeomAPI_PointsToBSplineSurface, through FreeCAD's
# Part.BSplineSurface().approximate, its defaults: degree 3 to 8, C2) of the same mesh resampled on a G x G grid
# through our square parametrization (`surfkit param --method floater --boundary square`, the map
# the fit starts from), both at T = 1e-3 of the diagonal. Both surfaces are measured the same way
# inside FreeCAD (bench/approx_occt.py): mesh vertices and face centroids projected onto the
# surface by Open CASCADE (max), a 65 x 65 grid of the surface against the mesh (max). Open
# CASCADE's tolerance bounds its distance to the grid points only: it is run at T, T/2, T/4 and
# the first surface within T of the mesh (by that measure) is kept, else the closest.
# mask_cone has two components: the cone (the one holding its last vertex) is used; the other
# is the nefertiti mask again.
#
# Coarse-level G1 (issue 13, the coarse-level half): `surfkit smooth --tolerance-rel R` on
# bunny00, armadillo, cow and armadillo after two Loop subdivisions (832k triangles, closed), at
# R = 1e-3 and 1e-4: patches, STEP size, two-sided max / RMS deviation, normal jumps, singular
# patches, seconds per stage (wall: search, refinement, of both the VC1 builds and the checks,
# and the final deviation), wall and CPU seconds, peak MB, the load average before the run.
#   bench/approx.sh [SCRATCH_DIR]      env: BUILD (default build-bench), SHARED, GRID (default 60),
#                                      REL (default 1e-3), MESHES, PARTS (default "fit coarse"),
#                                      SHARE (surfkit fit --refine-share; default its own),
#                                      COARSE_MESHES, COARSE_RELS (default "1e-3 1e-4"),
#                                      SK (a built surfkit to run instead of building one),
#                                      SK_BENCH_ROWS (a file: also one tab-separated row per
#                                      disk for bench/all.sh)
set -eu
SRC=$(cd "$(dirname "$0")/.." && pwd)
BUILD=${BUILD:-$SRC/build-bench}
SHARED=${SHARED:-$SRC/../shared}
SCRATCH=${1:-$(mktemp -d /tmp/sk-bench-approx.XXXXXX)}
GRID=${GRID:-60} REL=${REL:-1e-3}
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
echo "# load average: $(cut -d' ' -f1-3 /proc/loadavg), $(nproc) cores; T = $REL of the diagonal, OCCT grid ${GRID}x${GRID}"
echo "| disk | tool | control points | max mesh->surface / diag | max surface->mesh / diag | met | CPU s (OCCT: approximation) |"
echo "|---|---|---|---|---|---|---|"
for mesh in $MESHES; do
  in=$M/$mesh.off
  if [ "$mesh" = mask_cone ]; then
    python3 "$SRC/tests/cli/cut_disk.py" "$in" "$SCRATCH/$mesh.off" "$(sed -n 2p "$in" | cut -d' ' -f2)" \
      "$(( $(sed -n 2p "$in" | cut -d' ' -f1) - 1 ))"
    in=$SCRATCH/$mesh.off
  fi
  "$SK" param "$in" -o "$SCRATCH/$mesh-uv.obj" --method floater --boundary square -q 2> /dev/null
  /usr/bin/time -f '%U %S %M' -o "$SCRATCH/$mesh.fit.kb" "$SK" fit "$in" -o "$SCRATCH/$mesh.step" --tolerance-rel "$REL" \
    ${SHARE:+--refine-share "$SHARE"} --json -q > "$SCRATCH/$mesh.json" 2> /dev/null || true
  tol=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["tolerance"])' "$SCRATCH/$mesh.json")
  SK_MESH=$SCRATCH/$mesh-uv.obj SK_STEP=$SCRATCH/$mesh.step SK_TOL=$tol SK_GRID=$GRID \
    SK_OUT=$SCRATCH/$mesh.occt.json /usr/bin/time -f %M -o "$SCRATCH/$mesh.fc.kb" timeout 1800 freecadcmd "$SRC/bench/approx_occt.py" > "$SCRATCH/$mesh.fc.log" 2>&1 || true
  python3 - "$mesh" "$SCRATCH/$mesh.json" "$SCRATCH/$mesh.occt.json" "$SCRATCH/$mesh" <<'PY'
import json, os, sys
mesh, ours_p, occ_p, base = sys.argv[1:]
o = json.load(open(ours_p))
try:
    r = json.load(open(occ_p))
except (OSError, ValueError):
    r = {}
d, tol = o["deviation"]["diagonal"], o["tolerance"]
def row(tool, m, secs):
    if not m:
        print("| %s | %s | - | - | - | - | - |" % (mesh, tool))
        return
    met = max(m["mesh_to_surface_max"], m["surface_to_mesh_max"]) <= tol
    print("| %s | %s | %d (%d x %d) | %.3g | %.3g | %s | %.2f |" % (
        mesh, tool, m["control_points"], m["poles"][0], m["poles"][1],
        m["mesh_to_surface_max"] / d, m["surface_to_mesh_max"] / d, "yes" if met else "no", secs))
try:  # CPU seconds of the whole `surfkit fit` run (fit, STEP, its own deviation check)
    user, sys_ = map(float, open(base + ".fit.kb").read().split()[-3:-1])
    cpu = user + sys_
except (OSError, ValueError):
    cpu = o["seconds_param"] + o["seconds_fit"]
row("surfkit fit", r.get("ours"), cpu)
if "occt_error" in r:
    print("| %s | OCCT approximate | failed: %s | | | | |" % (mesh, r["occt_error"][:60]))
elif r.get("grid_missing"):
    print("| %s | OCCT approximate | grid has %d holes | | | | |" % (mesh, r["grid_missing"]))
else:
    row("OCCT approximate, degree %s, tol %sT" % ("x".join(map(str, r.get("occt_degrees", []))),
        r.get("occt_factor", 1)), r.get("occt"), r.get("occt_seconds", 0))
rows = os.environ.get("SK_BENCH_ROWS")
if rows:
    def mb(path):
        try:
            return "%d" % (int(open(path).read().split()[-1]) // 1024)
        except (OSError, ValueError, IndexError):
            return "-"
    def desc(m):
        if not m:
            return "-"
        met = max(m["mesh_to_surface_max"], m["surface_to_mesh_max"]) <= tol
        return "%d control points, max dev %.3g of diag%s" % (m["control_points"], max(
            m["mesh_to_surface_max"], m["surface_to_mesh_max"]) / d, "" if met else " (NOT met)")
    occ = r.get("occt")
    with open(rows, "a") as fp:
        fp.write("fit (T=%s diag)\t%s.off\t%s\t%.3f\t%s\tOCCT PointsToBSplineSurface\t%s\t%s\tsurfkit %s; OCCT %s\n" % (
            os.environ.get("REL", "1e-3"), mesh, o.get("faces", "-"), o["seconds_param"] + o["seconds_fit"],
            mb(base + ".fit.kb"), "%.3f" % r["occt_seconds"] if occ and "occt_seconds" in r else "-",
            mb(base + ".fc.kb"), desc(r.get("ours")), desc(occ) if occ else r.get("occt_error", "failed")[:60]))
PY
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
    /usr/bin/time -f "%e %U %S %M" -o "$out.time" timeout 3600 "$SK" smooth "$in" -o "$out.step" \
      --tolerance-rel "$rel" --allow-fail --json -q > "$out.json" 2> "$out.err" || true
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
print("| %s | %d | %s | %d | %.1f | %.1f | %.3g | %.3g | %.3g | %.2g | %d | %s | %d, %d | %s / %s | %s | %.1f | %.1f | %d | %s |" % (
    mesh, d["input_faces"], rel, d["patches"], d["input_faces"] / d["patches"], step,
    dev["hausdorff"] / diag, dev["mesh_to_surface_rms"] / diag, dev["surface_to_mesh_rms"] / diag,
    d["max_normal_jump_deg"], d["singular_patches"], "yes" if d["met"] else "no",
    d["levels_tried"], d["refinement_rounds"], d.get("reused_patches", "-"), d.get("checked_patches", "-"),
    " / ".join("%.1f" % ss[k] for k in ("search", "refine", "vc1", "check", "deviation")),
    wall, user + sys_, kb / 1024, open(out + ".load").read().strip()))
PY
  done
done
fi
