#!/usr/bin/env bash
# libsurfkit.so exports exactly the functions declared in include/surfkit/*.h: every dynamic
# symbol it defines is an sk_ name (no internal sk__ one, nothing else), and every function a
# public header declares (static inline ones aside) is among them, so a declaration without
# SK_API is caught. The declarations come from gcc -aux-info over every header.
# Usage: exports.sh LIBSURFKIT_SO INCLUDE_DIR CC TMP
set -u
lib=$1 inc=$2 cc=$3 tmp=$4
rm -rf "$tmp"; mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }

nm -D --defined-only "$lib" | awk 'NF >= 3 {print $3}' | sed 's/@.*//' | sort -u >"$tmp/exported"
[ -s "$tmp/exported" ] || fail "no dynamic symbols in $lib"
bad=$(grep -v '^sk_[a-z0-9]' "$tmp/exported")
[ -z "$bad" ] || fail "exported symbols that are not public sk_ names: $(echo $bad)"

: >"$tmp/all.c"
for h in "$inc"/surfkit/*.h; do echo "#include \"surfkit/$(basename "$h")\"" >>"$tmp/all.c"; done
"$cc" -std=c11 -I"$inc" -aux-info "$tmp/aux" -fsyntax-only "$tmp/all.c" || fail "headers do not compile"
grep -F "$inc/surfkit/" "$tmp/aux" | grep -v '\*/ static ' \
  | sed -E 's/^.*\*\/ [^(]*[^a-zA-Z0-9_](sk_[a-zA-Z0-9_]+) \(.*$/\1/' | sort -u >"$tmp/declared"
[ "$(wc -l <"$tmp/declared")" -gt 50 ] || fail "too few declarations found ($(wc -l <"$tmp/declared"))"
grep -v '^sk_' "$tmp/declared" && fail "could not parse the declarations above"

missing=$(comm -23 "$tmp/declared" "$tmp/exported")
[ -z "$missing" ] || fail "declared in include/surfkit but not exported (SK_API missing?): $(echo $missing)"
extra=$(comm -13 "$tmp/declared" "$tmp/exported")
[ -z "$extra" ] || fail "exported but declared in no public header: $(echo $extra)"
echo "ok: $(wc -l <"$tmp/exported") functions exported, all declared in include/surfkit, nothing else"
