#!/usr/bin/env bash
# The Python environment of the main job and the tests: build/venv with
# python/requirements-dev.txt (numpy, cffi, matplotlib, pytest, ...).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ ! -x build/venv/bin/python ] || [ python/requirements-dev.txt -nt build/venv/.stamp ]; then
  python3 -m venv build/venv
  build/venv/bin/pip install -q --upgrade pip
  build/venv/bin/pip install -q -r python/requirements-dev.txt
  touch build/venv/.stamp
fi
