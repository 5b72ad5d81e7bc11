"""Find and load the libkin shared library (cffi ABI mode).

Lookup order: $LIBKIN_LIBRARY -> a copy inside this package (_lib/) -> the
repository's build tree (build/libkin.so, for development) -> the system
loader (ctypes.util.find_library). A failure lists every place tried. The
library's runtime version must equal the version of the headers the
declarations were generated from.
"""
import ctypes.util
import os
import pathlib

import cffi

from ._cdef import CDEF, VERSION_NUMBER

ffi = cffi.FFI()
ffi.cdef(CDEF)

_HERE = pathlib.Path(__file__).resolve().parent


def _candidates():
    env = os.environ.get("LIBKIN_LIBRARY")
    if env:
        yield "environment variable LIBKIN_LIBRARY", env
    for p in sorted((_HERE / "_lib").glob("libkin.so*")) + sorted((_HERE / "_lib").glob("libkin*.dylib")):
        yield "package copy", str(p)
    build = _HERE.parents[2] / "build" / "libkin.so"
    yield "repository build tree", str(build)
    found = ctypes.util.find_library("kin")
    yield "system loader (find_library('kin'))", found or "libkin.so"


def _load():
    tried = []
    for where, path in _candidates():
        if where != "system loader (find_library('kin'))" and not os.path.exists(path):
            tried.append(f"  {where}: {path} (not found)")
            continue
        try:
            lib = ffi.dlopen(path)
        except OSError as exc:
            tried.append(f"  {where}: {path} ({exc})")
            continue
        got = lib.kin_version_number()
        if got != VERSION_NUMBER:
            raise ImportError(
                f"libkin at {path} has version {got}, but this package was generated for "
                f"{VERSION_NUMBER}; rebuild the library or regenerate the package")
        return lib, path
    raise ImportError("could not load the libkin shared library; tried:\n" + "\n".join(tried))


lib, library_path = _load()


def new_struct(ctype, n=None):
    """A zeroed libkin options/info struct (or an array of n of them) with its
    leading `size` field set, as the C library requires (docs/abi.md)."""
    if n is None:
        p = ffi.new(ctype + " *")
        p.size = ffi.sizeof(ctype)
    else:
        p = ffi.new(ctype + "[]", n)
        for i in range(n):
            p[i].size = ffi.sizeof(ctype)
    return p
