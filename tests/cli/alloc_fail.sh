#!/usr/bin/env bash
# Allocation failure through the whole CLI (issue 17): `surfkit info` with the library's K-th
# allocation failing (SURFKIT_FAIL_ALLOC=K, cli/fault_alloc.c), for every K the run makes, over
# meshes that reach every part of the report (boundary loops, defects, each reader): every run
# either exits 3 with one line "out of memory" and prints no report, or exits 0 with exactly the
# reference output. Never a crash, never exit 1, never a different report.
set -u
bin=$1 src=$2 shared=$3 tmp=$4
rm -rf "$tmp"; mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
inputs="$shared/data/meshes/holes.off $shared/data/meshes/nefertiti.off
  $src/tests/data/good/disk_plus_repeated_vertex.off $src/tests/data/good/repeated_vertex_only.off
  $src/tests/data/good/tet_binary_le.ply $src/tests/data/good/tet_ascii.stl
  $src/tests/data/good/forms.obj"
# SK_TEST_QUICK (the sanitizer run): three inputs that still reach every reader path of info
[ -n "${SK_TEST_QUICK:-}" ] && inputs="$shared/data/meshes/holes.off
  $src/tests/data/good/disk_plus_repeated_vertex.off $src/tests/data/good/tet_binary_le.ply"
runs=0 nomem=0 exact=0
for f in $inputs; do
  for mode in text json; do
    opt=; [ $mode = json ] && opt=--json
    "$bin" info $opt "$f" >"$tmp/ref" 2>"$tmp/referr" || fail "reference run on $f: exit $?"
    n=$(SURFKIT_FAIL_ALLOC=count "$bin" info $opt "$f" 2>&1 >/dev/null | sed -n 's/^surfkit: allocations //p')
    [ -n "$n" ] && [ "$n" -gt 0 ] || fail "no allocation count for $f"
    for k in $(seq 1 "$n"); do
      SURFKIT_FAIL_ALLOC=$k timeout 60 "$bin" info $opt "$f" >"$tmp/out" 2>"$tmp/err"; rc=$?
      runs=$((runs + 1))
      case $rc in
      0) cmp -s "$tmp/ref" "$tmp/out" || fail "$f $mode k=$k: exit 0 with a different report: $(diff "$tmp/ref" "$tmp/out" | head -4)"
         exact=$((exact + 1)) ;;
      3) [ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -q "out of memory" "$tmp/err" \
           || fail "$f $mode k=$k: exit 3 with: $(head -c 300 "$tmp/err")"
         [ ! -s "$tmp/out" ] || fail "$f $mode k=$k: exit 3 but printed a report"
         nomem=$((nomem + 1)) ;;
      *) fail "$f $mode k=$k: exit $rc (want 3 or 0): $(head -c 300 "$tmp/err")" ;;
      esac
    done
  done
done
[ $nomem -gt 0 ] || fail "no run failed: the injection did not reach the library"
rm -rf "$tmp"
echo "alloc_fail CLI: ok ($runs runs: $nomem out of memory, $exact identical to the reference)"
