#!/usr/bin/env bash
# The main job: build libkin, then run the hexagonal solar-sail folding study
# (paper Section 6.2): flat state R^A (complete branch analysis), the folding
# path into R^B, on to R^C, and back to R^A. Writes study_out/report.md with
# its figures. Extra arguments go to `libkin study` (e.g. --hub 4 --loops 1
# for the square sail, --quick to skip the 2^15-path homotopy, --out DIR).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/build.sh
bash tools/venv.sh
# with no arguments, the main job also maps which of the symmetric paths a
# bare membrane can follow (--contact: the path map with contact as an event)
if [ $# -eq 0 ]; then set -- --contact; fi
LIBKIN_LIBRARY="$PWD/build/libkin.so" PYTHONPATH="$PWD/python/src" \
  build/venv/bin/python -m libkin study "$@"
