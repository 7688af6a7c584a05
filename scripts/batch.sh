#!/usr/bin/env bash
# Runs one surfkit command over every mesh in a folder with GNU parallel (Debian `parallel`), one
# independent job per mesh, and collects each job's JSON summary, error line and exit code.
# A bad input fails only its own job; nothing else is lost.
#
#   scripts/batch.sh IN_DIR OUT_DIR [JOBS] -- SURFKIT_ARGS...
#
# SURFKIT_ARGS is the command with {} for the input file and {/.} for its name without
# extension, e.g.  scripts/batch.sh scans out -- param {} -o out/{/.}.obj --json
# Writes OUT_DIR/<name>.json (the job's stdout), OUT_DIR/<name>.err (its stderr),
# OUT_DIR/joblog.tsv (parallel's job log: start time and run time of each job) and
# OUT_DIR/summary.tsv (name, exit code: `lost` if a job never ran); exits 0 when every job succeeded, else 1.
# env: SURFKIT (the tool; default build/surfkit, else surfkit on the PATH).
set -euo pipefail
[ $# -ge 4 ] || { sed -n '2,14p' "$0"; exit 2; }
in=$1 out=$2; shift 2
jobs=$(nproc 2>/dev/null || echo 2)
if [ "$1" != -- ]; then jobs=$1; shift; fi
[ "$1" = -- ] || { echo "batch: expected -- before the surfkit arguments" >&2; exit 2; }
shift
here=$(cd "$(dirname "$0")/.." && pwd)
sk=${SURFKIT:-$here/build/surfkit}
[ -x "$sk" ] || sk=$(command -v surfkit) || { echo "batch: no surfkit tool found" >&2; exit 2; }
command -v parallel > /dev/null || { echo "batch: GNU parallel is not installed (apt-get install parallel)" >&2; exit 2; }
mkdir -p "$out"
shopt -s nullglob
files=("$in"/*.off "$in"/*.obj "$in"/*.ply "$in"/*.stl)
[ ${#files[@]} -gt 0 ] || { echo "batch: no mesh files in $in" >&2; exit 2; }
# --halt never: one failure does not stop the others; each job's streams and exit code go to
# its own files (<name>.json, <name>.err, <name>.code)
parallel --will-cite --halt never -j "$jobs" --joblog "$out/joblog.tsv" \
  "\"$sk\" $* -q > \"$out\"/{/.}.json 2> \"$out\"/{/.}.err; echo \$? > \"$out\"/{/.}.code" \
  ::: "${files[@]}"
for f in "${files[@]}"; do
  n=$(basename "${f%.*}")
  printf '%s\t%s\n' "$n" "$(cat "$out/$n.code" 2> /dev/null || echo lost)"
  rm -f "$out/$n.code"
done | sort > "$out/summary.tsv"
bad=$(awk -F'\t' '$2 != 0' "$out/summary.tsv" | wc -l)
echo "batch: ${#files[@]} inputs, $((${#files[@]} - bad)) succeeded, $bad failed (see $out/summary.tsv)"
[ "$bad" = 0 ]
