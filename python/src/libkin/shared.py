"""Large read-only arrays given to a run's workers once, on any executor.

A task that needs a large array (the hexagonal sail's flat state: 29,828
branch lines x 46 numbers, 11 MB, for each of 59,656 branch tasks) carries
a Ref to it instead: Sharing(executor).share(array) gives the Ref, and
resolve(ref) in the task gives the array, read once per process (an LRU of
RESOLVED arrays by content). How the array travels depends on the executor:

- none (serial) or a thread pool: the Ref holds the array itself;
- a process pool (parallel.ProcessPool, concurrent.futures'
  ProcessPoolExecutor): a file written whole (libkin.atomic) in a folder of
  this run (removed at close) and np.load(mmap_mode="r") in the worker;
- a dask.distributed.Client: client.scatter(array, broadcast=True); at
  submission parallel.run_tasks / stream_dask put Ref.dask_arg() in place of
  each Ref of a task dict ({"shared": digest, "data": future}: Dask gives the
  worker the array in place of the future).

A Ref is identified by its content (shape and SHA-256 of its bytes, never
the file path nor the future's key), so a task that carries one hashes the
same in every run (the store's keys, resume: atlas/store.py). share()
returns None for an executor it cannot reach (another kind): the caller then
sends the data some other way. Of libkin it imports libkin.atomic and
libkin.parallel.
"""
from __future__ import annotations

import collections
import concurrent.futures
import hashlib
import io
import os
import shutil
import tempfile
import threading
from typing import Any, Callable, Dict, Optional, Tuple

import numpy as np

from . import atomic

__all__ = ["Ref", "Sharing", "resolve", "content", "RESOLVED"]

#: arrays kept per process by resolve() (the least recently used dropped)
RESOLVED = 4


class Ref:
    """A shared read-only float64 array: its digest, its shape, and where
    a worker finds it (the array, a file path, or a Dask future)."""

    __slots__ = ("digest", "shape", "where")

    def __init__(self, digest: str, shape: Tuple[int, ...], where: Any) -> None:
        self.digest, self.shape, self.where = digest, tuple(int(n) for n in shape), where

    def __reduce__(self) -> Any:
        return Ref, (self.digest, self.shape, self.where)

    def dask_arg(self) -> Any:
        """What a Dask task takes in its place (parallel.run_tasks and
        stream_dask put it there): {"shared": digest, "shape", "data":
        future}, whose future Dask resolves in the worker to the array."""
        if isinstance(self.where, (str, np.ndarray)):
            return self
        return {**content(self), "data": self.where}

    def __repr__(self) -> str:
        return f"Ref({self.digest[:12]}, shape={self.shape})"


def content(ref: Ref) -> Dict[str, Any]:
    """What identifies a Ref (for hashing a task): its shape and digest."""
    return {"shared": ref.digest, "shape": list(ref.shape)}


def _digest(a: np.ndarray) -> str:
    return hashlib.sha256(repr(a.shape).encode() + a.tobytes()).hexdigest()


def _kind(executor: Any) -> Optional[str]:
    from .parallel import ProcessPool, is_dask_client
    if executor is None or isinstance(executor, concurrent.futures.ThreadPoolExecutor):
        return "object"
    if isinstance(executor, (ProcessPool, concurrent.futures.ProcessPoolExecutor)):
        return "file"
    if is_dask_client(executor):
        return "dask"
    return None


class Sharing:
    """The arrays shared with one executor's workers for a while (a
    context manager): at close the files are removed and the Dask futures
    released (the workers that resolved them keep their copies)."""

    def __init__(self, executor: Any, folder: Optional[str] = None) -> None:
        self.executor, self.kind = executor, _kind(executor)
        self._parent, self._folder = folder, None  # type: Optional[str], Optional[str]
        self._refs: Dict[str, Ref] = {}

    def share(self, array: Any) -> Optional[Ref]:
        """A Ref to a read-only float64 copy of array (the same Ref for the
        same content), or None where this executor cannot be reached."""
        if self.kind is None:
            return None
        a = np.ascontiguousarray(array, dtype=np.float64)
        d = _digest(a)
        if d in self._refs:
            return self._refs[d]
        if self.kind == "object":
            a = a.copy() if a is array else a
            a.setflags(write=False)
            where: Any = a
        elif self.kind == "file":
            if self._folder is None:
                try:
                    self._folder = tempfile.mkdtemp(prefix="libkin-shared-", dir=self._parent)
                except OSError:
                    return None
            where = os.path.join(self._folder, d + ".npy")
            buf = io.BytesIO()
            np.save(buf, a, allow_pickle=False)
            try:
                atomic.write_bytes(where, buf.getvalue())
            except OSError:  # a full disk, a folder not writable: not shared
                return None
        else:
            where = self.executor.scatter(a, broadcast=True, hash=False)
        ref = self._refs[d] = Ref(d, a.shape, where)
        return ref

    def close(self) -> None:
        if self.kind == "dask" and self._refs:
            for r in self._refs.values():
                try:
                    r.where.release()
                except Exception:  # the client already closed: nothing to release
                    pass
        self._refs.clear()
        if self._folder is not None:
            shutil.rmtree(self._folder, ignore_errors=True)
            self._folder = None

    def __enter__(self) -> "Sharing":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()


_cache: "collections.OrderedDict[Any, Any]" = collections.OrderedDict()
_lock = threading.Lock()


def resolve(ref: Any, build: Optional[Callable[[np.ndarray], Any]] = None) -> Any:
    """The array of a Ref (or of Ref.dask_arg()), read-only, or build(it)
    if given: made once per process (the last RESOLVED kept), later calls
    with the same content (and build) give the same object."""
    if isinstance(ref, Ref):
        digest, where = ref.digest, ref.where
    else:
        digest, where = ref["shared"], ref["data"]
    key = (digest, build)
    with _lock:
        got = _cache.get(key)
        if got is not None:
            _cache.move_to_end(key)
            return got
    if isinstance(where, str):
        a = np.load(where, mmap_mode="r", allow_pickle=False)
    else:
        a = np.asarray(where, dtype=np.float64)
        if a.flags.writeable:
            a = a.view()
            a.setflags(write=False)
    got = a if build is None else build(a)
    with _lock:
        _cache[key] = got
        while len(_cache) > RESOLVED:
            _cache.popitem(last=False)
    return got
