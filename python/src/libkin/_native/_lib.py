"""Find and load the libkin shared library (cffi ABI mode).

Lookup order: $LIBKIN_LIBRARY -> a copy inside this package (_lib/) -> the
repository's build tree (build/libkin.so, for development) -> the system
loader (ctypes.util.find_library). A failure lists every place tried. The
library's runtime version must equal the version of the headers the
declarations were generated from.
"""
from __future__ import annotations

import ctypes.util
import os
import pathlib
from typing import Any, Iterator, List, Optional, Tuple

import cffi

from ._cdef import CDEF, VERSION_NUMBER

# Typed as Any: the cdata cffi makes (structs, pointers) have their fields
# and functions from CDEF at run time, which no stub can describe.
ffi: Any = cffi.FFI()
ffi.cdef(CDEF)

# the package folder (libkin/), where an installed wheel keeps its copy in _lib/
_HERE = pathlib.Path(__file__).resolve().parents[1]
_SYSTEM = "system loader (find_library('kin'))"


def _candidates() -> Iterator[Tuple[str, str]]:
    env = os.environ.get("LIBKIN_LIBRARY")
    if env:
        yield "environment variable LIBKIN_LIBRARY", env
    for p in sorted((_HERE / "_lib").glob("libkin.so*")) + sorted((_HERE / "_lib").glob("libkin*.dylib")):
        yield "package copy", str(p)
    build = _HERE.parents[2] / "build" / "libkin.so"
    yield "repository build tree", str(build)
    found = ctypes.util.find_library("kin")
    yield _SYSTEM, found or "libkin.so"


def _load() -> Tuple[Any, str]:
    tried: List[str] = []
    for where, path in _candidates():
        if where != _SYSTEM and not os.path.exists(path):
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


def c_string(ptr: Any) -> str:
    """The text of a C ``const char *`` (UTF-8; '' for NULL)."""
    if ptr == ffi.NULL:
        return ""
    raw = ffi.string(ptr)
    return raw.decode("utf-8", "replace") if isinstance(raw, bytes) else str(raw)


#: The loaded library: every function and constant of the C headers
#: (``lib.kin_analyse``, ``lib.KIN_EINVAL``, ...).
lib: Any
#: The path the library was loaded from.
library_path: str
lib, library_path = _load()


def new_struct(ctype: str, n: Optional[int] = None) -> Any:
    """A zeroed libkin options/info struct with its leading `size` field set.

    Parameters
    ----------
    ctype : str
        The struct's C type, e.g. ``"kin_options"``.
    n : int, optional
        Make an array of `n` of them instead of one.

    Returns
    -------
    cffi pointer or array
        Owned by Python; ``size`` set as the C library requires (docs/abi.md).
    """
    if n is None:
        p = ffi.new(ctype + " *")
        p.size = ffi.sizeof(ctype)
    else:
        p = ffi.new(ctype + "[]", n)
        for i in range(n):
            p[i].size = ffi.sizeof(ctype)
    return p


def default_struct(ctype: str, *args: Any) -> Any:
    """An options struct holding the library's defaults for every field.

    Calls the sized form ``<ctype>_init(p, sizeof, *args)`` with the size of
    the struct these declarations describe: the plain ``<ctype>_default``
    symbol fills only the struct's first layout (docs/abi.md).

    Parameters
    ----------
    ctype : str
        The struct's C type, e.g. ``"kin_locate_options"``.
    *args
        Further arguments of the init function (``kin_sail_params``: n_sides, n_loops).

    Returns
    -------
    cffi pointer
        Owned by Python.
    """
    p = ffi.new(ctype + " *")
    rc = getattr(lib, ctype + "_init")(p, ffi.sizeof(ctype), *args)
    if rc != 0:
        raise RuntimeError(f"{ctype}_init refused sizeof({ctype}) = {ffi.sizeof(ctype)}: "
                           "the library does not match these declarations")
    return p
