#!/usr/bin/env bash
# test_static: a fully static consumer through pkg-config, as in
# docs/fortran.md's "static link": install into a scratch prefix, then
#   cc -static tests/consumer/main.c $(pkg-config --static --cflags --libs libkin)
# and run it (no dynamic loader). libkin.pc's Libs.private must name every
# library libkin.a's dependencies' static archives need (OpenMP, METIS,
# gfortran, ...). Skipped (77) with the reason when a static archive is
# missing here: one named by Libs.private, or one the configure step found
# no library for at all ($MISSING, cmake/KinStaticLibs.cmake).
# Usage: static_check.sh SRC BIN WORK; environment CC, CMAKE, MISSING.
set -u
src=$1 bin=$2 work=$3
cc=${CC:-cc}
rm -rf "$work" && mkdir -p "$work" || exit 1
if [ -n "${MISSING:-}" ]; then
  echo "SKIP: no library at all for ${MISSING} (needed by a dependency's static archive," \
       "e.g. CHOLMOD's by METIS; on Debian libmetis-dev ships no libmetis.a)"
  exit 77
fi
if ! command -v pkg-config >/dev/null; then
  echo "SKIP: no pkg-config"; exit 77
fi
"${CMAKE:-cmake}" --install "$bin" --prefix "$work/prefix" >"$work/install.log" 2>&1 ||
  { cat "$work/install.log"; exit 1; }
pcdir=$(echo "$work"/prefix/lib*/pkgconfig)
flags=$(PKG_CONFIG_PATH=$pcdir pkg-config --static --cflags --libs libkin) || exit 1
echo "pkg-config --static --cflags --libs libkin: $flags"
# every -l must have a static archive (the C library's own included)
absent=
for f in $flags; do
  case $f in
    -lkin) ;;
    -l*) a=$("$cc" -print-file-name=lib${f#-l}.a)
         case $a in /*) [ -e "$a" ] || absent="$absent lib${f#-l}.a" ;; *) absent="$absent lib${f#-l}.a" ;; esac ;;
  esac
done
if [ -n "$absent" ]; then
  echo "SKIP: no static archive for:$absent"
  exit 77
fi
# shellcheck disable=SC2086 # the flags are words
if ! "$cc" -static -std=c99 "$src/tests/consumer/main.c" -o "$work/consumer_static" $flags \
     >"$work/link.log" 2>&1; then
  grep -v "statically linked applications requires at runtime" "$work/link.log" | head -40
  echo "FAIL: the fully static link failed"
  exit 1
fi
if command -v readelf >/dev/null && readelf -l "$work/consumer_static" | grep -q INTERP; then
  echo "FAIL: $work/consumer_static has a dynamic loader"; exit 1
fi
"$work/consumer_static" || { echo "FAIL: the static consumer failed"; exit 1; }
echo "test_static: fully static consumer (pkg-config --static) linked and ran"
