#!/usr/bin/env bash
# `surfkit simplify`: report keys and level list (finest first), --levels / --faces stop rules, the
# same seed gives the same bytes, --all-levels writes every level with the input's Euler
# characteristic and boundary loops and the finest equals the input's counts, bad input exits 1
# with one line, usage errors exit 2.
set -u
bin=$1 shared=$3 tmp=$4
rm -rf "$tmp"; mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
val() { grep "\"$1\": " "$2" | head -1 | sed 's/.*: //; s/,$//'; }
m=$shared/data/meshes

"$bin" simplify "$m/lion.off" -o "$tmp/lion0.ply" --report "$tmp/r.json" -q || fail "simplify lion"
[ -s "$tmp/lion0.ply" ] || fail "no output"
grep -q '"levels": \[' "$tmp/r.json" || fail "no levels list"
for key in vertices faces seconds; do grep -q "\"$key\": " "$tmp/r.json" || fail "key $key"; done
first_faces=$(grep '"faces": ' "$tmp/r.json" | head -1 | sed 's/.*: //; s/,$//')
[ "$first_faces" = 14859 ] || fail "first level is not the input ($first_faces faces)"
n=$(val num_levels "$tmp/r.json")
[ "$(grep -c '"faces": ' "$tmp/r.json")" = "$n" ] || fail "level list length"

# the same seed gives the same file; --levels K gives K levels
"$bin" simplify "$m/lion.off" -o "$tmp/a.off" --seed 5 -q || fail "seed 5"
"$bin" simplify "$m/lion.off" -o "$tmp/b.off" --seed 5 -q || fail "seed 5 again"
cmp -s "$tmp/a.off" "$tmp/b.off" || fail "same seed, different output"
"$bin" simplify "$m/lion.off" -o "$tmp/c.off" --seed 6 -q || fail "seed 6"
cmp -s "$tmp/a.off" "$tmp/c.off" && fail "another seed, same output"
"$bin" simplify "$m/cow.off" -o "$tmp/cow.off" --levels 4 --report "$tmp/cow.json" -q || fail "--levels"
[ "$(val num_levels "$tmp/cow.json")" = 4 ] || fail "--levels 4"
"$bin" simplify "$m/cow.off" -o "$tmp/cow.off" --faces 1000 --report "$tmp/cow.json" -q || fail "--faces"
last=$(grep '"faces": ' "$tmp/cow.json" | tail -1 | sed 's/.*: //; s/,$//')
prev=$(grep '"faces": ' "$tmp/cow.json" | tail -2 | head -1 | sed 's/.*: //; s/,$//')
[ "$last" -le 1000 ] && [ "$prev" -gt 1000 ] || fail "--faces 1000: last levels $prev $last"

# every level of a mesh with holes: chi and loops kept; the finest is the input
"$bin" simplify "$m/mech-holes-shark.off" -o "$tmp/shark.off" --all-levels "$tmp/levels" \
  --report "$tmp/shark.json" -q || fail "--all-levels"
n=$(val num_levels "$tmp/shark.json")
[ "$(ls "$tmp/levels" | wc -l)" = "$n" ] || fail "level files"
for f in "$tmp"/levels/level_*.off; do
  "$bin" info --json "$f" >"$tmp/i.json" || fail "info $f"
  [ "$(val euler_characteristic "$tmp/i.json")" = -2 ] || fail "chi of $f"
  [ "$(val boundary_loops "$tmp/i.json")" = 4 ] || fail "loops of $f"
  [ "$(val manifold "$tmp/i.json")" = true ] || fail "manifold $f"
done
last=$(ls "$tmp"/levels/level_*.off | tail -1)
"$bin" info --json "$last" >"$tmp/i.json"
[ "$(val vertices "$tmp/i.json")" = 5246 ] && [ "$(val faces "$tmp/i.json")" = 10192 ] || fail "finest level"
cmp -s "$tmp/shark.off" "$tmp/levels/level_00.off" || fail "level 0 is not the output"

# bad input and usage
printf 'OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n' >"$tmp/quad.off"
# (a quad is triangulated on the way in; --keep-polygons refuses it as before: tests/cli/polygons.sh)
"$bin" simplify "$tmp/quad.off" -o "$tmp/t.off" -q || fail "quad mesh: not triangulated"
[ "$(sed -n 2p "$tmp/t.off" | cut -d' ' -f2)" -le 2 ] || fail "quad mesh: $(sed -n 2p "$tmp/t.off")"
"$bin" simplify "$tmp/quad.off" -o "$tmp/q.off" --keep-polygons 2>"$tmp/err"; rc=$?
[ $rc = 1 ] || fail "quad mesh: exit $rc"
[ "$(wc -l <"$tmp/err")" = 1 ] || fail "quad mesh: more than one line"
[ ! -e "$tmp/q.off" ] || fail "quad mesh left an output"
"$bin" simplify "$m/nonexistent.off" -o "$tmp/q.off" 2>/dev/null; [ $? = 1 ] || fail "missing file"
"$bin" simplify "$m/cow.off" 2>/dev/null; [ $? = 2 ] || fail "no -o"
"$bin" simplify "$m/cow.off" -o "$tmp/x.off" --levels 0 2>/dev/null; [ $? = 2 ] || fail "--levels 0"
"$bin" simplify "$m/cow.off" -o "$tmp/x.off" --levels 3 --faces 10 2>/dev/null; [ $? = 2 ] || fail "both"
"$bin" simplify "$m/cow.off" -o "$tmp/x.off" --bogus 2>/dev/null; [ $? = 2 ] || fail "unknown option"
"$bin" simplify --help | grep -q "usage: surfkit simplify" || fail "--help"
echo "simplify: ok"
