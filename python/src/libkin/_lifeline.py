"""Pool workers die with their parent (issue 39 item 2): die_with_parent(),
called in a worker's initializer (libkin.parallel._worker_init), so that a
SIGKILLed parent leaves no forked worker computing on (nor holding what it
inherited). No executor does it: concurrent.futures' workers notice a dead
parent only when they next read their call queue, i.e. after the task they
run, which may be long.

- On Linux, prctl(PR_SET_PDEATHSIG, SIGKILL), when the worker was forked
  from the parent's main thread: the signal follows the thread that forked,
  and a pool used from another thread could outlive it.
- Everywhere, a daemon thread that ends the worker as soon as its parent
  changes (os.getppid(), every POLL seconds): the fallback.

The parent's pid and thread are recorded just before each fork
(os.register_at_fork), so the worker compares with the process that forked
it, even if that one died before the worker's first instruction."""
from __future__ import annotations

import contextlib
import ctypes
import os
import signal
import sys
import threading
import time

__all__ = ["die_with_parent", "POLL"]

#: seconds between a worker's looks at its parent
POLL = 0.5
_PR_SET_PDEATHSIG = 1
_FORK = [0, False]  # set in the forking thread just before a fork: the parent's pid, its main thread?


def _before_fork() -> None:
    _FORK[:] = [os.getpid(), threading.current_thread() is threading.main_thread()]


if hasattr(os, "register_at_fork"):
    os.register_at_fork(before=_before_fork)


def die_with_parent() -> None:
    """End this process (a forked worker) when its parent dies."""
    parent, from_main = (_FORK[0], _FORK[1]) if _FORK[0] else (os.getppid(), False)
    if from_main and sys.platform.startswith("linux"):
        with contextlib.suppress(Exception):
            ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0)
    if os.getppid() != parent:  # the parent died before that
        os._exit(1)

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(POLL)
        os._exit(1)
    threading.Thread(target=watch, name="libkin-parent-watch", daemon=True).start()
