#!/usr/bin/env bash
# Atlases side by side: surfkit param (automatic charts, per-chart hierarchical MIPS, packing)
# against Blender's Smart UV Project + Pack Islands (Debian `blender`, headless) and xatlas
# (npm `xatlas-web` 0.1.0, bench/package.json, run in headless Chromium by
# bench/peers/xatlas_run.js: the package is an emscripten build that refuses plain node), on every
# closed or holed mesh of ../shared/data/meshes and a ~0.8M-triangle closed mesh (armadillo, two
# Loop subdivisions). One independent script (bench/atlas_metrics.py) computes every figure from
# the OBJ files of all three; seconds are each program's own (surfkit: atlas build; Blender:
# unwrap + pack, not import / export; xatlas: createAtlas .. getMeshData inside the page, not the
# browser start or the transfer). Peak MB: max RSS of the surfkit and Blender processes
# (/usr/bin/time), and for xatlas its wasm heap (the browser's own memory is not counted).
# xatlas-web 0.1.0 runs with xatlas's default options (its generateAtlas takes none: padding 0)
# and 16-bit input indices: a mesh over 65,536 vertices goes in as pieces (see xatlas_run.js).
# Gutters: surfkit's is --padding 2 at --resolution 1024 (at least 2 texels between charts, 1
# texel = 1/1024 of the unit square). Each peer runs twice: "blender" / "xatlas" as a user would
# start them (Blender pack_islands margin = 2/1024, which Blender 3.4 scales by the islands' area
# before it fits the pack into the square: measured 0.8-1 texel; xatlas-web: padding 0, about 1
# texel), and "blender@2" / "xatlas@2" at surfkit's gutter: Blender's margin raised until the
# measured gutter is at least 2 texels (up to 4 runs, each margin scaled by 2.1 / the gutter
# measured), xatlas through xatlasjs with padding XATLAS_PADDING (default 1: measured 2.7
# texels; padding 2 gives about 4.7, as xatlas pads each side and adds a bilinear texel) at
# resolution 1024. The gutter column is measured by bench/atlas_metrics.py for every program.
# Columns (bench/atlas_metrics.py): flips = clockwise or degenerate uv triangles; mirrored = charts
# laid out mirrored as a whole (xatlas does this; a reflection, not a fold); folds = triangles
# against their own chart's orientation.
# Usage: bench/atlas.sh [MESH.off ...]   (default: the list below)
# env: SK_BENCH_ROWS=FILE also appends one machine-readable row per program and mesh to FILE
#      ("atlas MESH PROGRAM faces charts seam_rel mips area_log flips overlaps util seconds
#      peak_MB mirrored folds gutter"); SK_ATLAS_PEERS (default "blender blender@2 xatlas
#      xatlas@2"); SK_ATLAS_BIG=0 skips the 0.8M mesh;
#      XATLAS_TIMEOUT (seconds, default 1800); SK_BUILD_DIR (default build); SK_ATLAS_SCRATCH (default build/bench_atlas);
#      XATLAS_BIG=1 also runs xatlas on meshes over 200k triangles (skipped by default: hours).
set -euo pipefail
cd "$(dirname "$0")/.."
B=${SK_BUILD_DIR:-build}
cmake -S . -B "$B" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$B" -j2 --target surfkit >/dev/null
sk=./$B/surfkit
M=../shared/data/meshes
T=${SK_ATLAS_SCRATCH:-build/bench_atlas}
mkdir -p "$T"
peers=${SK_ATLAS_PEERS-blender blender@2 xatlas xatlas@2}
case " $peers " in *" blender"*)
  command -v blender >/dev/null || { echo "blender not installed (scripts/setup.sh --interop)"; exit 1; } ;;
esac
case " $peers " in *" xatlas "*)
  command -v chromium >/dev/null || { echo "chromium not installed (scripts/setup.sh)"; exit 1; }
  [ -e bench/node_modules/xatlas-web/dist/xatlas-web.wasm ] ||
    (cd bench && npm ci --no-audit --no-fund --loglevel=error) ;;
esac
meshes=("$@")
if [ ${#meshes[@]} -eq 0 ]; then
    meshes=(sphere cube icosahedron eight knot1 elephant cow pig blobby fandisk holes lion
            mech-holes-shark mask_cone bunny00 armadillo)
    meshes=("${meshes[@]/#/$M/}")
    meshes=("${meshes[@]/%/.off}")
    if [ "${SK_ATLAS_BIG:-1}" != 0 ]; then
        [ -f "$T/armadillo-1m.ply" ] || $sk subdivide "$M/armadillo.off" -o "$T/armadillo-1m.ply" --scheme loop -n 2 -q
        meshes+=("$T/armadillo-1m.ply")
    fi
fi
margin=$(awk 'BEGIN { print 2 / 1024 }') # the same gutter as surfkit's default (2 texels at 1024)
row() { # name program json seconds peak_MB
    python3 - "$@" <<'PY'
import json, os, sys
name, prog, js, sec, mb = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5]
try:
    js = json.loads(js)
except ValueError:
    print("%-22s %-8s %s" % (name, prog, "failed"))
    sys.exit(0)
sec = float(sec) if sec else float("nan")
print("%-22s %-9s %7d %6d %8.2f %8.4f %8.4f %6d %8d %5d %8d %6.3f %6.2f %8.2f %7s" % (name, prog,
      js["faces"], js["charts"], js["seam_length_rel"], js["mips_mean"], js["area_log_mean"],
      js["flipped"], js["mirrored_charts"], js["folds"], js["overlaps"], js["utilization"],
      js["gutter_texels"], sec, mb or "-"))
rows = os.environ.get("SK_BENCH_ROWS")
if rows:
    with open(rows, "a") as fp:
        fp.write("atlas %s %s %d %d %.4f %.6f %.6f %d %d %.4f %.4f %s %d %d %.3f\n" % (name, prog,
                 js["faces"], js["charts"], js["seam_length_rel"], js["mips_mean"],
                 js["area_log_mean"], js["flipped"], js["overlaps"], js["utilization"], sec,
                 mb or "-", js["mirrored_charts"], js["folds"], js["gutter_texels"]))
PY
}
peak() { awk '{ printf "%.0f", $1 / 1024 }' "$1"; }
echo "# load average at start: $(cut -d' ' -f1-3 /proc/loadavg), $(nproc) cores"
printf '%-22s %-9s %7s %6s %8s %8s %8s %6s %8s %5s %8s %6s %6s %8s %7s\n' mesh program faces charts seam_rel \
    mips area_log flips mirrored folds overlaps util gutter seconds peak_MB
blender_run() { # IN OUT MARGIN: prints Blender's seconds
    /usr/bin/time -f %M -o "$T/time.txt" blender -b -P bench/peers/blender_smart_project.py -- \
        "$1" "$2" "$3" 2>/dev/null | sed -n 's/^BLENDER_SECONDS //p'
}
gutter() { python3 -c "import json, sys; print(json.loads(sys.argv[1])['gutter_texels'])" "$1"; }
for f in "${meshes[@]}"; do
    n=$(basename "${f%.*}")
    $sk convert "$f" "$T/$n.obj" >/dev/null
    /usr/bin/time -f %M -o "$T/time.txt" $sk param "$f" -o "$T/$n-surfkit.obj" --atlas --report "$T/$n-surfkit.json" -q
    s_sec=$(python3 -c "import json; print(json.load(open('$T/$n-surfkit.json'))['seconds'])")
    row "$n" surfkit "$(python3 bench/atlas_metrics.py "$T/$n-surfkit.obj")" "$s_sec" "$(peak "$T/time.txt")"
    for p in $peers; do
        sec="" mb="" js=""
        if [ "$p" = blender ]; then
            sec=$(blender_run "$T/$n.obj" "$T/$n-$p.obj" "$margin") || true
            mb=$(peak "$T/time.txt")
        elif [ "$p" = blender@2 ]; then # the margin that gives a measured gutter of >= 2 texels
            m=$margin
            for try in 1 2 3 4; do
                sec=$(blender_run "$T/$n.obj" "$T/$n-$p.obj" "$m") || true
                mb=$(peak "$T/time.txt")
                js=$(python3 bench/atlas_metrics.py "$T/$n-$p.obj" 2>/dev/null) || break
                g=$(gutter "$js")
                awk -v g="$g" 'BEGIN { exit !(g >= 2) }' && break
                m=$(awk -v m="$m" -v g="$g" 'BEGIN { print m * 2.1 / (g > 0.05 ? g : 0.05) }')
            done
            echo "# blender@2 on $n: margin $m (gutter $g texels)"
        elif [ "$(grep -c '^f ' "$T/$n.obj")" -gt 200000 ] && [ "${XATLAS_BIG:-0}" != 1 ]; then
            # xatlas-web took 370 s for bunny00 (75k triangles) here; the 0.8M mesh would take hours
            echo "# $p skipped on $n (over 200k triangles; XATLAS_BIG=1 runs it)"
            continue
        else
            rm -f "$T/$n-$p.obj"
            opts=()
            [ "$p" = xatlas@2 ] && opts=(--padding "${XATLAS_PADDING:-1}" --resolution 1024)
            out=$(node bench/peers/xatlas_run.js "$T/$n.obj" "$T/$n-$p.obj" "${opts[@]}" 2>"$T/$n-$p.err") || true
            sec=$(echo "$out" | sed -n 's/^XATLAS_SECONDS //p')
            mb=$(echo "$out" | sed -n 's/^XATLAS_HEAP_MB //p')
            pieces=$(echo "$out" | sed -n 's/^XATLAS_PIECES //p')
            [ "${pieces:-1}" = 1 ] || echo "# xatlas: $n went in as $pieces pieces of <= 65,536 vertices (16-bit indices)"
        fi
        [ -n "$js" ] || { [ -s "$T/$n-$p.obj" ] && js=$(python3 bench/atlas_metrics.py "$T/$n-$p.obj" 2>/dev/null); } || js=""
        row "$n" "$p" "$js" "$sec" "$mb"
    done
done
echo "# load average at end: $(cut -d' ' -f1-3 /proc/loadavg)"
