#!/usr/bin/env bash
# Every test: the C suite through `make check` (ctest), then the Python suite
# (pytest in a virtual environment) when the package is present.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/build.sh
cmake --build build --target check
if [ -d python/tests ]; then
  bash tools/venv.sh
  LIBKIN_LIBRARY="$PWD/build/libkin.so" PYTHONPATH="$PWD/python/src" \
    build/venv/bin/python -m pytest -q python/tests
fi
