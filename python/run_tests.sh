#!/usr/bin/env bash
# Builds and tests the Python module the way a user installs it: cmake --install into a temporary
# prefix, `pip install --no-build-isolation` of python/ (Debian's python3, setuptools, numpy),
# then pytest (Debian's python3-pytest) against the installed surfkit tool.
# Usage: python/run_tests.sh BUILD_DIR SOURCE_DIR SHARED_DIR TMP [CMAKE]
set -euo pipefail
build=$1 src=$2 shared=$3 tmp=$4 cmake=${5:-cmake}
py=/usr/bin/python3   # Debian's, not a pyenv shim: its numpy and pytest are the Debian packages
rm -rf "$tmp"; mkdir -p "$tmp"
"$cmake" --install "$build" --prefix "$tmp/prefix" >"$tmp/install.log"
cp -r "$src/python" "$tmp/python"   # pip builds in the source folder: keep the tree clean
rm -rf "$tmp/python/build" "$tmp/python"/*.egg-info
SURFKIT_PREFIX=$tmp/prefix SURFKIT_WERROR=1 "$py" -m pip install --no-build-isolation --no-deps --no-cache-dir \
  --disable-pip-version-check --target "$tmp/site" "$tmp/python" >"$tmp/pip.log" 2>&1 \
  || { cat "$tmp/pip.log"; echo "FAIL: pip install"; exit 1; }
cd "$tmp"
PYTHONPATH=$tmp/site SURFKIT_CLI=$tmp/prefix/bin/surfkit SK_SHARED_DIR=$shared SK_SOURCE_DIR=$src \
  "$py" -m pytest -q -p no:cacheprovider "$src/python/tests"
