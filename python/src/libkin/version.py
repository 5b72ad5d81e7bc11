"""The version of libkin: the loaded C library's (``kin_version_string()``),
which is also the version of this package.

A module of its own so that code below the package root (the studies' cache
keys, the command line) can name the version without importing the root and
everything it re-exports; ``libkin.__version__`` is this same string.
"""
from typing import Any, Dict

from ._native._lib import c_string, lib

__version__: str = c_string(lib.kin_version_string())

__all__ = ["__version__", "blas", "blas_line"]


def blas() -> Dict[str, Any]:
    """The BLAS this process runs libkin on: {"library": path, "openblas":
    bool, "kernel": OpenBLAS's core name or None, "threads": int or None,
    "config": OpenBLAS's build string or None}. Times, and the last digits of
    results, depend on the kernel and threads (OPENBLAS_CORETYPE,
    OPENBLAS_NUM_THREADS), so benchmarks print it with their tables
    (docs/performance.md). Found in the process's own map of loaded
    libraries, so it is the one actually loaded (update-alternatives or
    LD_LIBRARY_PATH may select the reference BLAS)."""
    import ctypes
    import re

    path = None
    try:
        with open("/proc/self/maps") as fh:
            for line in fh:
                name = line.split()[-1] if len(line.split()) >= 6 else ""
                # NumPy's wheels bring an OpenBLAS of their own (site-packages, *.libs):
                # not the one the C library calls
                if re.search(r"/lib(open)?blas[^/]*\.so", name) and "site-packages" not in name \
                        and ".libs/" not in name:
                    path = name
                    if "openblas" in name:
                        break
    except OSError:  # not Linux: nothing to say
        pass
    out: Dict[str, Any] = {"library": path, "openblas": False, "kernel": None, "threads": None, "config": None}
    if path is None:
        return out
    try:
        dll = ctypes.CDLL(path)
        core = dll.openblas_get_corename
    except (OSError, AttributeError):
        return out
    core.restype = ctypes.c_char_p
    dll.openblas_get_config.restype = ctypes.c_char_p
    out.update(openblas=True, kernel=core().decode(), threads=int(dll.openblas_get_num_threads()),
               config=dll.openblas_get_config().decode())
    return out


def blas_line() -> str:
    """blas() as one line for a benchmark's output."""
    b = blas()
    if not b["openblas"]:
        return f"[BLAS: {b['library'] or 'not found'} (not OpenBLAS: no kernel name)]"
    return f"[BLAS: OpenBLAS, kernel {b['kernel']}, {b['threads']} thread(s); {b['library']}]"
