#!/usr/bin/env bash
# Installs (idempotently) every Debian package surfkit needs to build, test and benchmark.
# Usage: scripts/setup.sh [--peers] [--interop]
#   --peers    also CGAL and OpenMesh for bench/peers, LEMON for bench/tjoin_lemon.cpp, and xatlas-web and xatlasjs (npm, bench/package.json)
#   --interop  also the programs tests/interop runs (Blender, FreeCAD, VTK's Python module;
#              scripts/test.sh, hence CI, asks for them). MeshLab is not installed:
#              meshlabserver 2020.09 does not run headless (no X: xcb fails; QT_QPA_PLATFORM=
#              offscreen: "GLEW initialization failed"), so tests/interop checks with VTK.
set -euo pipefail
cd "$(dirname "$0")/.."
pkgs=(build-essential cmake ninja-build pkg-config clang
      libsuitesparse-dev liblapacke-dev libopenblas-dev libcairo2-dev libcmocka-dev
      g++ libocct-data-exchange-dev chromium parallel valgrind
      python3-dev python3-numpy python3-pytest python3-setuptools python3-pip)
for arg in "$@"; do
  case "$arg" in
    --peers) pkgs+=(libcgal-dev libopenmesh-dev liblemon-dev) ;;
    --interop) pkgs+=(blender freecad python3-vtk9) ;;
    *) echo "setup: unknown option $arg (use --peers, --interop)" >&2; exit 2 ;;
  esac
done
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO=sudo
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
# three.js for the viewer, from the npm registry at the version viewer/package-lock.json pins
if [ ! -e viewer/node_modules/three/build/three.module.js ]; then
  if ! command -v npm > /dev/null; then
    SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO=sudo
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends npm
  fi
  (cd viewer && npm ci --no-audit --no-fund --loglevel=error)
fi
# the xatlas peers of bench/atlas.sh (npm xatlas-web and xatlasjs, pinned by bench/package-lock.json)
if [[ " $* " == *" --peers "* ]] && { [ ! -e bench/node_modules/xatlas-web/dist/xatlas-web.wasm ] ||
                                      [ ! -e bench/node_modules/xatlasjs/package.json ]; }; then
  (cd bench && npm ci --no-audit --no-fund --loglevel=error)
fi
echo "setup: all packages present (${#pkgs[@]} checked), three.js $(sed -n 's/.*"version": "\(.*\)".*/\1/p' viewer/node_modules/three/package.json | head -1)"
