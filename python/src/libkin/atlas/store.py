"""The run store of libkin.explore: every solved node and every followed
branch recorded as it completes, so an interrupted run resumes.

An SQLite file (the standard library's sqlite3, WAL mode, one transaction
per recorded result) holds the run's fingerprint (a hash of the model and
of the settings that shape the atlas) and the results, each keyed by a hash
of its task (the plain data a task takes: tasks.follow_branch's dict, the
complete solver's system). The explorer is deterministic, so a resumed run
asks for the same tasks in the same order: those in the store are taken
from it, the others computed and recorded, and the atlas is the one an
uninterrupted run gives. A store of another model or other settings is
refused (StoreMismatchError). Results are JSON (floats round-trip exactly).

The store is verified, never trusted: each record carries a SHA-256 digest
of its key, its kind and its JSON text (_digest). A record whose digest does
not match (an edited value, key or kind, garbage), or that has none (a
store written before digests, libkin 0.3.0 of before issue 39: the column
is added and those records are recomputed), is recomputed and recorded
again, and counted (`recomputed` in the run's stats["store"], and a line of
`libkin explore`). A store that cannot be used (not an SQLite file, a
damaged or truncated one, a failed write such as a full disk under it, a
table that is not a store's) raises StoreError, one line naming the store
and what to do: `libkin explore` exits with EXIT_STORE (5), never with a
traceback. A resumed run checks the file first (PRAGMA quick_check).

LIBKIN_STORE_KILL_AFTER=k (a test hook): the process kills itself with
SIGKILL right after the k-th result it records.
"""
from __future__ import annotations

import contextlib
import errno
import hashlib
import json
import os
import pathlib
import signal
import sqlite3
import time
from typing import Any, Callable, Dict, Iterator, List, Optional, Sequence, Union

from ..errors import InvalidArgumentError, KinError
from ..parallel import Progress, chunks_for, executor_width, is_dask_client, run_tasks, stream_dask, tick
from ..shared import Ref, content

# on Dask, tasks in flight (submitted, not yet recorded) per worker: the next
# ones wait on the scheduler while the client records the finished ones
DASK_WINDOW = 4
# and at most this many tasks in one Dask task (while that leaves at least 4
# windows of chunks): the client's cost per Dask task, about 5 ms
# of its CPU (bench/bench_atlas_depth.py scaling), shared by the chunk
DASK_CHUNK = 16

__all__ = ["Store", "StoreError", "StoreMismatchError", "fingerprint", "default_path", "open_store", "remove_store"]

_SCHEMA = ("CREATE TABLE IF NOT EXISTS meta (key TEXT PRIMARY KEY, value TEXT NOT NULL)",
           "CREATE TABLE IF NOT EXISTS results (key TEXT PRIMARY KEY, kind TEXT NOT NULL, "
           "seq INTEGER NOT NULL, value TEXT NOT NULL, digest TEXT)")
_COLUMNS = {"meta": ["key", "value"], "results": ["key", "kind", "seq", "value", "digest"]}


class StoreMismatchError(InvalidArgumentError):
    """The store was written by a run of another model or other settings."""


class StoreError(KinError):
    """The store cannot be used: not a store, damaged or truncated, or a
    write failed (a full disk under it). `libkin explore` exits 5."""


def _digest(key: str, kind: str, text: str) -> str:
    """A record's checksum: its key, kind and JSON text, serialized as one
    JSON list (canonical: the three strings as stored)."""
    return hashlib.sha256(json.dumps([key, kind, text]).encode()).hexdigest()


def _store_error(path: pathlib.Path, what: str, exc: BaseException) -> StoreError:
    text = " ".join(str(exc).split()) or type(exc).__name__
    full = "full" in text.lower() or getattr(exc, "errno", None) == errno.ENOSPC
    todo = ("free space under it and continue with --resume (what was recorded is kept)" if full else
            "remove it (a run without --resume starts afresh) or give another --store")
    return StoreError(f"the store {path} cannot be used: {what}: {text}; {todo}")


def _hash(data: Any) -> str:
    return hashlib.sha256(json.dumps(data, sort_keys=True, default=_by_content).encode()).hexdigest()


def _by_content(x: Any) -> Any:
    """A NumPy array in a task (atlas/directions.py): by its shape and the
    digest of its bytes; a shared one (libkin.shared.Ref) by its content too,
    never by its file or future (the same key in every run)."""
    import numpy as np
    if isinstance(x, Ref):
        return content(x)
    if isinstance(x, np.ndarray):
        a = np.ascontiguousarray(x, dtype=np.float64)
        return {"ndarray": list(a.shape), "sha256": hashlib.sha256(a.tobytes()).hexdigest()}
    raise TypeError(f"not JSON serializable: {type(x).__name__}")


def fingerprint(model_text: str, settings: Any) -> str:
    """The run's identity: the model (JSON text, the start configuration
    included) and the settings that shape the atlas."""
    return _hash({"model": model_text, "settings": settings})


def default_path(out: Union[str, "os.PathLike[str]"]) -> pathlib.Path:
    """The store of the output folder out: `.NAME.explore.sqlite` next to it
    (outside it: the folder is replaced whole when the atlas is written)."""
    p = pathlib.Path(out).resolve()
    return p.parent / f".{p.name}.explore.sqlite"


def open_store(store: Union[None, str, "os.PathLike[str]", "Store"], resume: bool, model_text: str,
               settings: Any) -> Optional["Store"]:
    """explore()'s store argument as a Store (None: no store)."""
    if store is None or isinstance(store, Store):
        return store
    return Store(store, fingerprint(model_text, settings), resume)


def remove_store(path: Union[str, "os.PathLike[str]"]) -> None:
    """Delete a store and its WAL files."""
    for suffix in ("", "-wal", "-shm", "-journal"):
        try:
            os.unlink(f"{path}{suffix}")
        except FileNotFoundError:
            pass


class Store:
    """The results of one run. resume=False starts afresh (a store of the
    same run is emptied); resume=True keeps what is recorded. Either way a
    store of another run is refused."""

    def __init__(self, path: Union[str, "os.PathLike[str]"], fingerprint: str, resume: bool = False) -> None:
        self.path = pathlib.Path(path)
        self.db: Optional[sqlite3.Connection] = None
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self.db = sqlite3.connect(str(self.path), isolation_level=None)
            self._open(fingerprint, resume)
        except StoreMismatchError:
            self.close()
            raise
        except (sqlite3.Error, OSError) as exc:
            self.close()
            raise _store_error(self.path, "opening it", exc) from None
        except BaseException:
            self.close()
            raise
        self.reused = 0      # results taken from the store in this run
        self.recorded = 0    # results computed and recorded in this run
        self.recomputed = 0  # records that failed their digest (or had none): computed again
        kill = os.environ.get("LIBKIN_STORE_KILL_AFTER")
        self.kill_after = int(kill) if kill else None

    def _open(self, fingerprint: str, resume: bool) -> None:
        db = self.db
        assert db is not None
        if resume:
            bad = [r[0] for r in db.execute("PRAGMA quick_check").fetchall()]
            if bad != ["ok"]:
                raise sqlite3.DatabaseError("damaged (" + "; ".join(map(str, bad[:3])) + ")")
        db.execute("PRAGMA journal_mode=WAL")
        db.execute("PRAGMA synchronous=NORMAL")
        for stmt in _SCHEMA:
            db.execute(stmt)
        cols = {t: [r[1] for r in db.execute(f"PRAGMA table_info({t})")] for t in _COLUMNS}
        if cols["results"] == _COLUMNS["results"][:-1]:  # before digests: its records are recomputed
            db.execute("ALTER TABLE results ADD COLUMN digest TEXT")
            cols["results"] = _COLUMNS["results"]
        if cols != _COLUMNS:
            raise sqlite3.DatabaseError(f"its tables are not a libkin store's ({cols})")
        row = db.execute("SELECT value FROM meta WHERE key = 'fingerprint'").fetchone()
        if row is not None and row[0] != fingerprint:
            raise StoreMismatchError(f"the store {self.path} belongs to another run (another model, "
                                     "other settings, or results decided by another libkin's rules); give another "
                                     "--store or the same model and settings")
        with db:
            db.execute("BEGIN IMMEDIATE")
            if not resume:
                db.execute("DELETE FROM results")
            db.execute("INSERT OR REPLACE INTO meta VALUES ('fingerprint', ?)", (fingerprint,))
        self.seq = int(db.execute("SELECT COUNT(*) FROM results").fetchone()[0])

    @contextlib.contextmanager
    def _guard(self, what: str) -> Iterator[sqlite3.Connection]:
        """The connection, with SQLite's and the system's errors as StoreError."""
        if self.db is None:
            raise StoreError(f"the store {self.path} is closed")
        try:
            yield self.db
        except (sqlite3.Error, OSError) as exc:
            raise _store_error(self.path, what, exc) from None

    def close(self) -> None:
        if self.db is not None:
            self.db.close()
            self.db = None

    def finish(self, close: bool) -> Dict[str, Any]:
        """What this run took from the store and recorded (closed if close)."""
        rec = {"path": str(self.path), "reused": self.reused, "recorded": self.recorded,
               "recomputed": self.recomputed}
        if close:
            self.close()
        return rec

    def __enter__(self) -> Store:
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    def __len__(self) -> int:
        with self._guard("counting its records") as db:
            return int(db.execute("SELECT COUNT(*) FROM results").fetchone()[0])

    def get(self, key: str) -> Any:
        """The recorded result of key; None when there is none or when the
        record fails its digest (then counted in recomputed: the caller
        computes it and put() replaces the record)."""
        with self._guard("reading a record") as db:
            row = db.execute("SELECT kind, value, digest FROM results WHERE key = ?", (key,)).fetchone()
        if row is None:
            return None
        kind, text, digest = row
        value = None
        if (isinstance(kind, str) and isinstance(text, str) and key.startswith(kind + ":")
                and digest == _digest(key, kind, text)):
            try:
                value = json.loads(text)
            except ValueError:
                value = None
        if value is None:
            self.recomputed += 1
            return None
        self.reused += 1
        return value

    def put(self, kind: str, key: str, value: Any, text: Optional[str] = None) -> None:
        """Record one result (one committed transaction; text: its JSON, if
        already made). A commit per result keeps every finished result
        through a kill; it costs 0.18 ms (11 s of the client's CPU in the
        hexagonal sail's full atlas, 59,656 results: batching the commits was
        measured and not kept, since a kill would then lose finished work)."""
        text = json.dumps(value) if text is None else text
        with self._guard("recording a result") as db, db:
            db.execute("BEGIN IMMEDIATE")
            db.execute("INSERT OR REPLACE INTO results VALUES (?, ?, ?, ?, ?)",
                       (key, kind, self.seq, text, _digest(key, kind, text)))
        self.seq += 1
        self.recorded += 1
        if self.kill_after is not None and self.recorded >= self.kill_after:
            os.kill(os.getpid(), signal.SIGKILL)

    def cached(self, kind: str, task: Any, compute: Callable[[], Any]) -> Any:
        """The recorded result of task, or compute() recorded."""
        key = kind + ":" + _hash(task)
        got = self.get(key)
        if got is None:
            text = json.dumps(compute())
            got = json.loads(text)  # as a reader of the store will see it
            self.put(kind, key, got, text)
        return got

    def run_tasks(self, fn: Callable[[Any], Any], items: Sequence[Any], executor: Any, progress: Progress,
                  what: str, deadline: Optional[float], stop: Optional[Callable[[], bool]] = None,
                  on_result: Optional[Callable[[int, Any], None]] = None) -> List[Any]:
        """parallel.run_tasks(fn, items, ...) with each result recorded as it
        is taken (in the order of items, while the others run: the workers
        never wait for a batch) and recorded results taken from the store.
        on_result(k, result): called for each result as it is at hand (those
        from the store first, in order; then as they are taken), never for
        a task not run.
        stop(): nothing more is started once it is true (those tasks give
        None); the tasks in flight complete and are recorded. A kill loses
        the tasks in flight (results are recorded as they complete, in any
        order). On a process pool up to POOL_CHUNK branches go in one task
        (parallel.chunks_for: the pool's cost per task shared; a kill loses
        those chunks). On Dask the tasks are streamed
        in chunks (parallel.stream_dask: at most DASK_WINDOW x width chunks of up
        to DASK_CHUNK tasks in flight, the client's cost per Dask task shared)."""
        kind = getattr(fn, "__name__", "task")
        keys = [kind + ":" + _hash(it) for it in items]
        out: List[Any] = [self.get(k) for k in keys]
        todo = [i for i, r in enumerate(out) if r is None]
        done = len(items) - len(todo)

        def record(j: int, res: Any) -> None:
            nonlocal done
            i = todo[j]
            if res is not None:
                text = json.dumps(res)  # once: the stored text, and the result as a reader sees it
                res = json.loads(text)
                self.put(kind, keys[i], res, text)
            out[i] = res
            done += 1
            tick(progress, done, len(items), what)
            if on_result is not None and res is not None:
                on_result(i, res)

        if on_result is not None:
            for i, res in enumerate(out):
                if res is not None:
                    on_result(i, res)
        if not todo or (stop is not None and stop()):
            return out
        if is_dask_client(executor):  # streamed in chunks: a kill loses at most the window in flight
            width = executor_width(executor)
            chunk = max(1, min(DASK_CHUNK, len(todo) // (DASK_WINDOW * 4 * width)))
            stream_dask(fn, [items[i] for i in todo], executor, record, DASK_WINDOW * width, deadline, stop, chunk)
            return out
        run_tasks(fn, [items[i] for i in todo], executor, None, what, deadline, on_result=record, stop=stop,
                  chunk=chunks_for(executor, len(todo)))
        return out
