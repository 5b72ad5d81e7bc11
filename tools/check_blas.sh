#!/usr/bin/env bash
# Run the C suite (ctest, without the tests that do no linear algebra) under several BLAS/LAPACK
# variants and print a table: OpenBLAS with each CPU kernel this machine can
# run (OPENBLAS_CORETYPE), Debian's reference LAPACK over OpenBLAS's BLAS, and
# the reference LAPACK and BLAS together (selected at run time with
# LD_LIBRARY_PATH: libkin links liblapack.so.3/libblas.so.3, which Debian
# resolves through its alternatives). Exits non-zero if any variant fails.
#
# usage: tools/check_blas.sh [BUILD_DIR]   (default: build, already built)
set -uo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
if [ ! -f "$build/CTestTestfile.cmake" ]; then
  echo "check_blas: no CTest tree in $build: run tools/build.sh first" >&2
  exit 2
fi
arch=/usr/lib/x86_64-linux-gnu
probe=$(find "$build/tests" -maxdepth 1 -name 'test_lap' -type f | head -1)

flags=$(grep -m1 '^flags' /proc/cpuinfo 2>/dev/null || true)
variants=("default|" "Prescott|OPENBLAS_CORETYPE=Prescott" "Nehalem|OPENBLAS_CORETYPE=Nehalem")
case "$flags" in *" avx "*) variants+=("Sandybridge|OPENBLAS_CORETYPE=Sandybridge");; esac
case "$flags" in *avx2*) variants+=("Haswell|OPENBLAS_CORETYPE=Haswell" "Zen|OPENBLAS_CORETYPE=Zen");; esac
case "$flags" in *avx512f*) variants+=("SkylakeX|OPENBLAS_CORETYPE=SkylakeX");; esac
if [ -f $arch/lapack/liblapack.so.3 ]; then
  variants+=("reference LAPACK + OpenBLAS BLAS|LD_LIBRARY_PATH=$arch/lapack")
  if [ -f $arch/blas/libblas.so.3 ]; then
    variants+=("reference LAPACK + reference BLAS|LD_LIBRARY_PATH=$arch/blas:$arch/lapack")
  else
    echo "check_blas: reference BLAS ($arch/blas/libblas.so.3, Debian libblas3) missing: that variant is skipped"
  fi
else
  echo "check_blas: reference LAPACK ($arch/lapack/liblapack.so.3, Debian liblapack3) missing: those variants are skipped"
fi

# Which library and kernel a variant really loads: ldd under its environment,
# and OpenBLAS's own report of its core (OPENBLAS_VERBOSE=2).
loaded() {
  local envs=$1 lib
  lib=$(env $envs ldd "$probe" 2>/dev/null | awk -v n="$2" '$1 == n {print $3}')
  readlink -f "$lib" 2>/dev/null | sed "s|$arch/||"
}
core_of() {
  env $1 OPENBLAS_VERBOSE=2 "$probe" 2>&1 >/dev/null | sed -n 's/^Core: *//p' | head -1
}

printf '\n| variant | LAPACK loaded | BLAS loaded | OpenBLAS core | C tests | time |\n'
printf '|---|---|---|---|---|---|\n'
fails=0
logs=$(mktemp -d)
for v in "${variants[@]}"; do
  name=${v%%|*}
  envs=${v#*|}
  log="$logs/$(echo "$name" | tr -c 'A-Za-z0-9' _).log"
  t0=$(date +%s%N)
  # the tests that do no linear algebra run once, in the main C suite: the
  # install, ABI, export and layer checks and the fuzz targets
  (cd "$build" && env $envs ctest -E '^(test_install|abi_check|abi_mutations|abi_generated|exports|architecture|fuzz_short)$' \
     --timeout 120 >"$log" 2>&1)
  rc=$?
  t1=$(date +%s%N)
  summary=$(grep -oE '[0-9]+% tests passed, [0-9]+ tests failed out of [0-9]+' "$log" | sed -E 's/.*passed, ([0-9]+) tests failed out of ([0-9]+)/\1 failed of \2/')
  [ -n "$summary" ] || summary="no result"
  core=$(core_of "$envs")
  status=pass
  if [ $rc -ne 0 ]; then
    status="FAIL: $(grep -oE '[0-9]+ - [A-Za-z_]+' "$log" | awk '{print $3}' | tr '\n' ' ')"
    fails=$((fails + 1))
  fi
  printf '| %s | %s | %s | %s | %s (%s) | %.1f s |\n' "$name" "$(loaded "$envs" liblapack.so.3)" \
    "$(loaded "$envs" libblas.so.3)" "${core:--}" "$summary" "$status" "$(awk -v a="$t0" -v b="$t1" 'BEGIN {print (b - a) / 1e9}')"
done
rm -rf "$logs"
echo
if [ $fails -ne 0 ]; then
  echo "check_blas: $fails variant(s) failed"
  exit 1
fi
echo "check_blas: every variant passed"
