"""Validation of numpy arrays before C sees a pointer."""
import numpy as np

from ._lib import ffi
from .errors import ModelFormatError


def as_c_array(value, dtype, shape, name):
    """Return a C-contiguous array of dtype and shape (None = any length in
    that axis), copying only when value is not one already. Raises
    ModelFormatError naming `name` on a wrong shape or a lossy dtype."""
    try:
        arr = np.asarray(value)
    except Exception as exc:  # noqa: BLE001 - numpy raises many kinds
        raise ModelFormatError(f"{name}: not an array ({exc})") from None
    if arr.dtype == object:
        raise ModelFormatError(f"{name}: ragged or non-numeric array")
    if np.dtype(dtype).kind in "iu" and arr.dtype.kind == "f":
        if arr.size and not np.all(np.isfinite(arr)) or (arr.size and np.any(arr != np.round(arr))):
            raise ModelFormatError(f"{name}: expected integers, got {arr.dtype}")
    if np.dtype(dtype).kind in "iu" and arr.size:
        info = np.iinfo(dtype)
        if arr.min() < info.min or arr.max() > info.max:
            raise ModelFormatError(f"{name}: values out of range for {np.dtype(dtype).name}")
    if arr.ndim != len(shape) or any(s is not None and s != n for s, n in zip(shape, arr.shape)):
        want = "(" + ", ".join("n" if s is None else str(s) for s in shape) + ")"
        raise ModelFormatError(f"{name}: expected shape {want}, got {arr.shape}")
    return np.ascontiguousarray(arr, dtype=dtype)


def read_ptr(arr, ctype):
    """Zero-copy pointer for C to read arr (which must be C-contiguous)."""
    assert arr.flags.c_contiguous
    return ffi.cast(ctype, ffi.from_buffer(arr))


def write_ptr(arr, ctype):
    """Zero-copy pointer for C to fill arr (writable, contiguous in memory)."""
    # a Fortran-ordered (rows, cols) array is the C-ordered (cols, rows)
    # array of its transpose: the same memory, which is what column-major C wants
    buf = arr if arr.flags.c_contiguous else arr.T
    assert buf.flags.c_contiguous
    return ffi.cast(ctype, ffi.from_buffer(buf, require_writable=True))
