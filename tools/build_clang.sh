#!/usr/bin/env bash
# Configure and build libkin and its C tests with clang in ./build-clang
# (RelWithDebInfo, no benchmarks), for the C suite built with clang
# (tools/run_tests.sh): the library must build, link and pass with GCC and
# Clang alike. One line per stage; the compiler's output is in
# build-clang/logs/ (shown if a stage fails). Needs tools/deps.sh (clang).
set -euo pipefail
cd "$(dirname "$0")/.."
KIN_LOG_DIR=build-clang/logs
source tools/stage.sh
if ! command -v clang >/dev/null 2>&1; then
  echo "libkin: clang not found: run tools/deps.sh" >&2
  exit 1
fi
jobs=$(nproc)
[ "$jobs" -le 2 ] || jobs=2
if [ -f build-clang/CMakeCache.txt ]; then cfg_est="about 1 s"; build_est="a few seconds if little changed"
else cfg_est="about 5 s"; build_est="about 1 min on 2 cores"; fi
stage "configuring with CMake in build-clang/ (CC=clang)" "$cfg_est; log build-clang/logs/cmake.log" \
  build-clang/logs/cmake.log env CC=clang cmake -S . -B build-clang -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DKIN_BUILD_BENCH=OFF
stage "compiling the library and tests with clang" "$build_est; log build-clang/logs/build.log" \
  build-clang/logs/build.log cmake --build build-clang -j"$jobs"
