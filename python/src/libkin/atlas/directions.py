"""A bifurcation's branch directions for its follow tasks, at any size.

The follower decides what a return to the start is against the start's
real branch directions (kin_follow_event_ex, docs/follow.md "Branch
directions"): a closed loop only when the direction it comes back along,
t, is nearest the branch's own line by at least the margin (0.05 rad):
angle(t, k) >= angle(t, own) + margin for every other line k; otherwise
following goes on and the start is located as a bifurcation. A node's
directions go whole with each of its tasks where they are few
(tasks.BRANCH_DIRECTIONS_MAX numbers). Where they are many (the hexagonal
sail's flat state: 29,828 x 46 numbers, 11 MB, for each of 59,656 tasks)
follow() gives them to the workers ONCE (libkin.shared: the array itself
serially or on threads, a file mapped by each worker of a process pool, a
Dask broadcast), and each task carries a reference to them (named by their
content: the store's keys are the same in every run) and the index of its
own line. In the worker the lines are checked once (BranchLines) and the
follower asks them for the nearest line at each return
(kin_follow_options.return_fn): every return is decided as with all lines,
in the one follow. Passing the array itself to C in every task cost 16.2
ms a task against 7.2 with the own line alone (C checks every number and
searches the own line in each call); shared, 8.5 (bench/bench_returns.py):
the lines cost only at returns (0.8 ms each, 0.5 a task).

Where the executor cannot be given the lines (another kind of executor, a
folder not writable) the old passes remain, with subsets S of the lines
(the own line always among them, in their order) such that the follower
decides exactly as with all:

* The follower uses the directions only in that decision, so up to the
  first return its path is the same with any S; and at a return a loop
  with all of them is a loop with S (own still nearest, the next nearest
  no nearer). So a task that ends in anything but a loop with S decided
  every return as all directions would: its result is theirs.
* A task that ends in a loop with S, at b = angle(t, own), is certain when
  every line outside S is at least 2 b + margin from dir: the angle between
  lines is a metric, so such a line k has angle(t, k) >= angle(dir, k) -
  angle(dir, t) >= b + margin.

The passes: first S = {own} (a return ends the task as a loop where the
follower's Newton root from its arrival direction is the own line; a root on
another line, not in S, is undecided there and with all lines it is that
line: not a loop either way). A loop not
certain is followed again with the lines within RETURN_RADIUS of the
path's direction at its end (the task's "return_tangent", near t): a
return along another branch finds that branch among them and goes on, as
with all lines. A loop still not certain is followed again with every line
within 2 b + margin of dir, until certain (at worst with all of them). The
subsets go as NumPy arrays (the store hashes them by content). Following
the returns twice cost the full atlas of the flat state 835 s of CPU (187 s
of first-pass tasks stopped at a return, 210 s the 11,196 tasks again);
with the lines shared, 600 s and the same atlas (docs/atlas.md).
"""
from __future__ import annotations

from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple

import numpy as np
from numpy.typing import NDArray

from ..shared import Sharing
from . import tasks

# added to the certificate's bound: the rounding of the angles (theirs in C,
# these by arccos, accurate to 1e-15 rad above the margin)
SLACK = 1e-9
# a return to the start is decided again first with the lines within this
# angle (radians) of its direction at the end (an estimate: a task that
# still ends in a loop is decided again around its own line)
RETURN_RADIUS = 0.15


def branch_margin() -> float:
    """The follower's default branch_margin (kin_follow_options), radians."""
    from .._native._lib import default_struct
    return float(default_struct("kin_follow_options").branch_margin)


class _Lines:
    """A node's branch lines (sign +1 directions, unit rows) and their angles to a direction."""

    def __init__(self, lines: List[NDArray[np.float64]]) -> None:
        self.raw = np.array(lines, dtype=float)
        self.unit = self.raw / np.linalg.norm(self.raw, axis=1)[:, None]

    def near(self, t: NDArray[np.float64], radius: float) -> NDArray[np.bool_]:
        """Which lines are within radius (radians) of the line of t."""
        return np.abs(self.unit @ (t / np.linalg.norm(t))) > np.cos(radius)

    def angles(self, own: int) -> NDArray[np.float64]:
        c = np.abs(self.unit @ self.unit[own])
        a = np.arccos(np.minimum(c, 1.0))
        a[own] = 0.0
        return a


def node_lines(every: Sequence[Any]) -> Tuple[Dict[int, List[Any]], Dict[Tuple[int, int], int]]:
    """Per node of work [(node, solution, sign, beta, direction)] with at
    least two solutions: its branch directions (sign +1, in work order), and
    for each (node, solution) the index of its line among them."""
    lines: Dict[int, List[Any]] = {}
    index: Dict[Tuple[int, int], int] = {}
    for nid, sol, sg, _, d in every:
        if sg == 1:
            index[(nid, sol)] = len(lines.setdefault(nid, []))
            lines[nid].append(d)
    return {nid: L for nid, L in lines.items() if len(L) >= 2}, index


def follow(work: Sequence[Any], every: Sequence[Any], item: Callable[[int, Any], Dict[str, Any]],
           run: Callable[..., List[Any]], record: Optional[Dict[str, int]] = None,
           executor: Any = None, on_result: Optional[Callable[[int, Any], None]] = None) -> List[Any]:
    """The results of work's branches [(node, solution, sign, beta,
    direction)], each decided against all of its node's branch directions
    (from every: the level's work). item(node, direction) -> the task
    without "branches"; run(tasks[, on_result]) -> results (None: not run); executor:
    where run runs them (the many directions shared with its workers).
    record, if given, gains the counts of the tasks run again ("tasks"), the
    lines they carried ("lines", "lines_max") and their CPU seconds ("cpu_ms").
    on_result(k, result), if given: called for each final result as it
    is at hand (any order, never for a task not run); run(tasks, on_result)
    passes it on where no result can be decided again (every line reaches
    its tasks), else it is called once all are final."""
    lines, index = node_lines(every)
    limit = tasks.BRANCH_DIRECTIONS_MAX
    # as arrays, not nested lists: Dask walks a task's nested lists element by element
    # looking for futures (its client spent 30 ms a depth-1 task on them) and the store
    # JSON-encoded them for the task's key (9 ms); an array is one object to both
    whole = {nid: np.array(L, dtype=float) for nid, L in lines.items() if len(L) * len(L[0]) <= limit}
    with Sharing(executor) as sharing:
        many = {nid for nid, *_ in work if nid in lines and nid not in whole}
        refs = {nid: sharing.share(np.array(lines[nid], dtype=float)) for nid in sorted(many)}
        items = []
        for nid, sol, _, _, d in work:
            it = item(nid, d)
            if refs.get(nid) is not None:  # every line, the same array for all the node's tasks
                it["branches"], it["own"] = refs[nid], index[(nid, sol)]
            else:
                it["branches"] = whole[nid] if nid in whole else (np.array([d], dtype=float) if nid in lines else None)
            items.append(it)
        final = all(refs[nid] is not None for nid in refs)  # no loop is decided again
        results = run(items, on_result) if final and on_result is not None else run(items)
    big: Dict[int, _Lines] = {}
    reach: Dict[int, float] = {}  # per task: every line outside its last subset is at least this far from dir
    margin = branch_margin()
    pending = [k for k, res in enumerate(results) if res is not None and res["event"] == tasks.LOOP
               and work[k][0] in many and refs[work[k][0]] is None]
    while True:
        again: List[int] = []
        subsets: List[NDArray[np.float64]] = []
        for k in pending:
            res = results[k]
            if res is None or res["event"] != tasks.LOOP:
                continue  # not run (time limit), or not a loop: decided as with all lines
            nid, sol = work[k][0], work[k][1]
            L = big.get(nid) or big.setdefault(nid, _Lines(lines[nid]))
            own = index[(nid, sol)]
            angles = L.angles(own)
            first = k not in reach
            if first:
                reach[k] = float(np.delete(angles, own).min())  # S = {own}
            b = float(res.get("return_angle", float("inf")))
            if 2.0 * b + margin + SLACK <= reach[k]:
                continue  # certain: what all directions give
            t = res.get("return_tangent")
            if first and t is not None:
                # most returns come back along another branch: the lines near the return
                # direction (and the own one) make the follower go on as with all of them
                inside = L.near(np.asarray(t, dtype=float), RETURN_RADIUS)
                inside[own] = True
            else:
                inside = angles < 2.0 * b + margin + 2.0 * SLACK
            outside = angles[~inside]
            reach[k] = float(outside.min()) if outside.size else float("inf")
            again.append(k)
            subsets.append(L.raw[inside])
        if not again:
            if on_result is not None and not final:
                for k, res in enumerate(results):
                    if res is not None:
                        on_result(k, res)
            return results
        redo = []
        for k, S in zip(again, subsets):
            it = dict(items[k])
            it["branches"] = S
            redo.append(it)
        pending = again
        for k, S, res in zip(again, subsets, run(redo)):
            results[k] = res
            if record is not None:
                n = len(S)
                cpu = round(1e3 * (res or {}).get("cpu_seconds", 0.0))
                for key, v in (("tasks", 1), ("lines", n), ("cpu_ms", cpu)):
                    record[key] = record.get(key, 0) + v
                record["lines_max"] = max(record.get("lines_max", 0), n)

