#!/usr/bin/env bash
# Installs what is needed (with the programs of tests/interop), builds with warnings as errors, runs every test; then builds with
# AddressSanitizer + UndefinedBehaviorSanitizer and runs the tests again (lighter data set), and
# runs every fuzz target over the bad-input corpus (no fuzzing, only replay). The release tests
# include the API checks (api_exports, api_headers, api_layers), the install test with its C and
# C++ consumers (install_consumers) and the Python module's pytest suite (python_module).
# Usage: scripts/test.sh            (from the repository root; ../shared must be beside it)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh --interop
jobs=$(nproc 2>/dev/null || echo 2)

echo "== release build (-Werror) and tests"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DSK_WERROR=ON >/dev/null
cmake --build build -j"$jobs"
ctest --test-dir build --output-on-failure -j"$jobs"

echo "== valgrind (memcheck) of surfkit info over tests/data"
# uninitialised reads are invisible to ASan (issue 17: walk_boundary); memcheck sees them
vg_one() {
  valgrind -q --error-exitcode=99 ./build/surfkit info "$1" >/dev/null 2>"build/vg.$$.$2.log"
  [ $? -ne 99 ] || { echo "valgrind: errors on $1"; cat "build/vg.$$.$2.log"; return 1; }
  rm -f "build/vg.$$.$2.log"
}
export -f vg_one
ls tests/data/bad/* tests/data/good/* | awk '{print $0 " " NR}' |
  xargs -P"$jobs" -n2 bash -c 'vg_one "$0" "$1"' || { echo "valgrind corpus run failed"; exit 1; }
echo "valgrind: $(ls tests/data/bad/* tests/data/good/* | wc -l) files clean"

echo "== ASan + UBSan build and tests"
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Debug -DSK_WERROR=ON -DSK_SANITIZE=ON \
  -DSK_OPENMP=OFF -DSK_BUILD_BENCH=OFF >/dev/null
cmake --build build-asan -j"$jobs"
# fontconfig (cairo's text) keeps process-wide caches until exit: not ours, suppressed
SK_TEST_QUICK=1 ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
  LSAN_OPTIONS="suppressions=$PWD/tests/lsan-fontconfig.supp:print_suppressions=0" \
  ctest --test-dir build-asan --output-on-failure -j"$jobs"

if [ -n "$(ls tests/fuzz/fuzz_*.c 2>/dev/null)" ] && command -v clang >/dev/null; then
  echo "== fuzz targets (clang, libFuzzer) replaying tests/data"
  CC=clang cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSK_FUZZ=ON \
    -DSK_OPENMP=OFF -DSK_BUILD_BENCH=OFF >/dev/null
  targets=$(cd tests/fuzz && ls fuzz_*.c | sed 's/\.c$//')
  # shellcheck disable=SC2086
  cmake --build build-fuzz -j"$jobs" --target $targets
  for t in $targets; do
    ./build-fuzz/tests/"$t" -runs=0 tests/data/bad tests/data/good >/dev/null 2>build-fuzz/"$t".log \
      || { cat build-fuzz/"$t".log; echo "$t failed on the corpus"; exit 1; }
    echo "$t: corpus replayed cleanly"
  done
fi
echo "== all tests passed"
