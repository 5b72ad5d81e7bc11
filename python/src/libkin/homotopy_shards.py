"""The complete solver in shards: the 2^s homotopy paths tracked as
independent tasks on any executor, merged into exactly the result of one
call (kin_quadrics_homotopy_range + kin_quadrics_homotopy_merge, kin_branch.h).

A shard is a task of plain data: Q (as a list), the seed and its range of
paths in; the endpoint records out as bytes (the records are a documented
ABI, KIN_HOMOTOPY_ENDPOINT_SIZE bytes each) and the endpoint coordinates as
bytes of float64. The merge (duplicate and conjugate checks, re-tracking of
the paths concerned, accounting) runs in the calling process.
"""
from __future__ import annotations

from typing import Any, Dict, List, Optional, Tuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .errors import InvalidArgumentError, StateError, check

ACCOUNTING = ("paths", "real", "real_distinct", "nonreal", "singular", "failed", "duplicates", "unpaired",
              "retracked")


def _options(seed: int, threads: int) -> Any:
    from ._lib import lib, new_struct
    opt = new_struct("kin_homotopy_options")
    lib.kin_homotopy_options_default(opt)
    opt.seed = int(seed)
    opt.nthreads = int(threads)
    return opt


def _system(Q: ArrayLike) -> Tuple[NDArray[np.float64], int, int]:
    Q = np.ascontiguousarray(np.asarray(Q, dtype=np.float64))
    if Q.ndim != 3 or Q.shape[1] != Q.shape[2]:
        raise InvalidArgumentError(f"Q: expected shape (s, m, m), got {Q.shape}")
    s, m = Q.shape[0], Q.shape[1]
    if m != s + 1:
        raise StateError(f"the solvers need m = s + 1; here m = {m}, s = {s}")
    return Q, m, s


def range_task(task: Dict[str, Any]) -> Dict[str, Any]:
    """Track paths task["first"] .. task["first"] + task["count"] - 1 of the
    complete solver for task["Q"] (s, m, m) with task["seed"]. Returns
    {"first", "count", "ends": bytes, "z": bytes}."""
    from ._arrays import read_ptr, write_ptr
    from ._lib import ffi, lib
    Q, m, s = _system(task["Q"])
    first, count = int(task["first"]), int(task["count"])
    ends = ffi.new("kin_homotopy_endpoint[]", count)
    ends[0].size = ffi.sizeof("kin_homotopy_endpoint")  # KIN_HOMOTOPY_ENDPOINT_SIZE
    z = np.empty(2 * m * count)
    rc = lib.kin_quadrics_homotopy_range(m, s, read_ptr(Q, "double *"), _options(task.get("seed", 1),
                                         task.get("threads", 1)), first, count, ends, write_ptr(z, "double *"))
    check(rc, what="homotopy range")
    return {"first": first, "count": count, "ends": bytes(ffi.buffer(ends)), "z": z.tobytes()}


def shard_ranges(s: int, shards: int) -> List[Tuple[int, int]]:
    """[(first, count)] splitting the 2^s paths into `shards` nearly equal ranges."""
    n = 1 << s
    shards = max(1, min(int(shards), n))
    cuts = [n * k // shards for k in range(shards + 1)]
    return [(cuts[k], cuts[k + 1] - cuts[k]) for k in range(shards)]


def solve_sharded(Q: ArrayLike, executor: Optional[Any] = None, shards: int = 4, seed: int = 1,
                  threads: int = 1) -> Tuple[NDArray[np.float64], Dict[str, int]]:
    """Real solutions beta (nsol, m) of beta^T Q_j beta = 0 and the
    accounting, as solve_quadrics(Q, "homotopy", seed=seed) gives them, with
    the paths tracked in `shards` tasks on executor (None: here, one after
    the other; a concurrent.futures.Executor or a dask.distributed.Client)."""
    from ._arrays import read_ptr, write_ptr
    from ._lib import ffi, lib, new_struct
    from .atlas import run_tasks
    Q, m, s = _system(Q)
    items = [{"Q": Q.tolist(), "seed": seed, "threads": threads, "first": f, "count": c}
             for f, c in shard_ranges(s, shards)]
    parts = run_tasks(range_task, items, executor)
    n = 1 << s
    rec = ffi.sizeof("kin_homotopy_endpoint")
    ends = ffi.new("kin_homotopy_endpoint[]", n)
    buf = ffi.buffer(ends)
    z = np.empty(2 * m * n)
    for p in sorted(parts, key=lambda p: p["first"]):
        buf[p["first"] * rec:(p["first"] + p["count"]) * rec] = p["ends"]
        z[2 * m * p["first"]:2 * m * (p["first"] + p["count"])] = np.frombuffer(p["z"], dtype=np.float64)
    maxsol = 1 << min(s, 16)
    betas = np.empty((maxsol, m))
    nsol = ffi.new("int *")
    info = new_struct("kin_homotopy_info")
    rc = lib.kin_quadrics_homotopy_merge(m, s, read_ptr(Q, "double *"), _options(seed, threads), ends,
                                         read_ptr(z, "double *"), write_ptr(betas, "double *"), maxsol, nsol,
                                         ffi.NULL, info)
    check(rc, what="homotopy merge")
    return betas[: nsol[0]].copy(), {k: int(getattr(info, k)) for k in ACCOUNTING}


def available() -> bool:
    """True if the library has the sharded solver."""
    from ._lib import lib
    try:
        lib.kin_quadrics_homotopy_range
        lib.kin_quadrics_homotopy_merge
    except AttributeError:
        return False
    return True
