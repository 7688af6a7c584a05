#!/usr/bin/env bash
# Installs (idempotently) every Debian package surfkit needs to build, test and benchmark.
# Usage: scripts/setup.sh [--peers]   (--peers also installs CGAL and OpenMesh for bench/peers)
set -euo pipefail
cd "$(dirname "$0")/.."
pkgs=(build-essential cmake ninja-build pkg-config clang
      libsuitesparse-dev liblapacke-dev libopenblas-dev libcairo2-dev libcmocka-dev
      g++ libocct-data-exchange-dev chromium parallel
      python3-dev python3-numpy python3-pytest python3-setuptools python3-pip)
if [ "${1:-}" = "--peers" ]; then
  pkgs+=(g++ libcgal-dev libopenmesh-dev)
fi
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
echo "setup: all packages present (${#pkgs[@]} checked), three.js $(sed -n 's/.*"version": "\(.*\)".*/\1/p' viewer/node_modules/three/package.json | head -1)"
