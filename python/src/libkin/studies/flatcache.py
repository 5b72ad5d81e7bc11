"""The flat state's complete solve, kept between runs of a study.

The 2^s homotopy at the sail's flat state is the study's longest step and
depends only on the model and the solver's settings. flat_solve() keeps its
result (the roots and the accounting, the seconds it took included) in
`.NAME.flat-solve.json` next to the output folder NAME, keyed by a hash of
the model, the second-order system, the symmetry group, the solver's
settings and the library's version; a rerun with the same key takes it
from there instead of solving again (and reports the same numbers). A file
of another key, or one that does not parse, is replaced.
"""
import hashlib
import json
import os
import pathlib
import time
from typing import Any, Dict, Optional, Tuple, Union

import numpy as np

from libkin.version import __version__
from libkin.assembly import solve_quadrics
from libkin.atomic import write_text

SEED = 1  # the complete solver's (homotopy start system)


def cache_path(out: Union[str, "os.PathLike[str]"]) -> pathlib.Path:
    """The cache file of the output folder out (next to it, outside it)."""
    p = pathlib.Path(out).resolve()
    return p.parent / f".{p.name}.flat-solve.json"


def _key(a: Any, Q: Any, group: Any) -> str:
    h = hashlib.sha256()
    solver = {"solver": "homotopy", "seed": SEED, "prove": 2}  # the C default (Arb and FLINT only)
    h.update(json.dumps({"model": a.to_json(), "solver": solver, "version": __version__},
                        sort_keys=True, default=str).encode())
    for arr in (Q, group):
        arr = np.ascontiguousarray(np.asarray(arr, dtype=float))
        h.update(repr(arr.shape).encode())
        h.update(arr.tobytes())
    return h.hexdigest()


def flat_solve(a: Any, group: Any, threads: int, progress: Any,
               out: Optional[Union[str, "os.PathLike[str]"]]) -> Tuple[np.ndarray, Dict[str, Any], bool]:
    """(betas, accounting, cached) of the complete solver on a's
    second-order system with the symmetry group; from the cache next to out
    if it holds this system's (out None: no cache)."""
    Q = a.second_order()
    key = _key(a, Q, group)
    path = None if out is None else cache_path(out)
    if path is not None and path.exists():
        try:
            rec = json.loads(path.read_text())
            if rec.get("key") == key:
                return np.asarray(rec["betas"], dtype=float), dict(rec["accounting"]), True
        except (OSError, ValueError, KeyError, TypeError):
            pass  # unreadable: solved again and replaced
    t0 = time.perf_counter()
    betas, acc = solve_quadrics(Q, "homotopy", seed=SEED, threads=threads, progress=progress, group=group)
    acc_out: Dict[str, Any] = {k: (int(v) if isinstance(v, (int, np.integer)) else v) for k, v in acc.items()}
    acc_out["seconds"] = round(time.perf_counter() - t0, 1)
    if path is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
        write_text(path, json.dumps({"key": key, "betas": np.asarray(betas).tolist(), "accounting": acc_out}) + "\n")
    return np.asarray(betas, dtype=float), acc_out, False
