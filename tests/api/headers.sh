#!/usr/bin/env bash
# Every public header compiles on its own (included first, and twice: include guards) as C11
# -pedantic and as C++11 -pedantic with warnings as errors, and every header that declares
# functions wraps them in extern "C" for C++.
# Usage: headers.sh INCLUDE_DIR CC CXX TMP
set -u
inc=$1 cc=$2 cxx=$3 tmp=$4
rm -rf "$tmp"; mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
flags=(-Wall -Wextra -Werror -Wshadow -Wundef -I"$inc")
n=0
for h in "$inc"/surfkit/*.h; do
  name=$(basename "$h")
  printf '#include "surfkit/%s"\n#include "surfkit/%s"\nint sk_header_check_%s;\n' "$name" "$name" "${name%.h}" >"$tmp/t.c"
  "$cc" -std=c11 -pedantic-errors "${flags[@]}" -Wstrict-prototypes -fsyntax-only -x c "$tmp/t.c" \
    || fail "$name does not compile alone as C11 -pedantic"
  "$cxx" -std=c++11 -pedantic-errors "${flags[@]}" -fsyntax-only -x c++ "$tmp/t.c" \
    || fail "$name does not compile alone as C++11 -pedantic"
  if grep -Eq '^SK_API ' "$h" && ! grep -q 'extern "C"' "$h"; then
    fail "$name declares functions but has no extern \"C\" block"
  fi
  n=$((n + 1))
done
[ "$n" -gt 10 ] || fail "only $n headers found in $inc/surfkit"
echo "ok: $n public headers compile alone as C11 and C++11 (-pedantic -Werror)"
