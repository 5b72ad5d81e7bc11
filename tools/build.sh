#!/usr/bin/env bash
# Configure and build libkin, its tests, examples and benchmarks in ./build
# (Release with debug info). One line per stage; the compiler's output is in
# build/logs/ (shown if a stage fails).
set -euo pipefail
cd "$(dirname "$0")/.."
source tools/stage.sh
bash tools/deps.sh
jobs=$(nproc)
[ "$jobs" -le 2 ] || jobs=2
if [ -f build/CMakeCache.txt ]; then cfg_est="about 1 s"; build_est="a few seconds if little changed"
else cfg_est="about 5 s"; build_est="about 1 min on 2 cores"; fi
stage "configuring with CMake in build/" "$cfg_est; log build/logs/cmake.log" build/logs/cmake.log \
  cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo
stage "compiling the library, tests, examples and benchmarks" "$build_est; log build/logs/build.log" \
  build/logs/build.log cmake --build build -j"$jobs"
