#!/usr/bin/env bash
# The Python side of "the same answer on every machine" (docs/performance.md):
# under several BLAS settings — OpenBLAS's Prescott, Haswell and SkylakeX
# kernels where this CPU can run them, and one OpenBLAS thread — run
#   1. the tests whose answers an SVD basis or the arrival order could decide
#      (atlas directions, the sail study against its stored runs, canonical
#      solutions, arrival order, and the follow ends of the depth-5 atlas that
#      rounding decides: tangent branches, broken crossings, flat-state returns),
#   2. the main job itself (`libkin study --contact`, what tools/run_main.sh
#      runs: the complete solve, the fold, the path map, contact), and
#   3. a symmetric depth-2 explore of sail:6:2,
# then compare 2 and 3 across the settings with tools/compare_runs.py: the
# main job's summary.json, its path map's atlas.json and its report.md (times
# masked), and the explorer's atlas (every count, label, choice, node and
# edge; numbers to the digits reported).
# Prints a table; exits non-zero if a setting fails or two settings differ.
#
# usage: tools/check_blas_python.sh [BUILD_DIR]   (default: build, built, with build/venv)
set -uo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
py="$build/venv/bin/python"
if [ ! -x "$py" ] || [ ! -f "$build/libkin.so" ]; then
  echo "check_blas_python: no $build/libkin.so or $py: run tools/build.sh and tools/venv.sh first" >&2
  exit 2
fi
flags=$(grep -m1 '^flags' /proc/cpuinfo 2>/dev/null || true)
settings=("Prescott|OPENBLAS_CORETYPE=Prescott")
case "$flags" in *avx2*) settings+=("Haswell|OPENBLAS_CORETYPE=Haswell");; esac
case "$flags" in *avx512f*) settings+=("SkylakeX|OPENBLAS_CORETYPE=SkylakeX");; esac
settings+=("one thread|OPENBLAS_NUM_THREADS=1")
tests=(python/tests/test_atlas_directions.py python/tests/test_sail_study.py
       python/tests/test_canonical_solutions.py python/tests/test_atlas_arrival_order.py
       python/tests/test_readings.py python/tests/test_atlas_tangent.py
       python/tests/test_follow_rounding_crossing.py python/tests/test_follow_flat_return.py)
out="$build/blas_python"
rm -rf "$out"
mkdir -p "$out"
export LIBKIN_LIBRARY="$PWD/$build/libkin.so" PYTHONPATH="$PWD/python/src"

printf '\n| setting | OpenBLAS core | tests | main job (study --contact) | explore sail:6:2 depth 2 | time |\n'
printf '|---|---|---|---|---|---|\n'
fails=0
studies=()
maps=()
reports=()
atlases=()
for s in "${settings[@]}"; do
  name=${s%%|*}
  envs=${s#*|}
  tag=$(echo "$name" | tr -c 'A-Za-z0-9' _)
  t0=$(date +%s)
  core=$(env $envs OPENBLAS_VERBOSE=2 "$py" -c "import libkin" 2>&1 | sed -n 's/^Core: *//p' | head -1)
  env $envs "$py" -m pytest -q -p no:cacheprovider "${tests[@]}" > "$out/$tag.tests.log" 2>&1
  rc=$?
  tres=$(tail -1 "$out/$tag.tests.log")
  [ $rc -eq 0 ] || { fails=$((fails + 1)); tres="FAILED: $tres"; }
  env $envs "$py" -m libkin study --contact --out "$out/$tag.study" > "$out/$tag.study.log" 2>&1
  if [ $? -eq 0 ]; then
    sres=done
    studies+=("$out/$tag.study/summary.json")
    maps+=("$out/$tag.study/atlas.json")
    reports+=("$out/$tag.study/report.md")
  else sres=FAILED; fails=$((fails + 1)); fi
  env $envs "$py" -m libkin explore sail:6:2 --depth 2 --symmetric --quiet --out "$out/$tag.explore" \
    > "$out/$tag.explore.log" 2>&1
  if [ $? -eq 0 ]; then eres=done; atlases+=("$out/$tag.explore/atlas.json")
  else eres=FAILED; fails=$((fails + 1)); fi
  printf '| %s | %s | %s | %s | %s | %s s |\n' "$name" "${core:--}" "$tres" "$sres" "$eres" "$(( $(date +%s) - t0 ))"
done
echo
for f in "$out"/*.tests.log; do
  if ! tail -1 "$f" | grep -q ' passed' || tail -1 "$f" | grep -q 'failed'; then
    echo "check_blas_python: $f:"; tail -30 "$f"
  fi
done
if [ ${#studies[@]} -gt 1 ]; then
  "$py" tools/compare_runs.py "${studies[@]}" || fails=$((fails + 1))
  "$py" tools/compare_runs.py "${maps[@]}" || fails=$((fails + 1))
  "$py" tools/compare_runs.py "${reports[@]}" || fails=$((fails + 1))
fi
if [ ${#atlases[@]} -gt 1 ]; then
  "$py" tools/compare_runs.py "${atlases[@]}" || fails=$((fails + 1))
fi
if [ $fails -eq 0 ]; then echo "check_blas_python: every setting passed and gave the same answers"
else echo "check_blas_python: $fails failure(s)"; fi
[ $fails -eq 0 ]
