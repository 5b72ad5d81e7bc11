#!/usr/bin/env bash
# The Python environment of the main job and the tests: build/venv with
# python/requirements-dev.txt (numpy, cffi, matplotlib, pytest, mypy, ...).
# Rebuilt only when the requirements change; pip's output is in
# build/logs/pip.log (shown if it fails).
set -euo pipefail
cd "$(dirname "$0")/.."
source tools/stage.sh
if [ -x build/venv/bin/python ] && [ ! python/requirements-dev.txt -nt build/venv/.stamp ]; then
  echo "libkin: Python environment build/venv: up to date"
  exit 0
fi
make_venv() {
  python3 -m venv build/venv
  build/venv/bin/pip install --upgrade pip
  build/venv/bin/pip install -r python/requirements-dev.txt
  touch build/venv/.stamp
}
stage "creating build/venv with python/requirements-dev.txt (pip, needs PyPI)" \
  "about 1 min; log build/logs/pip.log" build/logs/pip.log make_venv
