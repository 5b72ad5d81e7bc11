"""Running plain-data tasks: serially, on a concurrent.futures executor or on
a Dask cluster (run_tasks), and the executor a command line names
(executor). Used by the explorer (libkin.atlas) and the sharded complete
solver (libkin.homotopy); it imports no other part of libkin.
"""
from __future__ import annotations

import asyncio
import concurrent.futures
import contextlib
import sys
import time
from typing import Any, Callable, Iterator, List, Optional, Sequence, Union

#: progress of run_tasks and libkin.explore: None/False (quiet), True
#: (messages on stderr) or a callable getting (done, total, what)
Progress = Union[None, bool, Callable[[int, int, str], Any]]


def _is_dask_client(ex: Any) -> bool:
    try:
        from distributed import Client
    except ImportError:
        return False
    return isinstance(ex, Client)


def run_tasks(fn: Callable[[Any], Any], items: Sequence[Any], executor: Any = None, progress: Progress = None,
              what: str = "tasks", deadline: Optional[float] = None) -> List[Any]:
    """fn(item) for every item, serially (executor None) or on a
    concurrent.futures.Executor or a dask.distributed.Client; the results in
    the order of items. progress(done, total, what) after each. deadline (a
    time.perf_counter() value): tasks not started by then are not run (or
    are cancelled) and give None; tasks already running complete."""
    n = len(items)
    out: List[Any] = []
    if executor is None:
        for k, it in enumerate(items):
            out.append(None if deadline is not None and time.perf_counter() > deadline else fn(it))
            _tick(progress, k + 1, n, what)
        return out
    if _is_dask_client(executor):
        futures = executor.map(fn, items, pure=False)
    else:
        futures = [executor.submit(fn, it) for it in items]
    for k, f in enumerate(futures):
        if deadline is not None and not f.done():
            wait = deadline - time.perf_counter()
            try:
                out.append(f.result(timeout=max(wait, 0.0)) if wait > 0 else _cancel_or_wait(f))
            except (TimeoutError, concurrent.futures.TimeoutError, asyncio.TimeoutError):
                out.append(_cancel_or_wait(f))
        else:
            out.append(f.result())
        _tick(progress, k + 1, n, what)
    return out


def _cancel_or_wait(f: Any) -> Any:
    """Cancel a future that has not started (None); wait for a running one."""
    if f.cancel():
        return None
    return f.result()


def _tick(progress: Progress, done: int, total: int, what: str) -> None:
    if progress is None or progress is False:
        return
    if callable(progress):
        progress(done, total, what)
    elif done == total or done % max(1, total // 4) == 0:
        print(f"[explore] {what}: {done}/{total}", file=sys.stderr, flush=True)



@contextlib.contextmanager
def executor(kind: str, workers: int) -> Iterator[Any]:
    """The executor named on the command line (None for serial)."""
    if kind == "serial":
        yield None
    elif kind == "process":
        from concurrent.futures import ProcessPoolExecutor
        with ProcessPoolExecutor(max_workers=workers) as ex:
            yield ex
    else:
        try:
            from distributed import Client, LocalCluster
        except ImportError:
            raise ImportError("--executor dask needs dask[distributed] (pip install 'libkin[dask]')") from None
        with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                          dashboard_address=None) as cluster, Client(cluster) as client:
            yield client
