"""The second-order systems at a node: the complete solver, in shards on the
executor when there are enough paths for it (libkin.homotopy) or as one task,
and systems with more equations than the solvers take (solve_system).
"""
from __future__ import annotations

from typing import Any, Callable, Dict, List, Optional, Tuple

import numpy as np
from numpy.typing import NDArray

from ..assembly._canonical import canonical
from ..homotopy import shards as homotopy_shards
from ..parallel import run_tasks
from . import tasks

# with an executor, the complete solver is split into shards of about this
# many homotopy paths (at most 64 shards)
SHARD_PATHS = 256
# a system of at most this many homotopy paths (2^s) is solved here, not
# sent to the executor: it takes a millisecond or less, a task's round trip
# to a Dask cluster 10-100 ms of the client's time (most nodes past depth one
# of the hexagonal sail have s = 1 to 3; docs/atlas.md, "Depth two and beyond")
LOCAL_PATHS = 64
# an overdetermined system's candidate solves every equation to this
# (relative residual |beta^T Q_j beta| / |Q_j|_F, unit beta)
OVERDETERMINED_TOL = 1e-8


def numbered(betas: NDArray[np.float64], U: NDArray[np.float64]) -> List[Tuple[int, int, NDArray[np.float64],
                                                                               NDArray[np.float64]]]:
    """A node's directed branches [(solution index, sign, beta, sign U beta)]
    from its solutions betas (n, m) in U's coordinates: numbered and signed
    by the physical directions U beta (assembly._canonical), not by the
    basis U that the SVD returned nor the solver's order, so the atlas is
    the same with any BLAS kernel or thread count (docs/branches.md)."""
    return [(i, sg, b, sg * (U @ b)) for i, b in enumerate(canonical(betas, U)) for sg in (1, -1)]


def solve_system(Q: NDArray[np.float64], k: int, solve: Callable[[NDArray[np.float64]], Dict[str, Any]],
                 seed: int = 1) -> Tuple[Optional[NDArray[np.float64]], Dict[str, Any]]:
    """Unit solutions (n, k) of beta^T Q_j beta = 0 for the s independent
    Q_j (s, k, k), and a record. s = k - 1: the complete solver. s > k - 1
    (more equations than the solvers take): the complete solver on k - 1
    random combinations of them (seeded: deterministic), whose solutions
    include every common one, keeping those that solve all equations.
    solve(Q) runs the complete solver ({"betas", "accounting"}).
    s < k - 1: the solutions form a continuum; none are returned."""
    s = Q.shape[0]
    if s < k - 1:
        return None, {"solutions": 0, "reason": f"{s} independent second-order equation(s) in {k} unknowns: "
                                               "the solutions form a continuum, not isolated branches"}
    if s == k - 1:
        res = solve(Q)
        betas = np.asarray(res["betas"]).reshape(-1, k)
        return betas, {"solutions": len(betas), "accounting": res["accounting"]}
    rng = np.random.default_rng(seed)
    A, _ = np.linalg.qr(rng.standard_normal((s, k - 1)))
    Qc = np.einsum("ja,jxy->axy", A, Q)
    res = solve(Qc)
    cand = np.asarray(res["betas"]).reshape(-1, k)
    norms = np.linalg.norm(Q.reshape(s, -1), axis=1)
    resid = (np.abs(np.einsum("nx,jxy,ny->nj", cand, Q, cand)) / norms).max(axis=1) if len(cand) else cand[:, 0]
    betas = cand[resid <= OVERDETERMINED_TOL]
    rec = {"solutions": len(betas), "accounting": res["accounting"],
           "combined": f"{k - 1} random combinations of {s} equations", "candidates": len(cand)}
    if not len(betas):
        rec["reason"] = f"none of the {len(cand)} candidate(s) solves all {s} second-order equations"
    return betas, rec


def complete_solve(Q: NDArray[np.float64], executor: Any, shards: Optional[int], seed: int,
                   threads: int, group: Optional[NDArray[np.float64]] = None,
                   deadline: Optional[float] = None,
                   stop: Optional[Callable[[], bool]] = None) -> Optional[Dict[str, Any]]:
    """The complete solver on Q (s, m, m): in shards on the executor when
    there are enough paths for it (homotopy_shards), else as one task, or
    here for at most LOCAL_PATHS paths (the same solver, the same roots).
    group (k, m, m): the symmetric solver with that group (stabiliser.py).
    deadline (time.perf_counter()) and stop(): past the one or once the
    other is true, the solve is abandoned (None): in this process within
    about 0.1 s (the solver's cancel), on an executor when the shards in
    flight return."""
    import time
    s = Q.shape[0]
    if shards is None:
        shards = 1 if executor is None else max(1, min(64, (1 << s) // SHARD_PATHS))

    def late() -> bool:
        return (deadline is not None and time.perf_counter() > deadline) or (stop is not None and stop())
    if late():
        return None
    if shards > 1 and homotopy_shards.available():
        solved = homotopy_shards.solve_sharded(Q, executor, shards, seed, threads, group=group, deadline=deadline)
        if solved is None:
            return None
        return {"betas": solved[0].tolist(), "accounting": dict(solved[1], shards=int(shards))}
    task = {"Q": Q.tolist(), "seed": seed, "threads": threads}
    if executor is None or (1 << s) <= LOCAL_PATHS:  # here: cancelled through the progress callback
        from ..assembly import solve_quadrics
        from ..errors import CancelledError
        try:
            betas, acc = solve_quadrics(Q, "homotopy", seed=seed, threads=threads, group=group,
                                        progress=lambda done, total: late())
        except CancelledError:
            return None
        return {"betas": betas.tolist(), "accounting": {k: int(v) for k, v in acc.items()}}
    if group is not None:
        return run_tasks(homotopy_shards.symmetric_task, [dict(task, group=np.asarray(group).tolist())], executor,
                         deadline=deadline)[0]
    return run_tasks(tasks.solve_task, [task], executor, deadline=deadline)[0]
