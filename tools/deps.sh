#!/usr/bin/env bash
# Install what libkin needs on Debian 12 (idempotent): compiler, CMake,
# LAPACK/BLAS (OpenBLAS and the reference libblas3 for tools/check_blas.sh),
# GSL, jansson (JSON model files), SuiteSparse KLU (KIN_STEP_SPARSE), nauty (kin_symmetries), pkg-config, Python's venv module,
# Arb (libflint-arb-dev: the interval certificates of the complete solver, libkin/certify/),
# gfortran (the Fortran module), abigail-tools (tools/abi_check.sh) and clang
# (the C suite built with clang, tools/build_clang.sh) with its runtime libraries
# libclang-rt-14-dev (libFuzzer and the sanitizers: the fuzz targets, tests/fuzz),
# chromium and chromium-driver (the atlas viewer's test in a real browser,
# python/tests/test_viewer_browser.py, headless through selenium) and macaulay2
# (Macaulay2's NumericalCertification re-proves the complete solver's counts,
# python/tests/test_homotopy_prove_m2.py; 27 packages, about 12 s).
# Nothing to do (and no root needed) when everything is installed. Otherwise
# it installs with apt-get as root, or through sudo if that works without a
# password; failing both it prints the exact command to run and exits 1.
# apt's output goes to build/logs/apt.log (shown if it fails).
set -euo pipefail
cd "$(dirname "$0")/.."
source tools/stage.sh
pkgs=(build-essential cmake pkg-config libopenblas-dev liblapack-dev libblas3 libgsl-dev libjansson-dev libsuitesparse-dev libnauty2-dev python3-venv python3-dev
      gfortran abigail-tools clang libclang-rt-14-dev chromium chromium-driver libflint-arb-dev
      macaulay2)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "libkin: Debian packages: all ${#pkgs[@]} present"
  exit 0
fi
# one install command: the one run and the one printed for a non-root user
apt_install=(apt-get install -y --no-install-recommends "${missing[@]}")
if [ "$(id -u)" -eq 0 ]; then
  SUDO=()
elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
  SUDO=(sudo -n)
else
  echo "libkin: missing Debian packages: ${missing[*]}" >&2
  echo "libkin: as root, run:  apt-get update && DEBIAN_FRONTEND=noninteractive ${apt_install[*]}" >&2
  exit 1
fi
install_missing() {
  "${SUDO[@]}" apt-get update
  DEBIAN_FRONTEND=noninteractive "${SUDO[@]}" "${apt_install[@]}"
}
stage "installing Debian packages: ${missing[*]}" "about 1-3 min; log build/logs/apt.log" \
  build/logs/apt.log install_missing
