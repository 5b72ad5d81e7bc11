#!/usr/bin/env bash
# tools/abi_check.sh must fail on deliberate ABI breaks (ctest abi_mutations,
# docs/abi.md). A stand-in library (tests/abi_standin/: structs named like
# libkin's, a few functions) is built as the baseline and stored with
# `abi_check.sh --update`, then rebuilt with one mutation at a time and
# checked against it with the real script and the real abi/libkin.suppr:
#   1 a member appended to a size-prefixed struct   -> pass
#   2 two members of a public struct swapped        -> FAIL
#   3 a public function removed                     -> FAIL
#   4 a member inserted in the middle               -> FAIL
#   5 a member appended to a struct without a size  -> FAIL
#   6 a function added                              -> pass
# usage: abi_mutations.sh WORK_DIR     (takes about a second)
set -uo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/.." && pwd)"
work="${1:?usage: abi_mutations.sh WORK_DIR}"
command -v abidiff >/dev/null && command -v abidw >/dev/null || { echo "abi_mutations: SKIPPED: no abigail-tools"; exit 77; }
cc="${CC:-cc}"
rm -rf "$work" && mkdir -p "$work/abi"
build() { # mutation -> $work/m<mutation>/libkin.so
  mkdir -p "$work/m$1"
  "$cc" -g -O0 -fPIC -shared -fvisibility=hidden -DMUTATION="$1" -I"$here/abi_standin" \
    -Wl,-soname,libkin.so.1 "$here/abi_standin/standin.c" -o "$work/m$1/libkin.so" || exit 2
}
check() { # mutation -> abi_check's exit status
  KIN_ABI_LIB="$work/m$1/libkin.so" KIN_ABI_HEADERS="$here/abi_standin" KIN_ABI_DIR="$work/abi" \
    bash "$root/tools/abi_check.sh" >"$work/m$1.log" 2>&1
}
fail=0
build 0
KIN_ABI_LIB="$work/m0/libkin.so" KIN_ABI_HEADERS="$here/abi_standin" KIN_ABI_DIR="$work/abi" \
  bash "$root/tools/abi_check.sh" --update >/dev/null || { echo "abi_mutations: storing the baseline failed"; exit 2; }
want=(0 0 1 1 1 1 0)
names=("none" "member appended" "members swapped" "function removed" "member inserted"
       "member appended to a fixed struct" "function added")
for m in 0 1 2 3 4 5 6; do
  build "$m"
  check "$m"; got=$?
  if [ "$got" -ne "${want[$m]}" ]; then
    echo "abi_mutations: mutation $m (${names[$m]}): abi_check exit $got, want ${want[$m]}:"
    sed 's/^/    /' "$work/m$m.log"
    fail=1
  else
    echo "abi_mutations: mutation $m (${names[$m]}): abi_check exit $got as expected"
  fi
done
exit $fail
