#!/usr/bin/env bash
# ABI check (docs/abi.md): compare the shared library in BUILD_DIR (default
# ./build) with the stored baseline of its soname, abi/<soname>.abi (an
# abidw dump of this tree's build: no git, no second build at test time),
# and fail when the ABI changed incompatibly:
#  - a function or variable removed or changed (abidiff's summary, after the
#    suppressions of abi/libkin.suppr);
#  - a member of a public struct removed, moved, retyped or renamed, or one
#    appended to a struct that carries no layout size
#    (tools/abi_layouts_diff.py on the baseline and a dump of the build:
#    libabigail 2.2's abidiff misses layout changes against an XML dump, and
#    its has_data_member_inserted_at = end suppression would accept a
#    reordering). Members appended at the end of a size-prefixed struct (the
#    list in abi/libkin.suppr, generated from the headers by
#    tools/gen_abi.py) are the one accepted struct change.
# Added functions are compatible. An incompatible change needs a new soname
# (bump KIN_ABI_VERSION in include/libkin/kin_version.h) and a baseline for
# it: a soname without a stored baseline fails until one is stored.
#
#   bash tools/abi_check.sh [BUILD_DIR]            check        (ctest abi_check)
#   bash tools/abi_check.sh --update [BUILD_DIR]   store abi/<soname>.abi from the build
#
# Environment (tests/abi_mutations.sh uses them on stand-in libraries):
# KIN_ABI_LIB the library (default BUILD_DIR/libkin.so), KIN_ABI_HEADERS its
# public headers (default include/libkin), KIN_ABI_DIR where baselines are
# (default abi/), KIN_ABI_SUPPR the suppression file (default abi/libkin.suppr).
#
# Exit: 0 compatible, 1 incompatible (or no baseline for the soname), 2 tool
# error, 77 skipped (abidiff/abidw missing: tools/deps.sh installs
# abigail-tools; or a library without debug info: a Release build).
set -uo pipefail  # (no grep -q after a pipe: an early exit would fail the pipeline)
root="$(cd "$(dirname "$0")/.." && pwd)"
update=0
if [ "${1:-}" = "--update" ]; then update=1; shift; fi
build="${1:-$root/build}"
lib="${KIN_ABI_LIB:-$build/libkin.so}"
headers="${KIN_ABI_HEADERS:-$root/include/libkin}"
abidir="${KIN_ABI_DIR:-$root/abi}"
supprfile="${KIN_ABI_SUPPR:-$root/abi/libkin.suppr}"
if ! command -v abidiff >/dev/null || ! command -v abidw >/dev/null; then
  echo "abi_check: SKIPPED: abidiff/abidw not found (Debian package abigail-tools, installed by tools/deps.sh)"
  exit 77
fi
[ -e "$lib" ] || { echo "abi_check: $lib not built"; exit 2; }
if ! readelf -S "$lib" | grep '\.debug_info' >/dev/null; then
  echo "abi_check: SKIPPED: $lib has no debug info: build with -g (RelWithDebInfo, tools/build.sh)"; exit 77
fi
soname="$(readelf -d "$lib" | sed -n 's/.*(SONAME).*\[\(.*\)\].*/\1/p')"
[ -n "$soname" ] || { echo "abi_check: $lib has no soname"; exit 2; }
baseline="$abidir/$soname.abi"

dump() { # the abidw dump of $lib into $1: the baseline's options
  abidw --headers-dir "$headers" --no-corpus-path --no-comp-dir-path --short-locs --drop-private-types \
    --no-elf-needed --type-id-style hash "$lib" --out-file "$1"
}
if (( update )); then
  dump "$baseline" || { echo "abi_check: abidw failed"; exit 2; }
  echo "abi_check: stored $baseline"
  exit 0
fi
if [ ! -f "$baseline" ]; then
  echo "abi_check: FAIL: no stored baseline $baseline for soname $soname."
  echo "  A new soname starts a new baseline: bash tools/abi_check.sh --update (docs/abi.md)"
  exit 1
fi

suppr=()
[ -f "$supprfile" ] && suppr=(--suppressions "$supprfile")
report="$(abidiff "${suppr[@]}" --hd2 "$headers" "$baseline" "$lib")"
rc=$?
echo "abi_check: $lib ($soname) against $baseline"
echo "$report"
if (( rc & 1 )) || (( rc & 2 )); then echo "abi_check: abidiff failed (exit $rc)"; exit 2; fi
tmp="$(mktemp -d)"; trap 'rm -rf "$tmp"' EXIT
dump "$tmp/current.abi" || { echo "abi_check: abidw failed"; exit 2; }
layouts="$(python3 "$root/tools/abi_layouts_diff.py" "$baseline" "$tmp/current.abi" "$supprfile" "$(dirname "$headers")")"
lrc=$?
echo "$layouts"
(( lrc > 1 )) && { echo "abi_check: tools/abi_layouts_diff.py failed (exit $lrc)"; exit 2; }

why=()
(( rc & 8 )) && why+=("abidiff: incompatible change (exit $rc)")
echo "$report" | grep -E 'changes summary: [1-9][0-9]* Removed' >/dev/null && why+=("a function or variable removed")
echo "$report" | grep -E 'changes summary: [0-9]+ Removed, [1-9][0-9]* Changed' >/dev/null && why+=("a function or variable changed")
(( lrc == 1 )) && why+=("a struct layout changed (only members appended to a size-prefixed struct are compatible)")
if (( ${#why[@]} )); then
  echo "abi_check: FAIL: incompatible ABI change under soname $soname:"
  printf '  - %s\n' "${why[@]}"
  echo "  keep the change compatible, or bump KIN_ABI_VERSION (include/libkin/kin_version.h) and store"
  echo "  the new soname's baseline (bash tools/abi_check.sh --update); docs/abi.md"
  exit 1
fi
echo "abi_check: OK: compatible with the $soname baseline"
exit 0
