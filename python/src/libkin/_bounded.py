"""Bounded reading of model files (issue 22: nothing read without a bound).

`read_bounded` reads a file only if it is a regular file of at most
`MAX_BYTES` bytes (64 MiB, the C library's KIN_LOAD_MAX_BYTES), opened without
blocking: a FIFO, a device (``/dev/zero``, a terminal) or a directory raises
`FileAccessError` at once, a larger file `LimitError` before it is read (or
as soon as it grows past the limit). `documented_errors` makes a loader raise
only libkin's classes on hostile input: what parsing lets escape
(OverflowError from a huge integer, RecursionError from deep nesting,
UnicodeDecodeError, a ValueError or TypeError of the standard library or
numpy) becomes `ModelFormatError`, a MemoryError `OutOfMemoryError`.
"""
from __future__ import annotations

import functools
import os
import stat
from typing import Any, Callable, Optional, TypeVar, Union, cast

from .errors import FileAccessError, KinError, LimitError, ModelFormatError, OutOfMemoryError

#: Largest model file read unless a loader's ``max_bytes`` says otherwise
#: (the C library's KIN_LOAD_MAX_BYTES).
MAX_BYTES = 64 * 1024 * 1024

F = TypeVar("F", bound=Callable[..., Any])


def read_bounded(path: Union[str, "os.PathLike[str]"], max_bytes: Optional[int] = None) -> bytes:
    """The bytes of the regular file at `path`, at most `max_bytes` of them
    (None: `MAX_BYTES`). Raises FileAccessError (an OSError) for a file that
    is not regular, LimitError (a ValueError) for one that is too large, and
    the OSError of open() for one that cannot be opened."""
    limit = MAX_BYTES if max_bytes is None else int(max_bytes)
    if limit < 0:
        raise LimitError(f"max_bytes = {limit}: must be >= 0")
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0) | getattr(os, "O_BINARY", 0)
    fd = os.open(path, flags)
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise FileAccessError(f"{os.fspath(path)}: not a regular file (a FIFO, device or directory is not read)")
        if st.st_size > limit:
            raise LimitError(f"{os.fspath(path)}: file of {st.st_size} bytes is larger than the limit of "
                             f"{limit} bytes (max_bytes raises it)")
        chunks, n = [], 0
        while n <= limit:
            chunk = os.read(fd, min(limit + 1 - n, 1 << 20))
            if not chunk:
                break
            chunks.append(chunk)
            n += len(chunk)
        if n > limit:
            raise LimitError(f"{os.fspath(path)}: file grew past the limit of {limit} bytes while read")
        return b"".join(chunks)
    finally:
        os.close(fd)


def decode_utf8(data: bytes) -> str:
    """`data` as UTF-8 text; ModelFormatError if it is not."""
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ModelFormatError(f"not UTF-8 text: byte {exc.start}: {exc.reason}") from None


def documented_errors(what: str) -> Callable[[F], F]:
    """Decorator: the wrapped loader raises KinError subclasses and OSError
    only. `what` names the input in the messages ("FOLD file")."""
    def wrap(fn: F) -> F:
        @functools.wraps(fn)
        def inner(*args: Any, **kwargs: Any) -> Any:
            try:
                return fn(*args, **kwargs)
            except (KinError, OSError):
                raise
            except MemoryError:
                raise OutOfMemoryError(f"{what}: out of memory while reading it") from None
            except RecursionError:
                raise ModelFormatError(f"{what}: lists or objects nested too deeply") from None
            except UnicodeError as exc:
                raise ModelFormatError(f"{what}: not UTF-8 text: {exc}") from None
            except (OverflowError, ValueError, TypeError, KeyError, IndexError, AttributeError,
                    ZeroDivisionError) as exc:
                raise ModelFormatError(f"{what}: malformed ({type(exc).__name__}: {exc})") from None
        return cast(F, inner)
    return wrap
