#!/usr/bin/env bash
# The build enforces the layers: compiled with the include path of module M's real target, a
# file includes the private headers ("N/x.h") and public headers ("surfkit/N.h") of module N
# if and only if N is M or one of M's dependencies. For example a file in src/mesh that
# includes "param/param_internal.h" or "surfkit/param.h" does not compile.
# Usage: layers.sh SRC_DIR CC TMP EXTRA_CFLAGS MODULE=INCDIRS:...=CLOSURE,...=HEADERS,... ...
set -u
src=$1 cc=$2 tmp=$3 extra=$4; shift 4
rm -rf "$tmp"; mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
declare -A incs closure headers
mods=()
for spec in "$@"; do
  IFS='=' read -r m i c h <<<"$spec"
  mods+=("$m"); incs[$m]=$i; closure[$m]=",$c,"; headers[$m]=$h
done
[ ${#mods[@]} -ge 5 ] || fail "only ${#mods[@]} modules given"
ok=0 refused=0
probe() {  # module header expect(0 = compiles, 1 = refused)
  local m=$1 hdr=$2 expect=$3 args=()
  IFS=':' read -ra dirs <<<"${incs[$m]}"
  for d in "${dirs[@]}"; do args+=(-I"$d"); done
  printf '#include "%s"\nint sk_layer_probe;\n' "$hdr" >"$tmp/probe.c"
  # shellcheck disable=SC2086
  if "$cc" -std=c11 -fsyntax-only "${args[@]}" $extra "$tmp/probe.c" 2>"$tmp/err"; then
    [ "$expect" = 0 ] || fail "a file in src/$m can include \"$hdr\" (not one of its layers)"
    ok=$((ok + 1))
  else
    [ "$expect" = 1 ] || { cat "$tmp/err"; fail "a file in src/$m cannot include \"$hdr\""; }
    grep -q "No such file" "$tmp/err" || { cat "$tmp/err"; fail "\"$hdr\" in $m failed, not as missing"; }
    refused=$((refused + 1))
  fi
}
for m in "${mods[@]}"; do
  for n in "${mods[@]}"; do
    expect=1; case ${closure[$m]} in *",$n,"*) expect=0 ;; esac
    for p in "$src/src/$n"/*.h; do
      [ -e "$p" ] && probe "$m" "$n/$(basename "$p")" $expect
    done
    IFS=',' read -ra hs <<<"${headers[$n]}"
    for h in "${hs[@]}"; do probe "$m" "surfkit/$h" $expect; done
  done
done
# the example of the issue, stated on its own
case ${closure[mesh]} in *,param,*) fail "mesh depends on param" ;; esac
probe mesh surfkit/param.h 1
[ -e "$src/src/param/param_internal.h" ] && probe mesh param/param_internal.h 1
[ "$refused" -gt 0 ] && [ "$ok" -gt 0 ] || fail "nothing probed"
echo "ok: ${#mods[@]} modules, $ok allowed includes compile, $refused upward or sideways ones are refused"
