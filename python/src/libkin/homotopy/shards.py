"""The complete solver in shards: the 2^s homotopy paths tracked as
independent tasks on any executor, merged into exactly the result of one
call (kin_quadrics_homotopy_range + kin_quadrics_homotopy_merge, kin_branch.h).

A shard is a task of plain data: Q (as a list), the seed and its range of
paths in; the endpoint records out as bytes (the records are a documented
ABI, KIN_HOMOTOPY_ENDPOINT_SIZE bytes each) and the endpoint coordinates as
bytes of float64, with the fingerprint of the system and seed they were
tracked for. The merge (duplicate and conjugate checks, re-tracking of
the paths concerned, accounting) runs in the calling process, after every
shard's fingerprint is checked (a shard of another job is refused, named);
the C merge then checks every certified record against Q itself
(kin_quadrics_homotopy_merge).
"""
from __future__ import annotations

import hashlib
from typing import Any, Dict, List, Optional, Tuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InvalidArgumentError, StateError, check
from ..assembly._canonical import canonical

ACCOUNTING = ("paths", "real", "real_distinct", "nonreal", "singular", "failed", "duplicates", "unpaired",
              "retracked", "proven_real", "proven_nonreal", "unproven", "proven_all", "proven_refined",
              "proven_overlap", "unproven_nopoint", "unproven_refused")


def _options(seed: int, threads: int) -> Any:
    from .._native._lib import default_struct
    opt = default_struct("kin_homotopy_options")
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


def fingerprint(Q: ArrayLike, seed: int) -> str:
    """What a shard's records belong to: the system Q (its float64 bytes and
    shape) and the seed, hashed (SHA-256). solve_sharded refuses a shard
    whose records carry another, naming it, before any merge."""
    Q = np.ascontiguousarray(np.asarray(Q, dtype=np.float64))
    h = hashlib.sha256(repr((Q.shape, int(seed))).encode())
    h.update(Q.tobytes())
    return h.hexdigest()


def _check_parts(parts: List[Dict[str, Any]], items: List[Dict[str, Any]], expected: str) -> None:
    """Every part must answer its own item and carry the system's fingerprint."""
    for k, (p, it) in enumerate(zip(parts, items)):
        what = f"shard {k} of {len(items)} (first {it['first']}, count {it['count']})"
        if not isinstance(p, dict) or p.get("system") != expected:
            err = StateError(f"{what} was tracked for another system or seed: refused")
            err.shard = k  # type: ignore[attr-defined]
            raise err
        if p.get("first", it["first"]) != it["first"]:
            err = StateError(f"{what} answered another range (first {p.get('first')}): refused")
            err.shard = k  # type: ignore[attr-defined]
            raise err


def range_task(task: Dict[str, Any]) -> Dict[str, Any]:
    """Track paths task["first"] .. task["first"] + task["count"] - 1 of the
    complete solver for task["Q"] (s, m, m) with task["seed"]. Returns
    {"first", "count", "ends": bytes, "z": bytes}."""
    from .._native._arrays import read_ptr, write_ptr
    from .._native._lib import ffi, lib
    Q, m, s = _system(task["Q"])
    first, count = int(task["first"]), int(task["count"])
    ends = ffi.new("kin_homotopy_endpoint[]", count)
    ends[0].size = ffi.sizeof("kin_homotopy_endpoint")  # KIN_HOMOTOPY_ENDPOINT_SIZE
    z = np.empty(2 * m * count)
    rc = lib.kin_quadrics_homotopy_range(m, s, read_ptr(Q, "double *"), _options(task.get("seed", 1),
                                         task.get("threads", 1)), first, count, ends, write_ptr(z, "double *"))
    check(rc, what="homotopy range")
    return {"first": first, "count": count, "ends": bytes(ffi.buffer(ends)), "z": z.tobytes(),
            "system": fingerprint(Q, task.get("seed", 1))}


def _split(n: int, shards: int) -> List[Tuple[int, int]]:
    """[(first, count)] splitting 0 .. n - 1 into `shards` nearly equal ranges."""
    shards = max(1, min(int(shards), n))
    cuts = [n * k // shards for k in range(shards + 1)]
    return [(cuts[k], cuts[k + 1] - cuts[k]) for k in range(shards)]


def shard_ranges(s: int, shards: int) -> List[Tuple[int, int]]:
    """[(first, count)] splitting the 2^s paths into `shards` nearly equal ranges."""
    return _split(1 << s, shards)


def orbit_task(task: Dict[str, Any]) -> Dict[str, Any]:
    """Track the representatives of orbits task["first"] ..
    task["first"] + task["count"] - 1 of the equivariant form task["Qt"]
    (s, m, m), task["perm"] (kin_quadrics_homotopy_orbit_range) with
    task["seed"], task["order"] the group's order. Returns {"count": records,
    "ends": bytes, "z": bytes} for every member of those orbits (each
    record says its path)."""
    from .._native._arrays import read_ptr, write_ptr
    from .._native._lib import ffi, lib
    Qt, m, s = _system(task["Qt"])
    perm = np.ascontiguousarray(np.asarray(task["perm"], dtype=np.intc))
    first, count = int(task["first"]), int(task["count"])
    room = count * int(task["order"])
    ends = ffi.new("kin_homotopy_endpoint[]", room)
    ends[0].size = ffi.sizeof("kin_homotopy_endpoint")
    z = np.empty(2 * m * room)
    got = ffi.new("long *")
    rc = lib.kin_quadrics_homotopy_orbit_range(m, s, read_ptr(Qt, "double *"), read_ptr(perm, "int *"),
                                               _options(task.get("seed", 1), task.get("threads", 1)), first, count,
                                               room, ends, write_ptr(z, "double *"), got)
    check(rc, what="homotopy orbit range")
    n = int(got[0])
    rec = ffi.sizeof("kin_homotopy_endpoint")
    return {"count": n, "ends": bytes(ffi.buffer(ends, n * rec)), "z": z[: 2 * m * n].tobytes(),
            "system": fingerprint(Qt, task.get("seed", 1))}


def equivariant_form(Q: ArrayLike, group: ArrayLike,
                     seed: int = 1) -> Optional[Tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.intc],
                                                      int, int]]:
    """(Qt, U, perm, order, norbits) of kin_quadrics_equivariant_form: the
    system in coordinates x with beta = U x where a cyclic subgroup of
    `group` (k, m, m) permutes coordinates and equations alike; None if no
    subgroup qualifies."""
    from .._native._arrays import read_ptr, write_ptr
    from .._native._lib import ffi, lib
    Q, m, s = _system(Q)
    R = np.asarray(group, dtype=np.float64)
    if R.ndim != 3 or R.shape[1:] != (m, m):
        raise InvalidArgumentError(f"group: expected shape (k, {m}, {m}), got {R.shape}")
    Rc = np.ascontiguousarray(R.transpose(0, 2, 1))  # column-major matrices
    Qt = np.empty((s, m, m))
    U = np.empty((m, m))
    perm = np.empty(m, dtype=np.intc)
    order, norbits = ffi.new("int *"), ffi.new("long *")
    err = ffi.new("char[]", 256)
    rc = lib.kin_quadrics_equivariant_form(m, s, read_ptr(Q, "double *"), R.shape[0], read_ptr(Rc, "double *"),
                                           int(seed), write_ptr(Qt, "double *"), write_ptr(U, "double *"),
                                           write_ptr(perm, "int *"), order, norbits, err, 256)
    check(rc, what="equivariant form: " + ffi.string(err).decode(errors="replace"))
    if order[0] == 0:
        return None
    # Qt holds column-major matrices of the symmetric Q_j (the same read
    # either way); U is column-major
    return Qt, U.T.copy(), perm, int(order[0]), int(norbits[0])


def _merge(Qm: NDArray[np.float64], m: int, s: int, seed: int, threads: int, ends: Any,
           z: NDArray[np.float64], proven_on: Optional[Tuple[NDArray[np.float64], NDArray[np.float64]]] = None
           ) -> Tuple[NDArray[np.float64], Dict[str, int]]:
    """The merge on Qm; proven_on (Q, U column-major): the equivariant
    form's merge, its proofs about the caller's Q at beta = U x"""
    from .._native._arrays import read_ptr, write_ptr
    from .._native._lib import ffi, lib, new_struct
    maxsol = 1 << s  # every real solution (pages not written are never touched)
    betas = np.empty((maxsol, m))
    nsol = ffi.new("int *")
    info = new_struct("kin_homotopy_info")
    if proven_on is None:
        rc = lib.kin_quadrics_homotopy_merge(m, s, read_ptr(Qm, "double *"), _options(seed, threads), ends,
                                             read_ptr(z, "double *"), write_ptr(betas, "double *"), maxsol, nsol,
                                             ffi.NULL, info)
    else:
        Q, Uc = proven_on
        rc = lib.kin_quadrics_homotopy_merge_equivariant(
            m, s, read_ptr(Q, "double *"), read_ptr(Qm, "double *"), read_ptr(Uc, "double *"),
            _options(seed, threads), ends, read_ptr(z, "double *"), write_ptr(betas, "double *"), maxsol, nsol,
            ffi.NULL, info)
    check(rc, what="homotopy merge")
    return betas[: nsol[0]].copy(), {k: int(getattr(info, k)) for k in ACCOUNTING}


def solve_sharded(Q: ArrayLike, executor: Optional[Any] = None, shards: int = 4, seed: int = 1,
                  threads: int = 1, group: Optional[ArrayLike] = None,
                  deadline: Optional[float] = None) -> Any:
    """Real solutions beta (nsol, m) of beta^T Q_j beta = 0 and the
    accounting, as solve_quadrics(Q, "homotopy", seed=seed) gives them, with
    the paths tracked in `shards` tasks on executor (None: here, one after
    the other; a concurrent.futures.Executor or a dask.distributed.Client).

    group (k, m, m), optional: a symmetry group of the system (as for
    solve_quadrics). Where a cyclic subgroup permutes the mechanisms and the
    equations alike, the tasks track one path per orbit of start roots in
    the equivariant form (kin_quadrics_equivariant_form,
    kin_quadrics_homotopy_orbit_range), the merge runs on the form and the
    solutions come back as beta = U x; the accounting gains 'order' and
    'orbits'. Otherwise every path, as without a group.

    deadline (a time.perf_counter() value), optional: shards not started by
    then are cancelled (parallel.run_tasks) and the solve is abandoned:
    None. Without a deadline the result is always (betas, accounting)."""
    from .._native._lib import ffi
    from ..parallel import run_tasks
    Q, m, s = _system(Q)
    n = 1 << s
    rec = ffi.sizeof("kin_homotopy_endpoint")
    ends = ffi.new("kin_homotopy_endpoint[]", n)
    buf = ffi.buffer(ends)
    z = np.empty(2 * m * n)
    form = equivariant_form(Q, group, seed) if group is not None else None
    if form is None:
        items = [{"Q": Q.tolist(), "seed": seed, "threads": threads, "first": f, "count": c}
                 for f, c in shard_ranges(s, shards)]
        parts = run_tasks(range_task, items, executor, deadline=deadline)
        if any(p is None for p in parts):
            return None
        _check_parts(parts, items, fingerprint(Q, seed))
        for p in sorted(parts, key=lambda p: p["first"]):
            buf[p["first"] * rec:(p["first"] + p["count"]) * rec] = p["ends"]
            z[2 * m * p["first"]:2 * m * (p["first"] + p["count"])] = np.frombuffer(p["z"], dtype=np.float64)
        betas, acc = _merge(Q, m, s, seed, threads, ends, z)
        return canonical(betas), acc  # solve_quadrics's order and signs
    Qt, U, perm, order, norbits = form
    items = [{"Qt": Qt.tolist(), "perm": perm.tolist(), "order": order, "seed": seed, "threads": threads,
              "first": f, "count": c} for f, c in _split(norbits, shards)]
    parts = run_tasks(orbit_task, items, executor, deadline=deadline)
    if any(p is None for p in parts):
        return None
    _check_parts(parts, items, fingerprint(Qt, seed))
    # the records of scattered paths, each to its place (a record's path is
    # an int at a documented offset)
    off = ffi.offsetof("kin_homotopy_endpoint", "path")
    table = np.zeros((n, rec), dtype=np.uint8)
    zt = z.reshape(n, 2 * m)
    count = np.zeros(n, dtype=np.int64)
    for p in parts:
        raw = np.frombuffer(p["ends"], dtype=np.uint8).reshape(p["count"], rec)
        paths = raw[:, off:off + 4].copy().view(np.intc).ravel()
        if paths.size and (paths.min() < 0 or paths.max() >= n):
            raise StateError("orbit ranges: a record's path is out of range")
        np.add.at(count, paths, 1)
        table[paths] = raw
        zt[paths] = np.frombuffer(p["z"], dtype=np.float64).reshape(p["count"], 2 * m)
    if not (count == 1).all():
        raise StateError(f"orbit ranges: {int((count == 0).sum())} paths missing, "
                         f"{int((count > 1).sum())} reported twice")
    buf[:] = table.tobytes()
    # the proofs about Q itself at beta = U x, as the one-call symmetric solver's
    x, acc = _merge(Qt, m, s, seed, threads, ends, z, proven_on=(Q, np.ascontiguousarray(U.T)))
    betas = x @ U.T  # beta = U x, row by row
    betas /= np.linalg.norm(betas, axis=1, keepdims=True)
    acc.update({"order": order, "orbits": norbits})
    return canonical(betas), acc  # solve_quadrics's order and signs


def symmetric_task(task: Dict[str, Any]) -> Dict[str, Any]:
    """The symmetric complete solver on one system, as one task (plain data
    in and out): {"Q", "group", "seed", "threads"} -> {"betas",
    "accounting"} (solve_quadrics(Q, group=group))."""
    from ..assembly import solve_quadrics
    betas, acc = solve_quadrics(np.asarray(task["Q"], dtype=float), "homotopy", seed=int(task.get("seed", 1)),
                                threads=int(task.get("threads", 1)), group=np.asarray(task["group"], dtype=float))
    return {"betas": betas.tolist(), "accounting": {k: int(v) for k, v in acc.items()}}


def available() -> bool:
    """True if the library has the sharded solver."""
    from .._native._lib import lib
    try:
        lib.kin_quadrics_homotopy_range
        lib.kin_quadrics_homotopy_merge
    except AttributeError:
        return False
    return True
