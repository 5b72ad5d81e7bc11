"""Validation of numpy arrays before C sees a pointer."""
from __future__ import annotations

from typing import Any, Optional, Sequence

import numpy as np
import numpy.typing as npt

from ._lib import ffi
from ..errors import ArgumentTypeError, InvalidArgumentError


def as_c_array(value: Any, dtype: npt.DTypeLike, shape: Sequence[Optional[int]], name: str) -> np.ndarray:
    """A C-contiguous array of `dtype` and `shape`, copied only if `value` is not one already.

    Parameters
    ----------
    value : array_like
        What the caller passed.
    dtype : numpy dtype
        The dtype C expects (float64, int32 or uint8).
    shape : sequence of int or None
        The expected shape; None accepts any length in that axis.
    name : str
        The argument's name, for the error message.

    Returns
    -------
    numpy.ndarray
        `value` as a C-contiguous array of `dtype`.

    Raises
    ------
    ArgumentTypeError
        `value` is not numeric, is ragged, or holds non-integers where
        integers are expected (a TypeError).
    InvalidArgumentError
        The shape is wrong or integers are out of range for `dtype` (a ValueError).
    """
    try:
        arr = np.asarray(value)
    except Exception as exc:  # noqa: BLE001 - numpy raises many kinds
        raise ArgumentTypeError(f"{name}: not an array ({exc})") from None
    if arr.dtype == object or arr.dtype.kind not in "biuf":
        raise ArgumentTypeError(f"{name}: ragged or non-numeric array ({arr.dtype})")
    want_kind = np.dtype(dtype).kind
    if want_kind in "iu" and arr.dtype.kind == "f" and arr.size:
        if not np.all(np.isfinite(arr)) or np.any(arr != np.round(arr)):
            raise ArgumentTypeError(f"{name}: expected integers, got {arr.dtype}")
    if want_kind in "iu" and arr.size:
        info = np.iinfo(dtype)
        if arr.min() < info.min or arr.max() > info.max:
            raise InvalidArgumentError(f"{name}: values out of range for {np.dtype(dtype).name}")
    if arr.ndim != len(shape) or any(s is not None and s != n for s, n in zip(shape, arr.shape)):
        want = "(" + ", ".join("n" if s is None else str(s) for s in shape) + ")"
        raise InvalidArgumentError(f"{name}: expected shape {want}, got {arr.shape}")
    return np.ascontiguousarray(arr, dtype=dtype)


def read_ptr(arr: np.ndarray, ctype: str) -> Any:
    """Zero-copy pointer for C to read `arr` (which must be C-contiguous)."""
    assert arr.flags.c_contiguous
    return ffi.cast(ctype, ffi.from_buffer(arr))


def write_ptr(arr: np.ndarray, ctype: str) -> Any:
    """Zero-copy pointer for C to fill `arr` (writable, contiguous in memory)."""
    # a Fortran-ordered (rows, cols) array is the C-ordered (cols, rows)
    # array of its transpose: the same memory, which is what column-major C wants
    buf = arr if arr.flags.c_contiguous else arr.T
    assert buf.flags.c_contiguous
    return ffi.cast(ctype, ffi.from_buffer(buf, require_writable=True))
