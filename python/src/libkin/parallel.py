"""Running plain-data tasks: serially, on a concurrent.futures executor or on
a Dask cluster (run_tasks, stream_dask), and the executor a command line
names (executor). Used by the explorer (libkin.atlas), its run store and
the sharded complete solver (libkin.homotopy); of libkin it imports only
libkin.errors and libkin._lifeline.

The executors are maintained ones: concurrent.futures' (ProcessPoolExecutor
with its initializer, forked workers; any Executor a caller gives) and
Dask's (LocalCluster, Client: submit, gather, cancel, wait; it reschedules a
lost worker's tasks itself). Kept here, part by part, as no executor gives it:

- ProcessPool + run_tasks' resubmission (worker renewal): a
  ProcessPoolExecutor whose worker died is broken for good, its futures in
  flight failed, and no executor reruns them. ProcessPool puts a new pool
  under the caller's one object; run_tasks resubmits the lost chunks up to
  RETRIES times, then raises WorkersLostError with the results so far. loky
  renews a broken pool too (get_reusable_executor), without the rerun, and
  its workers are new interpreters (1.7 s to the first result of 2 workers
  importing libkin here, 0.03 s forked; it refuses fork).
- ProcessPool.terminate(): a stop ends the workers of running tasks
  (SIGTERM, then SIGKILL); shutdown(cancel_futures=True) lets them run on
  (terminate_workers() comes with Python 3.14).
- run_tasks' window and halt: at most WINDOW_PER_WORKER tasks a worker in
  flight, each result taken as it completes (on_result: the store records
  it), a deadline or stop() cancelling what has not started in one sweep,
  the results in the items' order. Executor.map submits all at once, yields
  in order only, has no deadline or stop; as_completed() takes no new future.
- stream_dask (the store's streaming; run_tasks on Dask): the same window,
  the finished tasks gathered in one call per wait (a round trip to the
  scheduler per wait, not per task). distributed.as_completed takes new
  futures, but its next() returns only with a result (its timeout is the
  whole run's: no stop() meanwhile) and it fetches results one by one.
- chunks_for, run_chunk: several items a task within the window (chunksize
  is Executor.map's only).
- one_blas_thread: threadpoolctl sets the limit; ours is the count of uses
  nested or overlapping in one process (serial, a thread pool): the first in
  sets one thread, the last out restores (a threadpoolctl limit restores
  what was there at its own start). No executor limits BLAS in the caller's
  process (Dask does in its own worker processes only).
- terminate_on_sigterm, Terminated, _worker_init: the signals of the parent
  and of the workers; no executor makes SIGTERM the orderly stop of Ctrl-C
  (nor ends workers with a killed parent: libkin._lifeline).
- executor(): the command line's choice (ProcessPool, a LocalCluster's
  Client); on an exception it ends the workers, or silences Dask's logs.
- for_dask, tick, executor_width: the Dask form of libkin.shared's arrays,
  progress, how many tasks an executor runs at once.
"""
from __future__ import annotations

import asyncio
import concurrent.futures
import contextlib
import signal
import sys
import threading
import time
from concurrent.futures.process import BrokenProcessPool
from typing import Any, Callable, Dict, Iterator, List, Optional, Sequence, Union

from ._lifeline import die_with_parent
from .errors import KinError

#: times run_tasks renews a ProcessPool whose workers died before giving up
RETRIES = 3


class WorkersLostError(KinError, concurrent.futures.BrokenExecutor):
    """Worker processes died (killed) more often than run_tasks retries
    (also a concurrent.futures.BrokenExecutor, as BrokenProcessPool is).
    partial: the results of run_tasks received before, in the order of the
    items (None for the tasks not completed)."""

    def __init__(self, message: str, partial: Optional[List[Any]] = None) -> None:
        super().__init__(message)
        self.partial = partial if partial is not None else []


class Terminated(KeyboardInterrupt):
    """SIGTERM received while terminate_on_sigterm() was in force: the
    orderly stop of Ctrl-C."""


@contextlib.contextmanager
def terminate_on_sigterm() -> Iterator[None]:
    """Within: SIGTERM raises Terminated in the main thread, once (a second
    SIGTERM during the stop ends the process at once, as without this); the
    old handler is restored after. Does nothing outside the main thread."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def handler(signum: int, frame: Any) -> None:
        signal.signal(signal.SIGTERM, signal.SIG_DFL)
        raise Terminated()

    old = signal.signal(signal.SIGTERM, handler)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, old)


class _OneBlasThread:
    """The BLAS libraries of the process on one thread while a task runs:
    NumPy's own OpenBLAS, and the one libkin links (whose count the C side
    otherwise sets to one and puts back around every call of its own,
    model/blas_threads.c). In a 2-worker process pool on 2 cores the
    default counts (one thread per core) cost the flat-state atlas's branch
    tasks 3-11% more CPU (2,000 tasks, 6 pairs of runs alternately, load
    2.6-7; the wall time moved more, but noisily); serially in one process 1%. The counts are
    process-wide, so they are set for the duration only: the first of nested
    or concurrent uses sets one thread, the last one out restores what was
    there (threadpoolctl; nothing happens without it). In a thread other
    than the main one some OpenBLAS builds keep the count they had: pool
    workers run their tasks in their main thread.
    """

    def __init__(self) -> None:
        self.lock = threading.Lock()
        self.depth = 0
        self.controller: Any = None  # threadpoolctl.ThreadpoolController, made at the first use (False: none)
        self.modules = 0  # len(sys.modules) when it was made
        self.limiter: Any = None

    @contextlib.contextmanager
    def __call__(self) -> Iterator[None]:
        with self.lock:
            if self.depth == 0:
                if self.controller is None or self.modules != len(sys.modules):
                    # the loaded libraries, looked up again after imports (which may load another BLAS)
                    self.modules = len(sys.modules)
                    try:
                        from threadpoolctl import ThreadpoolController  # type: ignore[import-untyped]
                        self.controller = ThreadpoolController()
                    except Exception:  # noqa: BLE001 - not installed, or no BLAS it knows: nothing to set
                        self.controller = False
                if self.controller:
                    self.limiter = self.controller.limit(limits=1, user_api="blas")
            self.depth += 1
        try:
            yield
        finally:
            with self.lock:
                self.depth -= 1
                if self.depth == 0 and self.limiter is not None:
                    self.limiter.restore_original_limits()
                    self.limiter = None


#: with one_blas_thread(): the process's BLAS libraries on one thread for the block (_OneBlasThread)
one_blas_thread = _OneBlasThread()


def _worker_init() -> None:
    """In each pool worker: SIGTERM kills it (not the parent's handler,
    inherited by fork), Ctrl-C is the parent's to handle, it dies with its
    parent (libkin._lifeline); the --out lock is not inherited (libkin.atomic)."""
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    die_with_parent()


class ProcessPool(concurrent.futures.Executor):
    """A concurrent.futures process pool of `workers` processes that
    run_tasks can renew when a worker dies, and whose workers terminate()
    ends (SIGTERM, then SIGKILL) and joins."""

    def __init__(self, workers: int) -> None:
        self.workers = workers
        self._pool = self._new()

    def _new(self) -> concurrent.futures.ProcessPoolExecutor:
        return concurrent.futures.ProcessPoolExecutor(max_workers=self.workers, initializer=_worker_init)

    def submit(self, fn: Callable[..., Any], /, *args: Any, **kwargs: Any) -> "concurrent.futures.Future[Any]":
        try:
            return self._pool.submit(fn, *args, **kwargs)
        except BrokenProcessPool:  # broken in an earlier run: a new pool
            self.renew()
            return self._pool.submit(fn, *args, **kwargs)

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        self._pool.shutdown(wait=wait, cancel_futures=cancel_futures)

    def pids(self) -> List[int]:
        """The process ids of the current workers."""
        return list(getattr(self._pool, "_processes", None) or {})

    def renew(self) -> None:
        """Replace the pool (broken by a dead worker) by a new one of the
        same size; the old one's workers are ended."""
        self.terminate()
        self._pool = self._new()

    def terminate(self, grace: float = 2.0) -> None:
        """Cancel the pending tasks and end the workers, running tasks too."""
        procs = list((getattr(self._pool, "_processes", None) or {}).values())
        self._pool.shutdown(wait=False, cancel_futures=True)
        for p in procs:
            with contextlib.suppress(Exception):
                p.terminate()
        end = time.monotonic() + grace
        for p in procs:
            with contextlib.suppress(Exception):
                p.join(max(0.0, end - time.monotonic()))
                if p.is_alive():
                    p.kill()
                    p.join(grace)


#: progress of run_tasks and libkin.explore: None/False (quiet), True
#: (messages on stderr) or a callable getting (done, total, what)
Progress = Union[None, bool, Callable[[int, int, str], Any]]


def is_dask_client(ex: Any) -> bool:
    try:
        from distributed import Client
    except ImportError:
        return False
    return isinstance(ex, Client)


def run_tasks(fn: Callable[[Any], Any], items: Sequence[Any], executor: Any = None, progress: Progress = None,
              what: str = "tasks", deadline: Optional[float] = None,
              on_result: Optional[Callable[[int, Any], None]] = None,
              stop: Optional[Callable[[], bool]] = None, chunk: int = 1) -> List[Any]:
    """fn(item) for every item, serially (executor None) or on a
    concurrent.futures.Executor or a dask.distributed.Client; the results in
    the order of items. progress(done, total, what) after each.

    At most a window of tasks (WINDOW_PER_WORKER times the executor's width)
    is in flight; each result is taken as it completes, in any order, and
    the next task submitted, so no worker waits behind a slow task and a
    cancel has few futures to sweep (on Dask: stream_dask). on_result(k,
    result) is called in this thread as task k's result is taken (None for
    a task not run), so a caller can record results while the others run.

    deadline (a time.perf_counter() value) or stop() (checked every POLL s
    while waiting): once past / true, nothing more is started and the tasks
    in flight but not started are cancelled in one sweep; those, and the
    tasks never submitted, give None. The grace is the tasks running:
    serially the one running, on a concurrent.futures pool those its
    workers run (each bounded by its own budget); on Dask, at the deadline
    none (running tasks are cancelled too: their results are dropped), on
    stop() the window in flight (a signal lets the branches being followed
    complete).

    A process pool (ProcessPool) whose worker died is renewed and the tasks
    in flight resubmitted, up to RETRIES times; then WorkersLostError with
    the results so far. Dask's KilledWorker (a task whose workers died too
    often) gives WorkersLostError too.

    chunk > 1: up to that many consecutive items in one task (run_chunk;
    the window counts tasks), their results taken together: chunks_for()."""
    n = len(items)
    out: List[Any] = [None] * n
    taken = 0
    seen = [False] * n

    def take(k: int, res: Any) -> None:
        nonlocal taken
        out[k], seen[k] = res, True
        taken += 1
        if on_result is not None:
            on_result(k, res)
        tick(progress, taken, n, what)

    def halted() -> bool:
        return (deadline is not None and time.perf_counter() > deadline) or (stop is not None and bool(stop()))

    if executor is None:
        for k, it in enumerate(items):
            take(k, None if halted() else fn(it))
        return out
    window = WINDOW_PER_WORKER * executor_width(executor)
    chunk = max(1, int(chunk))
    if is_dask_client(executor):
        stream_dask(fn, items, executor, take, window, deadline, stop, chunk, what)
        for k in (k for k in range(n) if not seen[k]):  # not run (halted)
            take(k, None)
        return out
    inflight: Dict["concurrent.futures.Future[Any]", List[int]] = {}  # future -> the items it runs
    nxt = 0
    deaths = 0
    expired = False

    def submit(ks: List[int]) -> None:
        args = (fn, items[ks[0]]) if chunk == 1 else (run_chunk, fn, [items[k] for k in ks])
        inflight[executor.submit(*args)] = ks

    while nxt < n or inflight:
        if not expired and halted():
            expired = True
            for f in inflight:  # in one sweep, in order: a pool's feeder takes the next from the front
                f.cancel()
        while not expired and nxt < n and len(inflight) < window:
            submit(list(range(nxt, min(n, nxt + chunk))))  # the next chunk of items
            nxt = min(n, nxt + chunk)
        if not inflight:
            break
        timeout = None if (deadline is None and stop is None) or expired else POLL
        if deadline is not None and timeout is not None:
            timeout = max(0.0, min(timeout, deadline - time.perf_counter()))
        done = concurrent.futures.wait(inflight, timeout=timeout, return_when=concurrent.futures.FIRST_COMPLETED)[0]
        for f in [f for f in inflight if f in done]:  # in submission order
            if f not in inflight:  # resubmitted after a lost worker below
                continue
            ks = inflight.pop(f)
            if f.cancelled():
                for k in ks:
                    take(k, None)
                continue
            try:
                res = f.result()
            except BrokenProcessPool:
                deaths += 1
                if not isinstance(executor, ProcessPool) or deaths > RETRIES:
                    raise WorkersLostError(f"worker processes died {deaths} time{'s' if deaths > 1 else ''}; "
                                           f"{taken} of {n} {what} completed", out) from None
                executor.renew()
                lost = sorted(ks + [j for g, js in inflight.items() if not _succeeded(g) for j in js])
                for g in [g for g in inflight if not _succeeded(g)]:
                    del inflight[g]
                for i in range(0, len(lost), chunk):
                    if expired:
                        for j in lost[i:i + chunk]:
                            take(j, None)
                    else:
                        submit(lost[i:i + chunk])
                break  # the set of done futures is stale
            for k, r in zip(ks, res if chunk > 1 else [res]):
                take(k, r)
    for k in range(nxt, n):  # never submitted: halted
        take(k, None)
    return out


def for_dask(item: Any) -> Any:
    """A task item as a Dask task takes it: in a dict item, each value
    with a dask_arg() method (libkin.shared.Ref) replaced by what it gives
    (a dict holding a future Dask resolves in the worker)."""
    if isinstance(item, dict) and any(hasattr(v, "dask_arg") for v in item.values()):
        return {k: v.dask_arg() if hasattr(v, "dask_arg") else v for k, v in item.items()}
    return item


def run_chunk(fn: Callable[[Any], Any], items: Sequence[Any]) -> List[Any]:
    """[fn(item) for item in items]: one task for several items."""
    return [fn(it) for it in items]


def stream_dask(fn: Callable[[Any], Any], items: Sequence[Any], client: Any, record: Callable[[int, Any], None],
                window: int, deadline: Optional[float] = None, stop: Optional[Callable[[], bool]] = None,
                chunk: int = 1, what: str = "tasks") -> List[Any]:
    """fn(item) for every item on a dask.distributed.Client, `chunk` items
    a task (run_chunk: the client's cost per task, about 5 ms of its CPU,
    shared by the chunk), at most `window` tasks submitted and not yet
    received at any time; record(k, result) for each item as its task
    completes, in the order of completion, and the results in the order of
    items. The workers are kept busy (the next tasks wait in the window)
    while the client receives and records: the finished ones are gathered
    in one call per wait, so a round trip to the scheduler is paid per
    wait, not per task, and no task waits for a batch's slowest. Once
    stop() is true (checked at least every POLL seconds) nothing more is
    submitted and the tasks in flight complete (recorded); past the
    deadline they are cancelled too (Dask cancels running tasks). The
    tasks not run give None (not recorded). A task's error is raised;
    workers killed running one task: WorkersLostError."""
    from distributed import wait as dask_wait
    n, nxt, chunk = len(items), 0, max(1, int(chunk))
    out: List[Any] = [None] * n
    pending: Dict[str, Any] = {}  # future key -> (future, first item index)
    got_n = 0

    stopping = False
    while True:
        if deadline is not None and time.perf_counter() > deadline:
            if pending:
                client.cancel([f for f, _ in pending.values()])
            return out
        stopping = stopping or (stop is not None and stop())
        while not stopping and nxt < n and len(pending) < window:
            f = client.submit(run_chunk, fn, [for_dask(it) for it in items[nxt:nxt + chunk]], pure=False)
            pending[f.key] = (f, nxt)
            nxt += chunk
        if not pending:
            return out
        left = POLL if deadline is None else min(POLL, max(0.0, deadline - time.perf_counter()))
        try:  # at most POLL seconds, so that stop() and the deadline are seen
            done = dask_wait([f for f, _ in pending.values()], timeout=left, return_when="FIRST_COMPLETED").done
        except (TimeoutError, asyncio.TimeoutError):
            continue
        finished = [f for f in done if f.status == "finished"]
        for f in done:
            if f.status != "finished":
                try:
                    f.result()
                except Exception as exc:
                    if type(exc).__name__ == "KilledWorker":  # a task's workers died too often
                        raise WorkersLostError(f"Dask workers died running one task; "
                                               f"{got_n} of {n} {what} completed", out) from None
                    raise
        for f, got in zip(finished, client.gather(finished) if finished else []):
            first = pending.pop(f.key)[1]
            for k, res in enumerate(got, first):
                out[k] = res
                got_n += 1
                record(k, res)


#: tasks in flight per worker of the executor (run_tasks): enough that a
#: worker finds the next task queued when it finishes one; at most
#: POOL_CHUNK items in one process-pool task (chunks_for); POLL: seconds
#: between looks at stop() and the deadline while waiting
WINDOW_PER_WORKER, POOL_CHUNK, POLL = 4, 4, 0.1


def chunks_for(executor: Any, n: int) -> int:
    """Items per task for n tasks of a few ms (run_tasks' chunk): a process
    pool's task costs the client about 0.32 ms of CPU (2,000 tasks of 4 ms
    on 2 workers: 0.08-0.10 ms in chunks of 4, wall 4.4-4.6 -> 4.15 s), so
    up to POOL_CHUNK there while that leaves 4 windows of tasks; 1 elsewhere."""
    if not isinstance(executor, (ProcessPool, concurrent.futures.ProcessPoolExecutor)):
        return 1
    return max(1, min(POOL_CHUNK, n // (4 * WINDOW_PER_WORKER * executor_width(executor))))


def executor_width(executor: Any) -> int:
    """How many tasks the executor runs at once: 1 serially, a guess of 4
    for an executor that does not say."""
    if executor is None:
        return 1
    n: Any = None
    if is_dask_client(executor):
        with contextlib.suppress(Exception):
            n = sum(executor.nthreads().values())
    else:
        n = getattr(executor, "workers", None) or getattr(executor, "_max_workers", None)
    return max(1, int(n or 4))


def _succeeded(f: "concurrent.futures.Future[Any]") -> bool:
    return f.done() and not f.cancelled() and f.exception() is None


def tick(progress: Progress, done: int, total: int, what: str) -> None:
    """progress(done, total, what), or a line on stderr at each quarter when progress is True."""
    if progress is None or progress is False:
        return
    if callable(progress):
        progress(done, total, what)
    elif done == total or done % max(1, total // 4) == 0:
        print(f"[explore] {what}: {done}/{total}", file=sys.stderr, flush=True)


@contextlib.contextmanager
def executor(kind: str, workers: int) -> Iterator[Any]:
    """The executor named on the command line (None for serial). A
    process pool is a ProcessPool (renewed when a worker dies); leaving by
    an exception (Ctrl-C, Terminated) ends its workers at once."""
    if kind == "serial":
        yield None
    elif kind == "process":
        pool = ProcessPool(workers)
        try:
            yield pool
        except BaseException:
            pool.terminate()  # an error, Ctrl-C or SIGTERM: no worker left behind
            raise
        pool.shutdown(wait=True)
    else:
        try:
            import logging
            from distributed import Client, LocalCluster
        except ImportError:
            raise ImportError("--executor dask needs dask[distributed] (pip install 'libkin[dask]')") from None
        # dashboard ":0": a free port (the default 8787 warns when taken); silence_logs: a stopped run's
        # worker heartbeat to the closed scheduler logged a traceback under load (task errors reach the client)
        with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0",
                          silence_logs=logging.CRITICAL) as cluster, Client(cluster) as client:
            try:
                yield client
            except BaseException:
                _quiet_dask(client)  # stopped: no pages of shutdown warnings from the workers
                raise


def _quiet_dask(client: Any) -> None:
    """Silence the logs of distributed here, in the workers and nannies."""
    _quiet_logs()
    for nanny in (False, True):
        with contextlib.suppress(Exception):
            client.run(_quiet_logs, nanny=nanny)


def _quiet_logs() -> None:
    import logging
    logging.getLogger("distributed").setLevel(logging.CRITICAL + 1)
