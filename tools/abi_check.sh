#!/usr/bin/env bash
# ABI check: compare the shared library in BUILD_DIR (default ./build) with
# the last release's, and fail only when the ABI changed incompatibly while
# the soname (libkin.so.KIN_ABI_VERSION) stayed the same. See docs/abi.md.
#
# The reference is the release named in abi/reference: its library is built
# from git (`git archive`, with -g, cached in BUILD_DIR/abi-ref/) and the two
# binaries are compared by abidiff with their DWARF. Without git history the
# stored dump abi/libkin-<version>.abi is used instead; libabigail 2.2 sees
# only symbol changes (removed/added functions) that way, not struct layout
# changes, so the check says so.
#
# Exit: 0 compatible (or soname bumped), 1 incompatible change under the same
# soname, 2 tool error, 77 skipped (abidiff missing: tools/deps.sh installs
# abigail-tools).
set -uo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$(cd "${1:-$root/build}" && pwd)"
if ! command -v abidiff >/dev/null || ! command -v abidw >/dev/null; then
  echo "abi_check: SKIPPED: abidiff/abidw not found (Debian package abigail-tools, installed by tools/deps.sh)"
  exit 77
fi
# shellcheck source=/dev/null
source "$root/abi/reference"   # ref_version, ref_commit
cur="$build/libkin.so"
[ -e "$cur" ] || { echo "abi_check: $cur not built"; exit 2; }
suppr=()
[ -f "$root/abi/libkin.suppr" ] && suppr=(--suppressions "$root/abi/libkin.suppr")
if ! readelf -S "$cur" | grep -q '\.debug_info'; then
  echo "abi_check: warning: $cur has no debug info (build with -g, e.g. RelWithDebInfo): only symbols are compared"
fi

soname() { readelf -d "$1" | sed -n 's/.*(SONAME).*\[\(.*\)\].*/\1/p'; }

refdir="$build/abi-ref/$ref_commit"
ref=""
if [ -e "$refdir/build/libkin.so" ]; then
  ref="$refdir/build/libkin.so"
elif git -C "$root" cat-file -e "$ref_commit^{commit}" 2>/dev/null; then
  echo "abi_check: building the $ref_version reference library ($ref_commit) in $refdir"
  rm -rf "$refdir" && mkdir -p "$refdir/src"
  if git -C "$root" archive "$ref_commit" | tar -x -C "$refdir/src" &&
     cmake -S "$refdir/src" -B "$refdir/build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
       -DKIN_BUILD_TESTS=OFF -DKIN_BUILD_EXAMPLES=OFF -DKIN_BUILD_BENCH=OFF >"$refdir/build.log" 2>&1 &&
     cmake --build "$refdir/build" --target kin -j2 >>"$refdir/build.log" 2>&1; then
    ref="$refdir/build/libkin.so"
  else
    echo "abi_check: building the reference failed (see $refdir/build.log)"; exit 2
  fi
fi

if [ -n "$ref" ]; then
  old_soname="$(soname "$ref")"
  report="$(abidiff "${suppr[@]}" --hd1 "$refdir/src/include/libkin" --hd2 "$root/include/libkin" "$ref" "$cur")"
  rc=$?
  how="binaries with debug info"
else
  dump="$root/abi/libkin-$ref_version.abi"
  [ -f "$dump" ] || { echo "abi_check: neither git commit $ref_commit nor $dump available"; exit 2; }
  echo "abi_check: warning: no git history: comparing with $dump (symbols only: struct layout changes are not seen)"
  old_soname="$(sed -n "1s/.*soname='\([^']*\)'.*/\1/p" "$dump")"
  report="$(abidiff "${suppr[@]}" --hd2 "$root/include/libkin" "$dump" "$cur")"
  rc=$?
  how="stored dump against binary"
fi
new_soname="$(soname "$cur")"
echo "abi_check: libkin $ref_version ($old_soname) -> current build ($new_soname), $how"
echo "$report"
if (( rc & 1 )); then
  echo "abi_check: abidiff failed (exit $rc)"; exit 2
fi
# abidiff sets bit 8 only for a few sure breaks (removed symbols, ...); bit 4
# means "changed, maybe compatible". Added functions/variables are compatible;
# a removed or changed one (a struct behind a pointer grew, a parameter type
# changed) is not, unless abi/libkin.suppr declares the change safe (a struct
# that carries its own size grew at its end).
incompatible=0
if (( rc & 8 )); then
  incompatible=1
elif (( rc & 4 )); then
  if echo "$report" | grep -Eq 'changes summary: ([1-9][0-9]* Removed|[0-9]+ Removed, [1-9][0-9]* Changed)'; then
    incompatible=1
  fi
fi
if (( incompatible )); then
  if [ "$old_soname" = "$new_soname" ]; then
    echo "abi_check: FAIL: incompatible ABI change but the soname is still $new_soname:"
    echo "  bump KIN_ABI_VERSION in include/libkin/kin_version.h (docs/abi.md), or keep the change compatible"
    exit 1
  fi
  echo "abi_check: OK: incompatible ABI change with a new soname ($old_soname -> $new_soname)"
  exit 0
fi
if [ "$old_soname" != "$new_soname" ]; then
  echo "abi_check: OK: compatible with $ref_version, though the soname changed ($old_soname -> $new_soname)"
else
  echo "abi_check: OK: compatible with $ref_version (soname $new_soname)"
fi
exit 0
