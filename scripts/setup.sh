#!/usr/bin/env bash
# Installs (idempotently) every Debian package surfkit needs to build, test and benchmark.
# Usage: scripts/setup.sh [--peers]   (--peers also installs CGAL and OpenMesh for bench/peers)
set -euo pipefail
pkgs=(build-essential cmake ninja-build pkg-config clang
      libsuitesparse-dev liblapacke-dev libopenblas-dev libcairo2-dev libcmocka-dev
      g++ libocct-data-exchange-dev valgrind)
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
echo "setup: all packages present (${#pkgs[@]} checked)"
