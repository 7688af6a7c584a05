#!/usr/bin/env bash
# `surfkit view`: the page opens in a real browser (headless Chromium with the network mapped
# away: the page must not need it) and renders the model: the page reports what it drew (body
# data-status: rendered, layers, fraction of pixels covered, errors) and we check it; the
# screenshots stay in the test folder to look at. Bad input exits 1 and writes no page; usage
# errors exit 2. Skipped (77) when Chromium is not installed (scripts/setup.sh installs it).
set -u
bin=$1 src=$2 shared=$3 tmp=$4
rm -rf "$tmp"; mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
m=$shared/data/meshes
browser=$(command -v chromium || command -v chromium-browser || true)

"$bin" view "$src/data/sphere.off" --smooth -o "$tmp/sphere.html" -q > /dev/null || fail "view sphere"
"$bin" param "$m/lion-head.off" -o "$tmp/lion-uv.obj" -q > /dev/null || fail "param lion-head"
"$bin" view "$tmp/lion-uv.obj" -o "$tmp/lion.html" -q > /dev/null || fail "view uv"
"$bin" view "$m/cow.off" --uv "$tmp/lion-uv.obj" -o "$tmp/bad.html" -q 2> "$tmp/err"
[ $? = 1 ] || fail "--uv of another mesh accepted"
grep -q "not a parametrization" "$tmp/err" || fail "--uv message: $(cat "$tmp/err")"
printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n' > "$tmp/broken.off"
"$bin" view "$tmp/broken.off" -o "$tmp/broken.html" 2> "$tmp/err"; [ $? = 1 ] || fail "bad input"
[ "$(wc -l < "$tmp/err")" = 1 ] && grep -q broken.off "$tmp/err" || fail "bad input message"
[ -e "$tmp/broken.html" ] && fail "page written for bad input"
"$bin" view "$m/cow.off" -o "$tmp/x.png" 2> /dev/null; [ $? = 2 ] || fail "-o x.png"
grep -q '<script src=' "$tmp/sphere.html" && fail "the page loads a script from elsewhere"

[ -n "$browser" ] || { echo "SKIP: no chromium (scripts/setup.sh installs it)"; exit 77; }
open_page() { # page screenshot -> prints the page's data-status
    local prof; prof=$(mktemp -d "$tmp/profile.XXXXXX")
    local flags=(--headless --no-sandbox --disable-gpu --use-angle=swiftshader
                 --enable-unsafe-swiftshader --disable-quic --no-first-run
                 --disable-background-networking --disable-component-update --disable-sync
                 --host-resolver-rules="MAP * ~NOTFOUND" --user-data-dir="$prof"
                 --window-size=1000,750 --virtual-time-budget=20000)
    timeout 120 "$browser" "${flags[@]}" --screenshot="$2" "file://$1" > /dev/null 2>&1
    timeout 120 "$browser" "${flags[@]}" --dump-dom "file://$1" 2> /dev/null |
        sed -n 's/.*data-status="\([^"]*\)".*/\1/p' | sed 's/&quot;/"/g'
}
check() { # status key-pattern description
    echo "$1" | grep -q "$2" || fail "$3: status $1"
}
st=$(open_page "$tmp/sphere.html" "$tmp/sphere.png")
check "$st" '"rendered":true' "sphere not rendered"
check "$st" '"errors":\[\]' "sphere: errors"
check "$st" '"shown":"zebra"' "sphere: zebra not the first view"
for l in mesh surface zebra deviation "patch boundaries"; do check "$st" "\"$l\"" "sphere: layer $l"; done
cov=$(echo "$st" | sed 's/.*"covered":\([0-9.e-]*\).*/\1/')
awk -v c="$cov" 'BEGIN { exit !(c > 0.2 && c < 0.95) }' || fail "sphere covers $cov of the page"
[ -s "$tmp/sphere.png" ] || fail "no screenshot"

st=$(open_page "$tmp/lion.html" "$tmp/lion.png")
check "$st" '"rendered":true' "lion-head not rendered"
check "$st" '"errors":\[\]' "lion-head: errors"
check "$st" '"shown":"uv checkerboard"' "lion-head: checkerboard not the first view"
check "$st" '"uv distortion"' "lion-head: no distortion layer"
check "$st" '"triangles":16674' "lion-head: triangle count"
cov=$(echo "$st" | sed 's/.*"covered":\([0-9.e-]*\).*/\1/')
awk -v c="$cov" 'BEGIN { exit !(c > 0.05) }' || fail "lion-head covers $cov of the page"
echo "view: ok"
