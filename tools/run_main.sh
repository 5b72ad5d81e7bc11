#!/usr/bin/env bash
# The main job: build, then run the three-bar linkage study (analysis at R^C,
# its two paths, locating R^A along P1, a lap of the parallelogram path).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/build.sh >/dev/null
./build/examples/threebar
