"""Directed branches related by a symmetry of the node they leave.

A symmetry g of the structure that fixes a node (g.apply(node) = node) maps
every path out of it onto another: the branch along P_g d is the image under
g of the branch along d (P_g: g acting on the free coordinates), so its next
event is the same and its end is g applied to the other's end. explore()
follows one branch per orbit (follow_orbits, the default with symmetry) and
maps the others where the mapped end is certain (certain(): a closed loop,
a bifurcation located to the strict tolerance or a near miss located at its
minimum, onto a configuration with the same bar lengths), following the rest (follow_level); that divides the
following by up to the order of the node's stabilizer (6 at the hexagonal
sail's flat state, where the mirror z -> -z maps each branch onto its
opposite sense). differences() compares two atlases whatever the order of
their nodes and edges, up to the orbit mapping.

The branches are matched through a k-d tree of the unit directions
(branch_orbits) and the atlases' nodes through index.ConfigIndex, so n
branches cost O(n log n) rather than n^2 comparisons.
"""
from __future__ import annotations

from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple

import numpy as np
from numpy.typing import NDArray

from .index import ConfigIndex

# two unit directions are the same branch when they agree to this (max-norm);
# the complete solver's roots are certified far below it, and distinct
# branches are far apart
SAME_DIRECTION = 1e-6


def branch_orbits(directions: Sequence[NDArray[np.float64]], P: Sequence[NDArray[np.float64]]) -> List[Tuple[int, int]]:
    """For every directed branch k: (rep, j) with direction k = P[j] @
    direction rep, rep the smallest index of its orbit; (k, -1) for a
    representative. P: the stabilizer's matrices on the free coordinates
    (the identity may be among them).

    Each P[j]'s images of all directions are matched at once (a k-d tree
    of the directions, scipy.spatial.cKDTree, the nearest two within
    SAME_DIRECTION in the max-norm); where two lie within it, every
    direction within it is tried, lowest index first. 0.7 s against 1.35 s
    with one ConfigIndex query per representative and symmetry on the
    hexagonal flat state (59,656 directions, 6 symmetries)."""
    from scipy.spatial import cKDTree
    if not len(directions):
        return []
    D = np.array(directions, dtype=float)
    D /= np.linalg.norm(D, axis=1)[:, None]
    tree = cKDTree(D)
    near: List[List[Any]] = []  # per symmetry: per direction, the index of its image's match (-1: none, or a list)
    for Pj in P:
        img = D @ np.asarray(Pj, dtype=float).T
        dist, idx = tree.query(img, k=2, p=np.inf, distance_upper_bound=2 * SAME_DIRECTION)
        ok = dist[:, 0] <= SAME_DIRECTION
        row: List[Any] = np.where(ok, idx[:, 0], -1).tolist()
        for t in np.nonzero(ok & (dist[:, 1] <= SAME_DIRECTION))[0].tolist():
            row[t] = [i for i in sorted(tree.query_ball_point(img[t], 2 * SAME_DIRECTION, p=np.inf))
                      if np.abs(D[i] - img[t]).max() <= SAME_DIRECTION]
        near.append(row)
    out: List[Any] = [None] * len(D)
    for k in range(len(D)):
        if out[k] is not None:
            continue
        out[k] = (k, -1)
        for j, row in enumerate(near):
            for i in (row[k] if isinstance(row[k], list) else [row[k]]):
                if i >= 0 and out[i] is None:
                    out[i] = (k, j)
                    break
    return out


def mapped_result(res: Dict[str, Any], g: Any, end: Optional[NDArray[np.float64]] = None) -> Dict[str, Any]:
    """The follower's result of a branch mapped by the symmetry g: the same
    event, length and accuracies, the end and the samples moved by g (end:
    g applied to the result's end, where already made)."""
    out = dict(res)
    out["coords"] = (g.apply(np.asarray(res["coords"], dtype=float)) if end is None else end).tolist()
    out["samples"] = [g.apply(np.asarray(X, dtype=float)).tolist() for X in res.get("samples", [])]
    out["cpu_seconds"] = 0.0
    out["mapped"] = True
    return out


# the strict location tolerance of tasks.follow_branch (vr_tol's default):
# a bifurcation located to it is a certain end; one the follower could
# locate only to a relaxed tolerance is not
STRICT_VR_TOL = 1e-10
# a near miss ends at the minimum of v_r/v_max along the path, located to
# min_width (path length / RMS rest length; kin_follow_info, at most 1e-8):
# a certain end where that is below this, 10x under the explorer's
# identification tolerance (SAME_TOL, 1e-6 of the model size, which is
# larger than the RMS rest length): the image branch's minimum is then the
# mapped one to well within it
NEAR_MIN_WIDTH = 1e-7
# ... and where v_r/v_max there is at least this (the follower's vr_floor):
# a lower minimum is a bifurcation the locator could not pin, where the
# corrector fixes points only to about its tolerance / v_r across the path
# (on the hexagonal flat state, 7 of 1,500 near misses followed directly,
# all at v_r/v_max 1e-9 .. 5e-8, ended 1e-6 .. 1.2e-5 x the model size from
# their mapped ends; the others within 2e-8)
NEAR_MIN_VR = 1e-6
# a mapped end keeps every bar length to this (relative to the model's rest lengths)
LENGTH_TOL = 1e-9


def certain(res: Dict[str, Any], g: Any, bars: NDArray[np.int_]) -> bool:
    """Whether the image by g of a followed branch's result is what
    following the image branch gives, to the identification tolerance.

    The rule: the end is a closed loop (the path came back to the node,
    which g fixes), or a bifurcation located to the strict tolerance
    (STRICT_VR_TOL: located where v_r/v_max <= 1e-10, a point the follower
    pins down whichever way the steps fall); and g maps the end onto a
    configuration with the same bar lengths to LENGTH_TOL (g is an exact
    symmetry of the structure there, so the analysis there, m, s and v_r,
    is the same), or a near miss whose end is the minimum of v_r/v_max
    along the path located to NEAR_MIN_WIDTH (min_located: a geometric
    point, whichever way the steps fall) at v_r/v_max >= NEAR_MIN_VR. Not certain, and so followed: a
    near miss without a located minimum (it stops at the regular point
    before the dip, which depends on where the steps fall: mapped ends of
    those differed from followed ones by up to 0.008 on the hexagonal
    sail), a length or step budget (where the budget runs out depends on
    the steps too), a bifurcation located only to a relaxed tolerance
    (known to sqrt(tol) only), a failure."""
    if not _certain_event(res):
        return False
    X = np.asarray(res["coords"], dtype=float)
    return _same_lengths(_sorted_lengths(X, bars), g.apply(X), bars)


def _certain_event(res: Dict[str, Any]) -> bool:
    """certain()'s rule on the result alone (whatever the symmetry)."""
    ev = res.get("event")
    if ev == "near_miss":
        if not (res.get("min_located") and float(res.get("min_width", 1.0)) <= NEAR_MIN_WIDTH
                and float(res.get("accuracy", 0.0)) >= NEAR_MIN_VR):
            return False
    elif ev == "bifurcation":
        if not (float(res.get("vr_tol", 1.0)) <= STRICT_VR_TOL and float(res.get("accuracy", 1.0)) <= STRICT_VR_TOL):
            return False
    elif ev != "loop":
        return False
    return True


def _sorted_lengths(X: NDArray[np.float64], bars: NDArray[np.int_]) -> NDArray[np.float64]:
    return np.sort(np.linalg.norm(X[bars[:, 0]] - X[bars[:, 1]], axis=1))


def _same_lengths(L: NDArray[np.float64], Y: NDArray[np.float64], bars: NDArray[np.int_]) -> bool:
    """Y's bar lengths are L's (sorted) to LENGTH_TOL: g maps the end onto a configuration of
    the same structure."""
    M = _sorted_lengths(Y, bars)
    return bool(np.abs(L - M).max() <= LENGTH_TOL * max(1.0, float(L[-1]) if len(L) else 1.0))


def _map_certain(res: Dict[str, Any], g: Any, bars: NDArray[np.int_], memo: Dict[str, Any]) -> Optional[Dict[str, Any]]:
    """mapped_result(res, g) where certain(res, g, bars), else None; memo
    keeps what does not depend on g (the rule, the end, its sorted bar
    lengths) for the other images of the same result: the same answers,
    each image's end made once (the mapping of the hexagonal flat state's
    47,988 images cost 3.9 s of the client between the two passes)."""
    if "ok" not in memo:
        memo["ok"] = _certain_event(res)
        if memo["ok"]:
            memo["X"] = np.asarray(res["coords"], dtype=float)
            memo["L"] = _sorted_lengths(memo["X"], bars)
    if not memo["ok"]:
        return None
    Y = g.apply(memo["X"])
    return mapped_result(res, g, Y) if _same_lengths(memo["L"], Y, bars) else None


def follow_level(work: List[Any], images: List[Optional[Tuple[int, int]]],
                 follow: Callable[[List[Any], Callable[[int, Any], None]], List[Any]], syms: Sequence[Any],
                 bars: NDArray[np.int_],
                 take: Optional[Callable[[int, Any], None]] = None) -> Tuple[List[Any], int, int]:
    """The results of a level's directed branches: work[k] is followed when
    images[k] is None, else it is the image by syms[j] of work[rep] for
    images[k] = (rep, j) (rep < k), mapped where certain() and followed
    otherwise. follow(list of work, on_result) -> results (None: not
    followed, the time limit or a stop), calling on_result(index, result)
    as each is at hand. Returns (results, followed, mapped).

    The images of a followed branch are mapped as soon as its result comes
    in (the first pass); those not certain are followed in a second pass.
    take(k, result), if given, is called once for every k in the order of
    work, as soon as the results up to k are all at hand: the explorer
    identifies the ends while the workers follow the next branches, in the
    order a merge after the following would take (up to the first image
    not certain, which waits for the second pass), so the atlas does not
    depend on which branch completes first."""
    n = len(work)
    results: List[Any] = [None] * n
    known = [False] * n  # results[k] is final (a result, or None: not followed)
    todo = [k for k, im in enumerate(images) if im is None]
    of: Dict[int, List[Tuple[int, int]]] = {}  # a followed branch's images: (work index, symmetry)
    for k, im in enumerate(images):
        if im is not None:
            of.setdefault(im[0], []).append((k, im[1]))
    again: List[int] = []
    cursor, mapped = 0, 0

    def walk() -> None:  # take the results at hand, in order
        nonlocal cursor
        while cursor < n and known[cursor]:
            if take is not None:
                take(cursor, results[cursor])
            cursor += 1

    def feed(j: int, res: Any) -> None:  # a followed result: it and its certain images known
        nonlocal mapped
        k = todo[j]
        if known[k]:
            return
        results[k], known[k] = res, True
        memo: Dict[str, Any] = {}
        for i, g in of.get(k, []):
            got = None if res is None else _map_certain(res, syms[g], bars, memo)
            if got is not None:
                results[i], known[i] = got, True
                mapped += 1
            elif res is None:
                known[i] = True  # not followed either
            else:
                again.append(i)  # followed in the second pass
        walk()
    for j, res in enumerate(follow([work[k] for k in todo], feed)):
        feed(j, res)  # those not fed while following (not run, or decided at the end)
    again.sort()

    def feed2(j: int, res: Any) -> None:
        if not known[again[j]]:
            results[again[j]], known[again[j]] = res, True
            walk()
    for j, res in enumerate(follow([work[k] for k in again], feed2) if again else []):
        feed2(j, res)
    return results, len(todo) + len(again), mapped


def differences(a: Any, b: Any, tol: float = 1e-6, exclude: Optional[Callable[[Any], bool]] = None) -> List[str]:
    """How atlas b differs from atlas a, whatever the order of their nodes,
    solutions and edges (the symmetric solver returns the roots in another
    order): nodes matched by configuration (tol times the model size, or 10
    sqrt of the coarser location tolerance, as the explorer identifies
    them; up to a rigid motion where the supports allow one) with the same
    kind, m and s; the edges out of each orbit of nodes as the same
    multiset of (event, target, length within tol relative), the target's
    orbit standing for the target where the atlases expanded different
    nodes of the orbit: up to the orbit mapping. exclude(edge): edges of either atlas left out, and
    the nodes only they reach. [] when they are the same atlas."""
    out: List[str] = []
    scale = max(1.0, float(np.abs(a.nodes[0].coords - a.nodes[0].coords.mean(axis=0)).max())) if a.nodes else 1.0
    from ..symmetry.procrustes import aligned_distance
    rigid = bool(a.nodes) and a.nodes[0].m_rigid > 0  # up to the rigid motions the supports allow

    def dist(X: NDArray[np.float64], Y: NDArray[np.float64]) -> float:
        return aligned_distance(X, Y) if rigid else float(np.abs(X - Y).max())
    index = ConfigIndex(a.nodes[0].coords.shape if a.nodes else (1, 1), rigid=rigid)
    def kept(x: Any) -> Tuple[List[Any], List[Any]]:
        edges = [e for e in x.edges if exclude is None or not exclude(e)]
        reached = {0} | {e.source for e in edges} | {e.target for e in edges}
        return [n for n in x.nodes if n.id in reached], edges
    (a_nodes, a_edges), (b_nodes, b_edges) = kept(a), kept(b)
    for n in a_nodes:
        index.add(n.coords, n.id)
    worst = max([n.located_tol for n in a.nodes] + [0.0])
    match: Dict[int, int] = {}
    for n in b_nodes:
        for i in index.near(n.coords, scale * max(tol, 10 * np.sqrt(max(n.located_tol, worst)))):
            m = a.nodes[i]
            close = scale * max(tol, 10 * np.sqrt(max(n.located_tol, m.located_tol)))
            if dist(n.coords, m.coords) <= close:
                match[n.id] = i
                break
        if n.id not in match:
            out.append(f"node {n.id} ({n.kind}, m {n.m}, s {n.s}) is not in the other atlas")
        elif (a.nodes[match[n.id]].kind, a.nodes[match[n.id]].m, a.nodes[match[n.id]].s) != (n.kind, n.m, n.s):
            m = a.nodes[match[n.id]]
            out.append(f"node {n.id} is {n.kind} m {n.m} s {n.s}, there {m.kind} m {m.m} s {m.s}")
    if len(set(match.values())) != len(a_nodes) or len(a_nodes) != len(b_nodes):
        out.append(f"{len(a_nodes)} nodes against {len(b_nodes)} ({len(set(match.values()))} matched)")
    # the edges out of an orbit as the multiset of (event, target, length):
    # the same whatever the solution order (and the mechanism basis, which a
    # rigid motion of the node turns); the target's orbit stands for the
    # target where the two atlases expanded different nodes of an orbit
    # (the others are its images)
    def orbit(i: int) -> int:
        return a.nodes[i].orbit if 0 <= i < len(a.nodes) else -1
    sources = {(orbit(e.source), e.source) for e in a_edges}
    same = {o for o, src in sources} & {orbit(match.get(f.source, -1)) for f in b_edges
                                        if (orbit(match.get(f.source, -1)), match.get(f.source, -1)) in sources}
    mine: Dict[int, List[Tuple[str, int, float]]] = {}
    theirs: Dict[int, List[Tuple[str, int, float]]] = {}
    for e in a_edges:
        o = orbit(e.source)
        mine.setdefault(o, []).append((e.event, e.target if o in same else orbit(e.target), e.length))
    for f in b_edges:
        o, t = orbit(match.get(f.source, -1)), match.get(f.target, -1)
        theirs.setdefault(o, []).append((f.event, t if o in same else orbit(t), f.length))
    for src in sorted(set(mine) | set(theirs)):
        x, y = sorted(mine.get(src, [])), sorted(theirs.get(src, []))
        bad = len(x) != len(y) or any(p[:2] != q[:2] or abs(p[2] - q[2]) > tol * max(1.0, p[2]) for p, q in zip(x, y))
        if bad:
            out.append(f"the edges out of the orbit of node {src} differ: {len(x)} against {len(y)}, events "
                       f"{_count(x)} against {_count(y)}")
    if len(a_edges) != len(b_edges):
        out.append(f"{len(a_edges)} edges against {len(b_edges)}")
    return out


def _count(edges: List[Tuple[str, int, float]]) -> Dict[str, int]:
    out: Dict[str, int] = {}
    for ev, _, _ in edges:
        out[ev] = out.get(ev, 0) + 1
    return out
