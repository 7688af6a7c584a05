#!/usr/bin/env bash
# cmake --install into a temporary prefix, then two consumers outside the project: C through
# pkg-config (shared, and static with --static), C++ through find_package(surfkit) (shared and
# static targets); all run on a shared mesh and must print the installed tool's numbers.
# Usage: run.sh BUILD_DIR SOURCE_DIR SHARED_DIR TMP CC CMAKE
set -u
build=$1 src=$2 shared=$3 tmp=$4 cc=$5 cmake=$6
rm -rf "$tmp"; mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
p=$tmp/prefix mesh=$shared/data/meshes/lion-head.off
"$cmake" --install "$build" --prefix "$p" >"$tmp/install.log" || { cat "$tmp/install.log"; fail "install"; }

version=$(sed -n 's/^#define SK_VERSION_STRING "\(.*\)"$/\1/p' "$src/include/surfkit/core.h")
IFS=. read -r major minor _ <<<"$version"
for f in include/surfkit/surfkit.h include/surfkit/core.h bin/surfkit lib/libsurfkit.a \
         "lib/libsurfkit.so.$version" lib/pkgconfig/surfkit.pc lib/cmake/surfkit/surfkitConfig.cmake \
         lib/cmake/surfkit/surfkitConfigVersion.cmake; do
  [ -e "$p/$f" ] || fail "not installed: $f"
done
[ "$(readlink "$p/lib/libsurfkit.so")" = "libsurfkit.so.$major.$minor" ] || fail "libsurfkit.so link"
readelf -d "$p/lib/libsurfkit.so" | grep -q "SONAME.*\[libsurfkit.so.$major.$minor\]" || fail "SONAME"
[ "$("$p/bin/surfkit" --version)" = "surfkit $version" ] || fail "surfkit --version"

# what the installed tool says about the mesh
"$p/bin/surfkit" info --json "$mesh" >"$tmp/info.json" || fail "installed surfkit info"
val() { grep "\"$1\": " "$tmp/info.json" | head -1 | sed 's/.*: //; s/,$//'; }
expect="$version V $(val vertices) E $(val edges) F $(val faces) genus $(val genus)"

export PKG_CONFIG_PATH=$p/lib/pkgconfig
[ "$(pkg-config --modversion surfkit)" = "$version" ] || fail "pkg-config --modversion"
# shellcheck disable=SC2046
"$cc" -std=c11 -Wall -Wextra -Werror "$src/tests/install/consumer.c" -o "$tmp/consumer" \
  $(pkg-config --cflags --libs surfkit) -lm || fail "C consumer (pkg-config) does not build"
readelf -d "$tmp/consumer" | grep -q 'NEEDED.*libsurfkit.so' || fail "C consumer not linked to libsurfkit.so"
out=$(LD_LIBRARY_PATH=$p/lib "$tmp/consumer" "$mesh") || fail "C consumer run"
[ "${out% uvmax *}" = "$expect" ] || fail "C consumer printed '$out', the tool '$expect'"
uvmax=${out##* uvmax }
[ "$uvmax" = "1.000000" ] || fail "Floater on the unit circle: max |uv| is $uvmax"

# static: libsurfkit.a and the private dependencies from pkg-config --static
libs=$(pkg-config --static --libs surfkit | sed 's/ -lsurfkit / /; s/^-lsurfkit //')
# shellcheck disable=SC2086
"$cc" -std=c11 -Wall -Wextra -Werror "$src/tests/install/consumer.c" -o "$tmp/consumer_static" \
  $(pkg-config --cflags surfkit) "$p/lib/libsurfkit.a" $libs -lm || fail "C consumer (static) does not build"
readelf -d "$tmp/consumer_static" | grep -q 'NEEDED.*libsurfkit' && fail "static consumer needs libsurfkit.so"
[ "$("$tmp/consumer_static" "$mesh")" = "$out" ] || fail "static C consumer differs"

# C++ with find_package(surfkit)
"$cmake" -S "$src/tests/install/cxx" -B "$tmp/cxx" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$p" >"$tmp/cxx.log" 2>&1 || { cat "$tmp/cxx.log"; fail "find_package(surfkit)"; }
"$cmake" --build "$tmp/cxx" >>"$tmp/cxx.log" 2>&1 || { cat "$tmp/cxx.log"; fail "C++ consumer does not build"; }
for exe in consumer_cxx consumer_cxx_static; do
  got=$("$tmp/cxx/$exe" "$mesh") || fail "$exe run"
  [ "$got" = "$expect" ] || fail "$exe printed '$got', the tool '$expect'"
done
readelf -d "$tmp/cxx/consumer_cxx" | grep -q 'NEEDED.*libsurfkit.so' || fail "consumer_cxx not shared"
readelf -d "$tmp/cxx/consumer_cxx_static" | grep -q 'NEEDED.*libsurfkit' && fail "consumer_cxx_static needs the .so"
"$tmp/cxx/consumer_cxx" "$shared/data/meshes/no-such.off" 2>"$tmp/err" && fail "missing file accepted"
grep -q 'no-such.off' "$tmp/err" || fail "error message does not name the file: $(cat "$tmp/err")"
echo "ok: installed $version; C (pkg-config, shared + static) and C++ (find_package, shared + static) consumers print: $expect"
