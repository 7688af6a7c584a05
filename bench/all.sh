#!/usr/bin/env bash
# Every headline figure side by side with its peer, in one run, one table:
#   read       bench_io read (binary PLY, OBJ)           vs OpenMesh's reader (peers/openmesh_read)
#   hierarchy  bench_hierarchy (the full progressive mesh) vs OpenMesh's decimater with
#              ModIndependentSetsT (peers/openmesh_hierarchy, as bench/hierarchy.sh)
#   linear     bench_linear, each method, direct, hierarchical and amg solve, vs CGAL 5.5's
#              parametrizer of the same method (peers/cgal_param; Floater has no CGAL
#              counterpart: CGAL's mean value stands in), as bench/linear.sh and param.sh
#   mips       surfkit param --method mips (free boundary) vs CGAL's discrete conformal map and
#              ARAP (peers/cgal_mips, as bench/mips.sh)
#   atlas      bench/atlas.sh: surfkit vs Blender's Smart UV Project and xatlas (in Chromium)
#   vc1        bench_smooth: VC1 build, and build + continuity report (no peer)
#   export     bench_export (the STEP / IGES writer alone) vs Open CASCADE writing the same
#              surfaces again (freecadcmd, peers/occt_rewrite.py: Part.read of our file, then
#              exportStep / exportIges timed)
#   fit        bench/approx.sh: surfkit fit vs OCCT's GeomAPI_PointsToBSplineSurface
# Seconds are each program's own figure for the operation (read excluded where the programs
# time it themselves, as the scripts named above do); "peak MB" is the max RSS of that process
# (/usr/bin/time; xatlas: its wasm heap; fit/OCCT: the freecadcmd process). ratio = peer seconds /
# surfkit seconds (above 1: surfkit faster). The load average is printed at start and end: the
# machine may be shared, so compare rows of one run only.
# Sizes: default the 1M-triangle cases (lion-head Loop-subdivided 3 times, a 1,067,136-triangle
# disk; armadillo twice, an 832,000-triangle closed mesh; CGAL's mean value on the 1M disk, its
# other methods on the 267k disk, ARAP on lion-head: it did not finish the 1M disk in 15 minutes);
# --quick: a 267k-triangle read, the 67k disk for the linear methods (CGAL's four beside them),
# the 208k closed mesh for hierarchy and VC1, atlases of cow and knot1 (xatlas-web needs minutes
# from 50k triangles on): about 5 minutes on a quiet 2-core machine, 15-25 with others building.
# Usage: bench/all.sh [--quick]     env: BUILD (default build-bench), SHARED (default ../shared)
# Rows stay in BUILD/bench-all/rows.tsv.
set -uo pipefail
cd "$(dirname "$0")/.."
quick=0
for a in "$@"; do
  case $a in
    --quick) quick=1 ;;
    *) sed -n '2,/^set -uo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 2 ;;
  esac
done
B=${BUILD:-build-bench}
SHARED=${SHARED:-../shared}
M=$SHARED/data/meshes
S=$B/bench-all
mkdir -p "$S"
cmake -S . -B "$B" -G Ninja -DCMAKE_BUILD_TYPE=Release -DSK_BUILD_TESTS=OFF >/dev/null || exit 1
targets="surfkit bench_io bench_hierarchy bench_linear bench_param bench_smooth bench_export"
have=$(ninja -C "$B" -t targets all 2>/dev/null)
for p in openmesh_read openmesh_hierarchy cgal_param cgal_mips; do
  echo "$have" | grep -q "^bench/$p:" && targets="$targets $p"
done
cmake --build "$B" -j2 --target $targets >/dev/null || exit 1
SK=$B/surfkit BB=$B/bench
export OMP_WAIT_POLICY=passive
ROWS=$S/rows.tsv
: > "$ROWS"
echo "# bench/all.sh$([ $quick = 1 ] && echo ' --quick'): surfkit $(git rev-parse --short HEAD 2>/dev/null), $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
echo "# load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"
t_start=$(date +%s)

# one row: figure mesh faces ours_s ours_MB peer peer_s peer_MB note
row() { printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$@" >> "$ROWS"; }
# run CMD with /usr/bin/time: stdout to $S/out.txt, peak MB in $MB, wall seconds in $WALL
timed() {
  MB=- WALL=-
  /usr/bin/time -f "%e %M" -o "$S/time.txt" "$@" > "$S/out.txt" 2> "$S/err.txt" || { tail -1 "$S/err.txt" >&2; return 1; }
  read -r WALL kb < <(tail -1 "$S/time.txt")
  MB=$(( kb / 1024 ))
}
faces_of() { # OFF or PLY header face count
  case $1 in
    *.off) sed -n 2p "$1" | awk '{print $2}' ;;
    *.ply) grep -a -m1 '^element face' "$1" | awk '{print $3}' ;;
  esac
}
mk() { [ -e "$2" ] || "$SK" subdivide "$M/$1.off" -o "$2" -n "$3" -q; }

if [ $quick = 1 ]; then
  DISK=$S/lion-head-s2.off; mk lion-head "$DISK" 2
  CDISK=$S/lion-head-s1.off; mk lion-head "$CDISK" 1
  CLOSED=$S/armadillo-s1.ply; mk armadillo "$CLOSED" 1
  CGAL_BIG="" MIPS_MESHES="$M/lion-head.off" ATLAS="cow knot1" EXPORT="cow" FIT="nefertiti"
else
  DISK=$S/lion-head-s3.off; mk lion-head "$DISK" 3
  CDISK=$S/lion-head-s2.off; mk lion-head "$CDISK" 2
  CLOSED=$S/armadillo-s2.ply; mk armadillo "$CLOSED" 2
  CGAL_BIG="mvc" MIPS_MESHES="$M/lion-head.off $DISK" ATLAS="cow bunny00 armadillo" EXPORT="cow nefertiti"
  FIT="nefertiti lion-head"
fi
READ=$S/read-$(basename "${DISK%.off}")
[ -e "$READ.ply" ] || "$SK" convert "$DISK" "$READ.ply"
[ -e "$READ.obj" ] || "$SK" convert "$DISK" "$READ.obj"

# --- read
for f in "$READ.ply" "$READ.obj"; do
  best="" bmb=""
  for rep in 1 2 3; do # best of three: the first run also pays for the page cache
    timed "$BB/bench_io" read "$f" || continue
    t=$(awk -F'|' '{print $7 + 0}' "$S/out.txt")
    if [ -z "$best" ] || awk "BEGIN{exit !($t < $best)}"; then best=$t bmb=$MB; fi
  done
  pbest="" pmb="-"
  if [ -x "$BB/openmesh_read" ]; then
    for rep in 1 2 3; do
      timed "$BB/openmesh_read" "$f" || continue
      t=$(awk '{print $3}' "$S/out.txt")
      if [ -z "$pbest" ] || awk "BEGIN{exit !($t < $pbest)}"; then pbest=$t pmb=$MB; fi
    done
  fi
  row "read ${f##*.}" "$(basename "$f")" "$(faces_of "$DISK")" "${best:--}" "${bmb:--}" "OpenMesh read_mesh" "${pbest:--}" "$pmb" \
    "$(du -m "$f" | cut -f1) MB file, best of 3"
done

# --- hierarchy
if timed "$BB/bench_hierarchy" "$CLOSED" --repeat 1; then
  ours=$(sed -n 's/.*build \([0-9.]*\) s.*/\1/p' "$S/out.txt") omb=$MB
  lv=$(sed -n 's/.*: \([0-9]*\) levels, \([0-9]* -> [0-9]*\) faces.*/\1 levels, \2/p' "$S/out.txt")
  peer=- pmb=- plv=""
  if [ -x "$BB/openmesh_hierarchy" ] && timed "$BB/openmesh_hierarchy" "$CLOSED"; then
    peer=$(sed -n 's/.*build \([0-9.]*\) s.*/\1/p' "$S/out.txt") pmb=$MB
    plv=$(sed -n 's/.*: \([0-9]*\) levels, \([0-9]* -> [0-9]*\) faces.*/\1 levels, \2/p' "$S/out.txt")
  fi
  row hierarchy "$(basename "$CLOSED")" "$(faces_of "$CLOSED")" "$ours" "$omb" "OpenMesh DecimaterT+ModIndependentSetsT" "$peer" "$pmb" \
    "surfkit $lv; OpenMesh ${plv:--}"
fi

# --- linear methods
cgal_of() { case $1 in floater) echo mvc ;; *) echo "$1" ;; esac; }
declare -A CG_S CG_MB CG_Q
cgal_run() { # mesh method -> CG_S/CG_MB/CG_Q[mesh:method]
  local key="$1:$2"
  [ -n "${CG_S[$key]:-}" ] && return 0
  CG_S[$key]=- CG_MB[$key]=- CG_Q[$key]=""
  [ -x "$BB/cgal_param" ] || return 0
  local MB WALL cmm cfl
  if timed "$BB/cgal_param" "$1" "$2" "$S/cgal.bin"; then
    CG_S[$key]=$(tail -1 "$S/out.txt") CG_MB[$key]=$MB
    read -r _ cmm cfl < <("$BB/bench_param" --uv "$1" "$S/cgal.bin")
    CG_Q[$key]="CGAL MIPS mean $(printf %.4f "$cmm"), flips $cfl"
  fi
}
linear_rows() { # mesh methods cgal-methods
  local mesh=$1 me solver faces total it res mm fl
  for me in $2; do
    for solver in direct hierarchical amg auto; do
      timed "$BB/bench_linear" "$mesh" "$me" "$solver" || continue
      read -r _ faces _ _ _ _ _ _ _ _ total _ it res _ mm fl _ _ < "$S/out.txt"
      local omb=$MB
      local cm peer=- pmb=- pq="" pname="-"
      cm=$(cgal_of "$me")
      if [[ " $3 " == *" $cm "* ]]; then
        cgal_run "$mesh" "$cm"
        peer=${CG_S[$mesh:$cm]} pmb=${CG_MB[$mesh:$cm]} pq="; ${CG_Q[$mesh:$cm]}" pname="CGAL $cm"
      fi
      row "linear $me $solver" "$(basename "$mesh")" "$faces" "$total" "$omb" "$pname" "$peer" "$pmb" \
        "MIPS mean $(printf %.4f "$mm"), flips $fl$([ "$solver" != direct ] && echo ", $it iterations, residual $res")$pq"
    done
  done
}
if [ $quick = 1 ]; then # the 67k disk only, every method beside CGAL's
  linear_rows "$CDISK" "tutte floater mvc harmonic lscm" "tutte mvc harmonic lscm"
else
  linear_rows "$DISK" "tutte floater mvc harmonic lscm" "$CGAL_BIG"
  linear_rows "$CDISK" "tutte floater mvc harmonic lscm" "tutte mvc harmonic lscm"
fi

# --- MIPS (free boundary)
for mesh in $MIPS_MESHES; do
  timed "$SK" param "$mesh" -o "$S/mips.obj" --method mips --report "$S/mips.json" -q || continue
  read -r secs mm fl < <(python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); print(d["seconds"], d["mips_mean"], d["flipped"])' "$S/mips.json")
  omb=$MB
  peers="dcm arap"; [ "$(faces_of "$mesh")" -gt 100000 ] && peers="dcm"
  for pm in $peers; do
    peer=- pmb=- pq=""
    if [ -x "$BB/cgal_mips" ] && timed timeout 600 "$BB/cgal_mips" "$mesh" "$pm" "$S/cgal.bin"; then
      peer=$(tail -1 "$S/out.txt") pmb=$MB
      read -r _ pmm pfl < <("$BB/bench_param" --uv "$mesh" "$S/cgal.bin")
      pq="; CGAL MIPS mean $(printf %.4f "$pmm"), flips $pfl"
    fi
    row "mips (free boundary)" "$(basename "$mesh")" "$(faces_of "$mesh")" "$(printf %.3f "$secs")" "$omb" \
      "CGAL $([ $pm = dcm ] && echo 'discrete conformal' || echo ARAP)" "$peer" "$pmb" \
      "MIPS mean $(printf %.4f "$mm"), flips $fl$pq"
  done
done

# --- atlas (bench/atlas.sh with its machine-readable rows)
arows=$S/atlas-rows.txt
: > "$arows"
SK_BUILD_DIR=$B SK_ATLAS_SCRATCH=$S/atlas SK_BENCH_ROWS=$arows bench/atlas.sh $(for m in $ATLAS; do echo "$M/$m.off"; done) > "$S/atlas.txt" 2>&1 ||
  echo "# bench/atlas.sh failed: $(tail -1 "$S/atlas.txt")"
if [ $quick = 0 ]; then # the 0.8M closed mesh: Blender only (xatlas-web takes it only in pieces, for hours)
  SK_BUILD_DIR=$B SK_ATLAS_SCRATCH=$S/atlas SK_BENCH_ROWS=$arows SK_ATLAS_PEERS=blender bench/atlas.sh "$CLOSED" >> "$S/atlas.txt" 2>&1 || true
fi
awk '$3 == "surfkit" { s[$2] = $0 } $3 != "surfkit" && ($2 in s) {
  split(s[$2], a, " ")
  printf "atlas\t%s\t%s\t%s\t%s\t%s\t%s\t%s\tcharts %s / %s, MIPS mean %.4f / %.4f, area-log %.4f / %.4f, flips %s / %s (mirrored charts %s / %s), overlaps %s / %s, util %.3f / %.3f\n",
    $2, a[4], a[12], a[13], $3, $12, $13, a[5], $5, a[7], $7, a[8], $8, a[9], $9, a[14], $14, a[10], $10, a[11], $11
}' "$arows" >> "$ROWS"

# --- VC1 build and report
if timed "$BB/bench_smooth" "$CLOSED"; then
  b=$(sed -n 's/^| total build *| *\([0-9.]*\) |.*/\1/p' "$S/out.txt")
  br=$(sed -n 's/^| build + report *| *\([0-9.]*\) |.*/\1/p' "$S/out.txt")
  jump=$(sed -n 's/^max normal jump \([^ ]*\) deg.*singular patches \([0-9]*\).*/max normal jump \1 deg, singular patches \2/p' "$S/out.txt")
  row "vc1 build" "$(basename "$CLOSED")" "$(faces_of "$CLOSED")" "$b" "$MB" "(no peer)" - - "$jump"
  row "vc1 build + report" "$(basename "$CLOSED")" "$(faces_of "$CLOSED")" "$br" "$MB" "(no peer)" - - ""
fi

# --- export: our writer vs Open CASCADE's writer of the same surfaces
for mesh in $EXPORT; do
  timed "$BB/bench_export" "$M/$mesh.off" "$S" 1 || continue
  omb=$MB
  while IFS='|' read -r _ name fmt tris faces kb _ cpu wall _; do
    fmt=$(echo $fmt) f="$S/$(echo $name).$fmt"
    peer=- pmb=- note=""
    if command -v freecadcmd >/dev/null; then
      rm -f "$S/occt.json"
      HOME=$S/home SK_IN=$f SK_REWRITE=$S/occt-rewrite.$fmt SK_OUT=$S/occt.json \
        /usr/bin/time -f "%e %M" -o "$S/time.txt" timeout 900 freecadcmd bench/peers/occt_rewrite.py > "$S/fc.log" 2>&1
      if [ -s "$S/occt.json" ]; then
        read -r peer pf pkb < <(python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); print("%.3f" % d["seconds"], d["faces"], d["bytes"] // 1000)' "$S/occt.json")
        pmb=$(( $(tail -1 "$S/time.txt" | awk '{print $2}') / 1024 ))
        note="surfkit $(echo $faces) faces $(echo $kb) KB; OCCT $pf faces $pkb KB (peak MB includes its read)"
      fi
    fi
    row "export $fmt (writer)" "$mesh.off" "$(echo $tris)" "$(echo $wall)" "$omb" "OCCT $( [ $fmt = step ] && echo STEPControl_Writer || echo IGESControl_Writer)" "$peer" "$pmb" "$note"
  done < "$S/out.txt"
done

# --- fit (bench/approx.sh with its machine-readable rows)
frows=$S/fit-rows.txt
: > "$frows"
BUILD=$B MESHES="$FIT" RELS=1e-3 SK_BENCH_ROWS=$frows bench/approx.sh "$S/approx" > "$S/approx.txt" 2>&1 ||
  echo "# bench/approx.sh failed: $(tail -1 "$S/approx.txt")"
cat "$frows" >> "$ROWS"

echo "# load average at end: $(cut -d' ' -f1-3 /proc/loadavg); $(( $(date +%s) - t_start )) s in all"
echo
echo "| figure | mesh | faces | surfkit s | surfkit peak MB | peer | peer s | peer peak MB | ratio | notes |"
echo "|---|---|---:|---:|---:|---|---:|---:|---:|---|"
awk -F'\t' '{
  r = ($4 + 0 > 0 && $7 ~ /^[0-9.]+$/) ? sprintf("%.1fx", $7 / $4) : "-"
  printf "| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", $1, $2, $3, $4, $5, $6, $7, $8, r, $9
}' "$ROWS"
