#!/usr/bin/env bash
# The main job: build, then run the three-bar linkage example (analysis at the
# bifurcation R^C and a lap of its parallelogram path).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/build.sh >/dev/null
./build/examples/threebar
