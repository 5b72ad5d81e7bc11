#!/usr/bin/env bash
# Install what libkin needs on Debian 12 (idempotent): compiler, CMake,
# LAPACK/BLAS (OpenBLAS), GSL, jansson (JSON model files), pkg-config, and
# Python's venv module.
set -euo pipefail
pkgs=(build-essential cmake pkg-config libopenblas-dev liblapack-dev libblas3 libgsl-dev libjansson-dev python3-venv python3-dev)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  echo "installing: ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}" >/dev/null
fi
