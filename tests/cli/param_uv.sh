#!/usr/bin/env bash
# surfkit param writes uv normalized to the unit square for every method (nefertiti, lion-head),
# --no-normalize keeps the raw scale, PLY has s t, formats without uv are refused.
set -u
bin=$1 src=$2 shared=$3 tmp=$4
rm -rf "$tmp"; mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
m=$shared/data/meshes
# uv box of an OBJ's vt lines: "umin umax vmin vmax"
box() { awk '/^vt /{if(!n){a=$2;b=$2;c=$3;d=$3};n++; if($2<a)a=$2; if($2>b)b=$2; if($3<c)c=$3; if($3>d)d=$3} END{print a, b, c, d}' "$1"; }
unit() { awk -v s="$1" 'BEGIN{split(s,x," "); exit !(x[1]==0 && x[3]==0 && x[2]<=1 && x[4]<=1 && (x[2]==1 || x[4]==1))}'; }
for mesh in nefertiti lion-head; do
    for meth in tutte floater mvc harmonic lscm mips mips-flat; do
        extra=()
        case $meth in mips-flat) extra=(--method mips --flat) ;; *) extra=(--method "$meth") ;; esac
        "$bin" param "$m/$mesh.off" -o "$tmp/$mesh-$meth.obj" "${extra[@]}" --report "$tmp/$mesh-$meth.json" -q ||
            fail "$mesh $meth run"
        b=$(box "$tmp/$mesh-$meth.obj")
        unit "$b" || fail "$mesh $meth: uv box $b is not in the unit square with extent 1"
    done
done
# the MIPS energy is that of the raw map (normalization is a similarity)
"$bin" param "$m/nefertiti.off" -o "$tmp/raw.obj" --method mips --no-normalize --report "$tmp/raw.json" -q || fail "raw run"
val() { grep "\"$1\": " "$2" | head -1 | sed 's/.*: //; s/,$//'; }
a=$(val mips_sum "$tmp/raw.json") b=$(val mips_sum "$tmp/nefertiti-mips.json")
awk "BEGIN{d=$a-$b; if(d<0)d=-d; exit !(d <= 1e-11*$a)}" || fail "mips_sum raw $a, normalized $b"
# --no-normalize: floater keeps its unit circle
"$bin" param "$m/nefertiti.off" -o "$tmp/c.obj" --no-normalize -q || fail "floater raw"
b=$(box "$tmp/c.obj")
awk -v s="$b" 'BEGIN{split(s,x," "); exit !(x[1]<-0.99 && x[2]>0.99 && x[3]<-0.99 && x[4]>0.99)}' ||
    fail "--no-normalize floater box $b is not the unit circle's"
# PLY: s t, normalized
"$bin" param "$m/nefertiti.off" -o "$tmp/n.ply" --method mips --ascii -q || fail "ply"
grep -q '^property double s$' "$tmp/n.ply" && grep -q '^property double t$' "$tmp/n.ply" || fail "PLY lacks s t"
grep -q '^property double u$' "$tmp/n.ply" && fail "PLY still has u"
"$bin" convert "$tmp/n.ply" "$tmp/n2.obj" || fail "PLY s t read back"
unit "$(box "$tmp/n2.obj")" || fail "PLY uv read back: $(box "$tmp/n2.obj")"
# formats without uv are refused: usage error naming the format, no file
for ext in stl off; do
    "$bin" param "$m/nefertiti.off" -o "$tmp/x.$ext" 2> "$tmp/err"; rc=$?
    [ $rc = 2 ] || fail ".$ext exit code $rc"
    [ "$(wc -l < "$tmp/err")" = 1 ] || fail ".$ext message is not one line: $(cat "$tmp/err")"
    grep -qi "${ext^^} cannot hold texture coordinates" "$tmp/err" || fail ".$ext message: $(cat "$tmp/err")"
    [ -e "$tmp/x.$ext" ] && fail ".$ext file written"
done
# flipped triangles (harmonic on three_peaks flips 33): the output is written, a warning on
# stderr, exit 0 (the policy --help states)
"$bin" param "$m/three_peaks.off" -o "$tmp/t.obj" --method harmonic --report "$tmp/t.json" -q 2> "$tmp/err"; rc=$?
[ $rc = 0 ] || fail "flips: exit code $rc"
[ -s "$tmp/t.obj" ] || fail "flips: no output written"
[ "$(grep -c '^vt ' "$tmp/t.obj")" = "$(grep -c '^v ' "$tmp/t.obj")" ] || fail "flips: vt count"
grep -q 'warning: .*three_peaks.off: 33 of 3671 triangles flipped (harmonic)' "$tmp/err" || fail "flips warning: $(cat "$tmp/err")"
[ "$(val flipped "$tmp/t.json")" = 33 ] || fail "flips: report says $(val flipped "$tmp/t.json")"
"$bin" param --help | grep -q 'Flipped triangles.*OUT and the pictures' || fail "--help lacks the flip policy"
# option legality comes from the library (sk_parametrize_check): usage errors, exit 2
"$bin" param "$m/nefertiti.off" -o "$tmp/x.obj" --method lscm --boundary square 2> "$tmp/err"; [ $? = 2 ] || fail "lscm square exit"
grep -q 'lscm has a free boundary' "$tmp/err" || fail "lscm square message: $(cat "$tmp/err")"
"$bin" param "$m/nefertiti.off" -o "$tmp/x.obj" --steps 10 2> "$tmp/err"; [ $? = 2 ] || fail "--steps without mips exit"
[ -e "$tmp/x.obj" ] && fail "output after a usage error"
echo "param uv: every method in the unit square on nefertiti and lion-head; ok"
