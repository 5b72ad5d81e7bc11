#!/usr/bin/env bash
# Every test, and a report of each suite:
#   1. the C suite through `make check` (ctest),
#   2. the Python suite (pytest in the virtual environment build/venv),
#   3. the C suite again under every BLAS/LAPACK variant (tools/check_blas.sh),
#   4. the C suite built with clang in build-clang (tools/build_clang.sh; the
#      ABI check runs once, in 1),
#   5. the Python tests an SVD basis or arrival order could decide, the main
#      job (`study --contact`: summary, map and report) and a symmetric explore under OpenBLAS's Prescott,
#      Haswell and SkylakeX kernels and one thread, compared with each other
#      (tools/check_blas_python.sh).
# A suite that fails does not stop the others; the script fails if any did
# and says which.
set -uo pipefail
cd "$(dirname "$0")/.."
bash tools/build.sh || { echo "run_tests: the build failed; no suite ran"; exit 1; }

declare -A result
order=(C Python BLAS-variants C-clang Python-BLAS)

echo "== C suite (make check) =="
if cmake --build build --target check; then result[C]=passed; else result[C]=FAILED; fi

echo "== Python suite (pytest) =="
if [ -d python/tests ]; then
  if bash tools/venv.sh; then
    LIBKIN_LIBRARY="$PWD/build/libkin.so" PYTHONPATH="$PWD/python/src" \
      build/venv/bin/python -m pytest -q python/tests
    rc=$?
    # pytest exits 5 when it collected no test: that is a failure here
    if [ $rc -eq 0 ]; then result[Python]=passed; else result[Python]="FAILED (pytest exit $rc)"; fi
  else
    result[Python]="FAILED (virtual environment could not be set up)"
  fi
else
  result[Python]="FAILED (python/tests missing)"
fi

echo "== C suite under BLAS/LAPACK variants (tools/check_blas.sh) =="
if bash tools/check_blas.sh build; then result[BLAS-variants]=passed; else result[BLAS-variants]=FAILED; fi

echo "== C suite built with clang (build-clang) =="
if bash tools/build_clang.sh; then
  if (cd build-clang && ctest --output-on-failure -E '^abi_check$'); then result[C-clang]=passed
  else result[C-clang]=FAILED; fi
else
  result[C-clang]="FAILED (the clang build failed)"
fi

echo "== Python under BLAS settings, compared (tools/check_blas_python.sh) =="
if [ -x build/venv/bin/python ] && bash tools/check_blas_python.sh build; then result[Python-BLAS]=passed
else result[Python-BLAS]=FAILED; fi

echo
echo "== Summary =="
npass=0
nfail=0
for s in "${order[@]}"; do
  printf '  %-14s %s\n' "$s" "${result[$s]}"
  case "${result[$s]}" in passed) npass=$((npass + 1)) ;; *) nfail=$((nfail + 1)) ;; esac
done
echo "suites: $npass passed, $nfail failed"
[ $nfail -eq 0 ]
