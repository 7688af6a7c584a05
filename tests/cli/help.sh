#!/usr/bin/env bash
# Every subcommand's --help is generated from its option table and ends with "Examples:" and 2-4
# command lines; each of them runs (from a folder with the repository's data/) and exits 0.
# A mistyped option or choice value is a one-line usage error (exit 2) naming the option and
# the closest name ("did you mean").
set -u
bin=$1 src=$2 tmp=$4
rm -rf "$tmp"; mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
bindir=$(cd "$(dirname "$bin")" && pwd)
ln -s "$src/data" "$tmp/data"
for cmd in info convert subdivide simplify param smooth deviation view fit; do
  "$bin" $cmd --help > "$tmp/$cmd.help" || fail "$cmd --help exit"
  head -1 "$tmp/$cmd.help" | grep -q "^usage: surfkit $cmd " || fail "$cmd: usage line"
  grep -q '^options:$' "$tmp/$cmd.help" || fail "$cmd: no options list"
  sed -n '/^Examples:$/,$p' "$tmp/$cmd.help" | tail -n +2 > "$tmp/$cmd.ex"
  n=$(grep -c '^  surfkit ' "$tmp/$cmd.ex")
  [ "$n" -ge 2 ] && [ "$n" -le 4 ] || fail "$cmd: $n examples"
  [ "$(wc -l < "$tmp/$cmd.ex")" = "$n" ] || fail "$cmd: Examples is not the last section"
  while read -r line; do
    (cd "$tmp" && PATH="$bindir:$PATH" bash -c "$line" > "$tmp/out" 2> "$tmp/err") ||
      grep -q "built without the viewer" "$tmp/err" || fail "$cmd example '$line': $(cat "$tmp/err")"
  done < "$tmp/$cmd.ex"
done
# did you mean: options and choice values; one line, exit 2
cd "$tmp" || fail "cd"
check() { # expected-substring command...
  local want=$1; shift
  "$bindir/surfkit" "$@" > /dev/null 2> "$tmp/err"; local rc=$?
  [ $rc = 2 ] || fail "$*: exit $rc"
  [ "$(wc -l < "$tmp/err")" = 1 ] || fail "$*: not one line: $(cat "$tmp/err")"
  grep -qF -- "$want" "$tmp/err" || fail "$*: '$(cat "$tmp/err")' lacks '$want'"
}
check "unknown option '--tes' (did you mean --tess?)" smooth data/sphere.off -o x.obj --tes 3
check "unknown option '--levles' (did you mean --levels?)" simplify data/sphere.off -o x.off --levles 3
check "unknown option '--jsn' (did you mean --json?)" info data/sphere.off --jsn
check "unknown option '--max-strech' (did you mean --max-stretch?)" param data/sphere.off -o x.obj --max-strech=2
check "unknown option '--frobnicate'" info data/sphere.off --frobnicate
check "--scheme takes vc1 or pn, not 'pm' (did you mean pn?)" smooth data/sphere.off --json --scheme pm
check "--scheme takes loop or midpoint, not 'midpont' (did you mean midpoint?)" subdivide data/sphere.off -o x.off --scheme midpont
check "--method takes tutte, floater, mvc, harmonic, lscm or mips, not 'flaoter' (did you mean floater?)" param data/sphere.off -o x.obj --method flaoter
check "--tess takes a whole number from 1 to 64, not '0'" smooth data/sphere.off --json --tess 0
check "--tolerance takes a positive number" deviation a.off b.off --tolerance
check "--view takes three numbers X,Y,Z, not '1,2'" param data/nefertiti.off -o x.obj --view 1,2
check "needs IN -o OUT" simplify data/sphere.off
{ [ -e x.obj ] || [ -e x.off ]; } && fail "output after a usage error"
echo "help: ok"
