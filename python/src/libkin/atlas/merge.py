"""The merge of one level of libkin.explore: its branch ends identified as
nodes, in an order that does not depend on the order the results came in
(issue 35, docs/atlas.md "Identification").

explore() hands merge_level all of a level's results at once (work index ->
result, in the order they arrived); the ends are sorted by their rank
(model.arrival_rank: the node kind they give, the located accuracy, the
tolerance, the coordinates), so each new node's point is its best-located
end, and two ends are one node within model.pair_window (SAME_TOL plus the
error bound of each). Node ids follow the work order of each node's first
branch, the edges the work order. How clearly each end's node was decided
(identity.Judge: a factor IDENTITY_MARGIN of room on each side of the
window, else "undecided" with the numbers) goes into the level's row.
"""
from __future__ import annotations

import math
from typing import Any, Dict, List, Tuple

import numpy as np
from numpy.typing import NDArray

from . import tasks
from .identity import Judge, ratios
from .index import GroupedIndex
from .model import Edge, arrival_rank, node_kind

# an end further than this (times the model size) from its node's
# coordinates (identified up to a rigid motion, or coarsely located) is
# kept with its edge (Edge.end): the viewer draws the path to where it went
END_SAME = 1e-4


def merge_level(ex: Any, work: List[Any], got: Dict[int, Any], depth: int) -> None:
    """Identify the ends of one level's branches (got: work index ->
    result, in any order: the order results arrived in) and add the
    level's edges, in work order. The result depends only on the set
    of results (docs/atlas.md "Identification"):

    - the ends are taken in a canonical order (model.arrival_rank: the
      node kind they give, bifurcation first, then the located
      accuracy, then the coordinates), each joining the first earlier
      node within pair_tol of it (in id order: the nodes of the earlier
      levels, whose points are final), else the first of this level's
      new nodes within it (in that order), else starting a new one; so
      every new node's point, kind and analysis are those of its
      best-ranked end, whichever arrived first;
    - the new nodes get their ids in the order of their first branch
      in work order (node, solution, sign), as before;
    - a located bifurcation at an earlier node first reached as a near
      miss and not expanded makes it a bifurcation (Node.arrived), the
      best-ranked such end's analysis.
    A node's point is final once its level is merged: later levels only
    add edges to it (its branches were followed from that point)."""
    target: Dict[int, Any] = {}
    ends = []
    for k, res in got.items():
        ex.follow_cpu += float(res.get("cpu_seconds", 0.0))
        if res["event"] == tasks.LOOP:
            target[k] = work[k][0]
            continue
        kind = node_kind(res["event"], res)
        ends.append((arrival_rank(kind, res), k, kind))
    ends.sort(key=lambda e: (e[0], e[1]))
    fresh = GroupedIndex(ex.a.coords.shape, ex.rigid)  # this level's new nodes, by rank
    lead: List[Tuple[int, str, NDArray[np.float64], float]] = []  # per new node: (k, kind, point, located)
    judge = Judge()
    for _, k, kind in ends:
        res = got[k]
        X, located = np.asarray(res["coords"], dtype=float), float(res.get("vr_tol", 0.0))
        # the nodes within IDENTITY_MARGIN windows: the first (in id order)
        # within one window is the node, the rest judge the margin
        old = ratios(ex, X, located, ex.nodes, ex.index)
        new = ratios(ex, X, located, [(p, tol) for _, _, p, tol in lead], fresh)
        found = next((i for r, i in old if r <= 1.0), None)
        c = None if found is not None else next((c for r, c in new if r <= 1.0), None)
        join = next((r for r, i in old if i == found), next((r for r, i in new if i == c), math.nan))
        judge.judge(ex, k, located, found if found is not None else None if c is None else -1, join,
                    [(r, i) for r, i in old if i != found] + [(r, None) for r, i in new if i != c])
        if found is not None:
            target[k] = ex.nodes[found].arrived(kind, res)
            continue
        if c is None:
            c = len(lead)
            lead.append((k, kind, X, located))
            fresh.add(X, c, located)
        target[k] = ("new", c)
    first: Dict[int, int] = {}
    for k in sorted(got):
        t = target[k]
        if isinstance(t, tuple):
            first.setdefault(t[1], k)
    ids: Dict[int, int] = {}
    for c in sorted(first, key=first.__getitem__):  # new nodes in the order of their first branch
        k, kind, X, _ = lead[c]
        X = X.copy()  # a mapped end (g applied) has its supports' coordinates to rounding only
        X[ex.fixed] = ex.a.coords[ex.fixed]
        ids[c] = ex.add_node(X, kind, got[k], depth)
        judge.judge_image(ex, ex.nodes[ids[c]])
    if ex.levels.rows:
        ex.levels.rows[-1]["identity"] = judge.row()
    for k in sorted(got):
        nid, sol, sign, _beta, direction = work[k][:5]
        res, t = got[k], target[k]
        t = ids[t[1]] if isinstance(t, tuple) else t
        X = np.asarray(res["coords"], dtype=float)
        own = np.abs(X - ex.nodes[t].coords).max() <= END_SAME * ex.scale
        ex.edges.append(Edge(len(ex.edges), nid, t, int(sol), int(sign), [float(v) for v in direction],
                               res["event"], float(res["length"]), float(res["accuracy"]), res["samples"],
                               res["message"], int(res.get("steps", 0)), float(res.get("vr_tol", 0.0)),
                               None if own else X.tolist()))
