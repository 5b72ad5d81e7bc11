"""Progress display and Ctrl-C for the long C calls (include/libkin/kin_progress.h).

Every long call (the complete solver, locate, branch following) runs with a
C progress callback made here, whatever the caller asked for. The C library
calls it from the calling thread, at least every ~0.1 s of work, so Python
runs a little code that often in the thread that made the call: a pending
SIGINT then raises KeyboardInterrupt inside the callback. The callback
catches it, asks the C call to stop (returns 1: the call returns
KIN_ECANCELLED within a path or a step) and the KeyboardInterrupt is raised
again once the C call has returned, with the library's state consistent.

`progress` (the keyword of the wrappers) is
  None or False  no display (Ctrl-C still works);
  True           a tqdm bar on stderr, if tqdm is installed (else no display);
  a callable     progress(done, total), called with floats; a truthy return
                 cancels the call, which then raises CancelledError; an
                 exception it raises cancels the call and is raised again.
"""
from __future__ import annotations

import contextlib
from types import TracebackType
from typing import Any, Callable, Iterator, Optional, Type, Union

from ._lib import ffi, lib

#: What the `progress` keyword takes: None/False, True, or progress(done, total).
Progress = Union[None, bool, Callable[[float, float], Any]]


class Reporter:
    """The C callback of one long call and what happened in it."""

    def __init__(self, progress: Progress = None, desc: Optional[str] = None, unit: str = "it") -> None:
        if progress is not None and not isinstance(progress, bool) and not callable(progress):
            raise TypeError(f"progress: expected None, a bool or a callable, got {progress!r}")
        self._fn: Optional[Callable[[float, float], Any]] = progress if callable(progress) else None
        self._want_bar = progress is True
        self._desc, self._unit = desc, unit
        self._bar: Any = None
        self.interrupted = False  # a KeyboardInterrupt arrived during the call
        self.error: Optional[BaseException] = None  # the exception the caller's callable raised
        self.calls = 0
        # error=1: if an exception escapes _call anyway (a signal handled on
        # entry, before its try block), the call is cancelled too
        self.c_callback = ffi.callback("kin_progress_fn", self._call, error=1, onerror=self._onerror)

    def _call(self, user: Any, done: float, total: float) -> int:
        try:
            self.calls += 1
            if self._want_bar:
                self._show(done, total)
            if self._fn is not None and self._fn(done, total):
                return 1
            return 0
        except KeyboardInterrupt:
            self.interrupted = True
            return 1
        except BaseException as exc:  # noqa: BLE001 - raised again after the C call
            self.error = exc
            return 1

    def _onerror(self, exc_type: Optional[Type[BaseException]], exc_value: Optional[BaseException],
                 traceback: Optional[TracebackType]) -> None:
        if exc_type is not None and issubclass(exc_type, KeyboardInterrupt):
            self.interrupted = True
        elif self.error is None:
            self.error = exc_value
        return None  # the callback returns its error value, 1: cancel

    def _show(self, done_f: float, total_f: float) -> None:
        # whole counts (paths, steps) shown as integers
        done: float = int(done_f) if float(done_f).is_integer() else done_f
        total: float = int(total_f) if float(total_f).is_integer() else total_f
        if self._bar is None:
            try:
                from tqdm import tqdm
            except ImportError:
                self._want_bar = False
                return
            self._bar = tqdm(total=total, desc=self._desc, unit=self._unit)
        if total != self._bar.total:
            self._bar.total = total
        self._bar.update(done - self._bar.n)
        self._bar.n = done  # exact, and an int again after fractional steps

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None

    def raise_pending(self) -> None:
        """Raise the KeyboardInterrupt caught during the call, or the
        exception of the caller's callable."""
        if self.interrupted:
            raise KeyboardInterrupt
        if self.error is not None:
            raise self.error


@contextlib.contextmanager
def reporting(progress: Progress = None, desc: Optional[str] = None, unit: str = "it",
              handle: Any = None) -> Iterator[Reporter]:
    """Context for one long C call: yields a Reporter whose `c_callback` the
    call uses. With `handle`, the callback is installed on it
    (kin_set_progress) for the duration and removed after. On leaving,
    raises the KeyboardInterrupt caught during the call or the exception of
    the caller's callable; the caller then checks the status as usual
    (KIN_ECANCELLED from a callable's cancel raises CancelledError)."""
    rep = Reporter(progress, desc, unit)
    if handle is not None:
        lib.kin_set_progress(handle, rep.c_callback, ffi.NULL)
    try:
        yield rep
    finally:
        if handle is not None:
            lib.kin_set_progress(handle, ffi.NULL, ffi.NULL)
        rep.close()
    rep.raise_pending()
