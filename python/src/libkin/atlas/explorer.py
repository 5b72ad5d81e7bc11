"""The atlas: every path out of every bifurcation met, for any structure.

explore() starts from a configuration (a regular point or a bifurcation),
enumerates the directed branches there (both senses of the path at a regular
point; at a bifurcation the real solutions beta of the second-order
equations, from the complete solver or, in symmetric mode, from the system
restricted to the motions that keep the configuration's symmetry), follows
each to its next event (tasks.follow_branch: a located bifurcation, a
near-miss, a closed loop, the length budget, a failure), identifies end
points that are the same configuration (up to the rigid motions the supports
allow) or images of each other under the structure's symmetries
(libkin.symmetry.automorphisms), and recurses from the new bifurcations, level by level,
bounded by depth, node count, path length and time.

Determinism: the branches of a level are tasks whose results are merged
once all are in, in a canonical order (model.arrival_rank: a node's point is
its best-located end, merge_level), whatever order they complete or are
handed over in; node ids follow the order (node, solution index, sign) of
their first branch. So the atlas is the same serially, on a process pool or
on a Dask cluster (time_limit aside: a time-limited atlas is partial).
"""
from __future__ import annotations

import json
import math
import os
import sys
import time
from typing import TYPE_CHECKING, Any, Callable, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

if TYPE_CHECKING:
    from ..assembly import Assembly
    from ..symmetry.automorphisms import Symmetry

Branch = Tuple[int, int, NDArray[np.float64], NDArray[np.float64]]
Work = Tuple[int, int, int, NDArray[np.float64], NDArray[np.float64]]

from ..cliargs import as_assembly
from ..errors import InvalidArgumentError, KinError, LimitError
from ..parallel import Progress, chunks_for, run_tasks
from ..symmetry.automorphisms import same_symmetry, symmetries_at
from ..symmetry.procrustes import aligned_distance
from . import directions, levels, tasks
from .index import GroupedIndex
from .limits import MAX_NODES
from .merge import merge_level
from .model import BIFURCATION, SAME_TOL, UNDECIDED, Atlas, Edge, Node, node_kind, pair_window
from .orbits import branch_orbits, follow_level
from .solving import complete_solve, numbered, solve_system
from .stabiliser import fixing, mechanism_action, subspace_branches, useful_group

# symmetric="auto" uses the symmetric subspace when the complete solver would
# track more than 2^AUTO_MAX_S paths
AUTO_MAX_S = 12


class _Late(Exception):  # a node's complete solve abandoned: the time limit or a stop
    pass


def _say(progress: Progress, msg: str) -> None:
    if progress is True:
        print(f"[explore] {msg}", file=sys.stderr, flush=True)


class _Explorer:
    def __init__(self, a: Assembly, symmetric: Union[bool, str], executor: Any, progress: Progress,
                 max_length: float, seed: int, threads: int, symmetries: Optional[Sequence[Symmetry]],
                 max_steps: int, samples: int, shards: Optional[int], symmetry: bool, contact: bool,
                 view_samples: bool = True) -> None:
        from ..io.model_json import to_json
        self.a = a.clone()
        self.doc = to_json(a)
        self.text = json.dumps(self.doc)
        self.free_map = a.free_map()
        self.fixed = self.free_map < 0  # the supports' coordinates
        self.scale = max(1.0, float(np.abs(a.coords - a.coords.mean(axis=0)).max()))
        self.tol = SAME_TOL * self.scale
        self.symmetric, self.executor, self.progress = symmetric, executor, progress
        self.max_length, self.seed, self.threads = max_length, seed, threads
        self.max_steps, self.samples, self.shards = max_steps, samples, shards
        self.symmetry, self.contact, self.view_samples = symmetry, contact, view_samples
        self.deadline: Optional[float] = None
        self.symmetry_note = ""
        # detect the symmetries at every expanded node (the C search), unless given
        self.detect = symmetries is None
        if symmetries is not None:
            self.syms = list(symmetries)
        else:
            try:
                self.syms = symmetries_at(a, None, a.coords)
            except LimitError as exc:  # more graph automorphisms than the search enumerates
                self.detect, self.syms = False, []
                self.symmetry_note = f"not detected: {exc}"
                _say(progress, f"symmetries {self.symmetry_note}; exploring as if the structure had none")
        self.P = [g.free_matrix(self.free_map) for g in self.syms]
        self.bars = np.asarray(a.bars, dtype=int)
        self.nodes: List[Node] = []
        self.group_at: List[int] = []  # per node: the group's size when it was added (final_orbits)
        self.edges: List[Edge] = []
        self.rigid = a.analyse().m_rigid > 0
        # the nodes, and their images under each symmetry, by position
        self.index, self.images = GroupedIndex(a.coords.shape, self.rigid), GroupedIndex(a.coords.shape, self.rigid)
        self.follow_cpu, self.levels = 0.0, levels.Levels()  # followers' CPU seconds; per-level rows
        # branches followed, and mapped from a followed one by symmetry; returns decided again (directions.follow)
        self.followed, self.mapped, self.redo = 0, 0, {}  # type: Tuple[int, int, Dict[str, int]]
        self.store: Any = None  # store.Store: results recorded as they complete (reused on resume), and stop()
        self.stop: Optional[Callable[[], bool]] = None

    # -- identification
    def _distance(self, X: NDArray[np.float64], Y: NDArray[np.float64]) -> float:
        if self.rigid:  # up to the rigid motions the supports allow: align X onto Y
            return aligned_distance(X, Y)
        return float(np.abs(X - Y).max())

    def pair_tol(self, located_a: float, located_b: float) -> float:
        """How close two points must be to be one node: SAME_TOL times the
        model size plus the error bound of each (model.pair_window: a point
        located only to a coarse v_r <= tau v_max is known to about
        sqrt(tau), relative, of the true one)."""
        return pair_window(self.scale, located_a, located_b)

    def orbit_of(self, X: NDArray[np.float64], located: float = 0.0,
                 before: Optional[int] = None) -> Optional[Tuple[int, int]]:
        """(node id, symmetry index) with g.node = X, if X is an image of a
        node (of one with id < before, if given): the first such pair in
        the order (node, symmetry)."""
        for i, j in self.images.near(X, lambda worst: self.pair_tol(located, worst)):
            if before is not None and i >= before:
                break
            n = self.nodes[i]
            if self._distance(self.syms[j].apply(n.coords), X) <= self.pair_tol(located, n.located_tol):
                return n.id, j
        return None

    def _index_node(self, n: Node) -> None:
        self.index.add(n.coords, n.id, n.located_tol)
        for j, g in enumerate(self.syms):
            self.images.add(g.apply(n.coords), (n.id, j), n.located_tol)

    def add_node(self, X: ArrayLike, kind: str, an: Dict[str, Any], depth: int) -> int:
        i = len(self.nodes)
        n = Node(i, kind, np.asarray(X, dtype=float), an["m"], an["m_rigid"], an["s"], an["v_r_rel"], depth,
                 located_v_r=float(an.get("accuracy", 0.0)), located_tol=float(an.get("vr_tol", 0.0)), orbit=i)
        if kind == UNDECIDED:
            n.status = tasks.undecided_why(an)
        img = self.orbit_of(n.coords, n.located_tol) if len(self.syms) > 1 else None
        if img is not None:
            n.image_of = {"node": img[0], "symmetry": img[1]}
            n.orbit = self.nodes[img[0]].orbit
        self.nodes.append(n)
        self.group_at.append(len(self.syms))
        self._index_node(n)
        return i

    # -- enumeration at a node
    def learn_symmetries(self, node: Node) -> None:
        """Add the symmetries of the node's configuration to the group: each
        is a symmetry of the structure (symmetry/automorphisms.py), found at the
        configuration that has it."""
        grown = False
        for g in symmetries_at(self.a, None, node.coords) if self.detect else []:
            if not any(same_symmetry(g, h) for h in self.syms):
                self.syms.append(g)
                self.P.append(g.free_matrix(self.free_map))
                grown = True
        if grown:
            self.images.clear()
            for n in self.nodes:
                for j, g in enumerate(self.syms):
                    self.images.add(g.apply(n.coords), (n.id, j), n.located_tol)

    def final_orbits(self) -> None:
        """Orbits with the whole group found: node i joins the orbit of the
        first node j < i that a symmetry maps onto it (add_node's answer,
        where the group has not grown since)."""
        for n in self.nodes:
            if self.group_at[n.id] == len(self.syms):
                n.orbit = n.id if n.image_of is None else self.nodes[n.image_of["node"]].orbit
                continue
            n.orbit = n.id
            img = self.orbit_of(n.coords, n.located_tol, before=n.id)
            if img is not None:
                m, j = self.nodes[img[0]], img[1]
                n.orbit = m.orbit
                if n.image_of is None and not n.expanded:
                    n.image_of = {"node": m.id, "symmetry": j}

    def stabilizer(self, node: Node) -> List[int]:  # the symmetries (not the identity) that fix the node
        return fixing(self.syms, node.coords, self.pair_tol(node.located_tol, 0.0))

    def _assembly_at(self, node: Node) -> Assembly:
        a, o = self.a.clone(), self.a.options
        o.rank_tol = self._rank_tol(node)
        a.options, a.coords = o, node.coords
        return a

    def _rank_tol(self, node: Node) -> float:
        # a point located only to a coarser tolerance is analysed as the follower saw it
        return max(1e-9, 10.0 * node.located_tol) if node.kind == BIFURCATION else 1e-9

    def branches(self, node: Node) -> Tuple[List[Branch], Dict[str, Any]]:
        """[(solution index, sign, beta, direction)] at node, and a record."""
        a = self._assembly_at(node)
        an = a.analyse()
        U = an.internal_mechanisms
        # the self-stresses of bars between fixed joints constrain nothing
        # (Analysis.s_trivial): the second order has the others
        m, s = an.m_internal, an.s - an.s_trivial
        trivial = {"s_trivial": an.s_trivial} if an.s_trivial else {}
        if m == 0:
            return [], {"mode": "none", "reason": "no internal mechanism (rigid)"}
        if m == 1:
            return numbered(np.array([[1.0]]), U), {"mode": "regular", "solutions": 1}  # U's sign is the SVD's
        if s == 0:
            return [], {"mode": "none", "reason": f"m = {m} internal mechanisms and no self-stress: "
                                                  "a mechanism of several freedoms, not a bifurcation"}
        use_sym = self.symmetric is True or (self.symmetric == "auto" and s > AUTO_MAX_S)
        Q = a.second_order()
        tol = self.pair_tol(node.located_tol, 0.0)
        if use_sym:
            P = [self.P[j] for j in fixing(self.syms, node.coords, tol, proper_only=True)]
            betas_or_none, rec = subspace_branches(U, Q, P, self.solve_system)
            rec = {"m": m, "s": s, **trivial, **rec}
        else:
            R = mechanism_action(U, [self.P[j] for j in fixing(self.syms, node.coords, tol)]) \
                if self.symmetry else None
            R = R if useful_group(Q, R, self.seed) else None
            rec = {"m": m, "s": s, **trivial, "mode": "complete", **({} if R is None else {"solver_group": len(R)})}
            betas_or_none, more = self.solve_system(Q, m, R)
            rec.update(more)
        if betas_or_none is None:
            return [], rec
        return numbered(betas_or_none, U), rec

    def solve_system(self, Q: NDArray[np.float64], k: int,
                     group: Optional[NDArray[np.float64]] = None) -> Tuple[Optional[NDArray[np.float64]], Dict[str, Any]]:
        # the group acts on the system as given (s = k - 1), not on combinations of it
        return solve_system(Q, k, lambda Qx: self.solve(Qx, group if Qx is Q else None), self.seed)

    def solve(self, Q: NDArray[np.float64], group: Optional[NDArray[np.float64]] = None) -> Dict[str, Any]:
        """The complete solver on Q (s, m, m) (solving.complete_solve), with
        the stabiliser's group if given; _Late past the deadline or on stop."""
        def run() -> Dict[str, Any]:
            res = complete_solve(Q, self.executor, self.shards, self.seed, self.threads, group, self.deadline,
                                 self.stop)
            if res is None:
                raise _Late()
            return res
        key = [Q.tolist(), self.shards, self.seed, self.threads] + ([] if group is None else [group.tolist()])
        return run() if self.store is None else self.store.cached("solve", key, run)

    def follow_all(self, work: List[Work], every: Optional[List[Work]] = None,
                   on_result: Optional[Callable[[int, Any], None]] = None) -> List[Any]:
        """work: [(node, solution, sign, beta, direction)] -> results in order; every: all their nodes'
        branches; on_result(k, result) as each is at hand (directions.follow)."""
        def item(nid: int, d: NDArray[np.float64]) -> Dict[str, Any]:
            n, rest = self.nodes[nid], {"max_steps": self.max_steps, "samples": self.samples, "contact": self.contact}
            if not self.view_samples:  # (absent when True: the tasks, and so the store's keys, of the default)
                rest["view"] = False
            return {"model": self.text, "coords": n.coords, "rank_tol": self._rank_tol(n),
                    "direction": np.asarray(d, dtype=float), "max_length": self.max_length, **rest}

        def run(items: List[Any], on: Optional[Callable[[int, Any], None]] = None) -> List[Any]:
            args = (tasks.follow_branch, items, self.executor, self.progress, "branches", self.deadline)
            return self.store.run_tasks(*args, self.stop, on) if self.store is not None else \
                run_tasks(*args, on_result=on, chunk=chunks_for(self.executor, len(items)))
        return directions.follow(work, every if every is not None else work, item, run, self.redo, self.executor,
                                 on_result)


def explore(model: Union[Assembly, str, os.PathLike[str], Dict[str, Any]], start: Optional[ArrayLike] = None,
            depth: int = 1, max_nodes: int = MAX_NODES, max_length: Optional[float] = None,
            time_limit: Optional[float] = None, symmetric: Union[bool, str] = False, executor: Any = None,
            progress: Progress = None, seed: int = 1, threads: int = 1,
            symmetries: Optional[Sequence[Symmetry]] = None, max_steps: int = 2000, samples: int = 2,
            shards: Optional[int] = None, follow_orbits: Optional[bool] = None, store: Any = None,
            resume: bool = False, stop: Optional[Callable[[], bool]] = None, symmetry: bool = True,
            contact: bool = False, view_samples: bool = True) -> Atlas:
    """Map the paths out of `start` and out of every bifurcation they reach.

    Parameters
    ----------
    model : Assembly, str, path or dict
        An Assembly, a JSON model (file path, text or dict) or a spec ("sail:4:1", "threebar:RC").
    start : array_like (njoints, dim), optional
        The start configuration, a regular point or a bifurcation (default:
        the model's current one).
    depth : int
        Levels of bifurcations to expand (1: only the start's branches).
    max_nodes : int
        No node is expanded once the atlas has this many (default
        limits.MAX_NODES, 1,000,000: the depth bounds the run).
    max_length : float, optional
        Path-length budget of one branch (default: 10 times the model size, the
        largest distance of a joint from the centroid, at least 1).
    time_limit : float, optional
        Seconds; after it nothing more is started, the branches not yet
        started are cancelled, a node's complete solve in progress is
        abandoned (in this process at once; on an executor when its shards
        in flight return), the branches being followed complete; the atlas
        so far is returned, stats "partial" and "stopped_by": "time_limit"
        (the store keeps what was done: resume completes it).
    symmetric : bool or "auto"
        False: the complete solver at every bifurcation. True: only the
        branches that keep the node's symmetry (the proper rotations among
        the structure's symmetries that fix the node). "auto": symmetric
        where s > 12.
    executor : None, concurrent.futures.Executor or dask.distributed.Client
        Where the branches (and the complete solver's shards) run; None: here.
    progress : None, bool or callable
        True: messages on stderr; a callable gets (done, total, what).
    seed : int
        Seed of the complete solver (and of an overdetermined system's combinations).
    threads : int
        Threads of each complete-solver task.
    symmetries : sequence of automorphisms.Symmetry, optional
        The group to use; default: detected (at the start and at every
        expanded node).
    max_steps : int
        Step budget of one branch.
    samples : int
        Configurations kept along each branch from its one follow: this many
        evenly spread, and (view_samples) more where the viewer's curve would
        strain a bar by over 1 % (atlas/frames.py, docs/atlas.md); 0: none.
    shards : int, optional
        The complete solver's paths are tracked in this many tasks (default:
        about SHARD_PATHS paths a shard with an executor, one task without).
    follow_orbits : bool, optional
        False: every directed branch is followed. True: one branch per orbit
        of the node's stabilizer is followed, the others are its images
        where the image is certain (orbits.certain) and followed otherwise:
        the same atlas, up to |stabilizer| times less work. Default: symmetry.
    symmetry : bool
        True (default): symmetries save work without changing the atlas: the
        complete solve with the node's stabiliser (stabiliser.py, s >= 8) and
        follow_orbits. False: neither. Detected either way, for the nodes'
        orbits (symmetries=[]: none).
    store, resume : path or store.Store, bool
        Record each solve and branch there as it completes; resume: reuse an
        earlier run's (same model and settings: the same atlas) (store.py).
    stop : callable, optional
        Once true nothing more is started: the atlas so far (stats partial).
    contact, view_samples : bool
        Stop at the first contact of two parts; the viewer's samples (samples).

    Returns
    -------
    Atlas
        Nodes, directed edges, the symmetries found, settings and stats.

    Raises
    ------
    InvalidArgumentError
        An argument out of range (symmetric, depth, a budget, start's shape).
    """
    t0 = time.perf_counter()
    a = as_assembly(model)
    if start is not None:
        a = a.clone()
        a.coords = np.asarray(start, dtype=float)
    if not isinstance(symmetry, bool):
        raise InvalidArgumentError(f"symmetry: expected True or False, got {symmetry!r}")
    follow_orbits = symmetry if follow_orbits is None else follow_orbits
    if not isinstance(follow_orbits, bool):
        raise InvalidArgumentError(f"follow_orbits: expected True, False or None, got {follow_orbits!r}")
    if symmetric not in (False, True, "auto"):
        raise InvalidArgumentError(f"symmetric: expected False, True or 'auto', got {symmetric!r}")
    if not isinstance(depth, int) or depth < 0:
        raise InvalidArgumentError(f"depth: expected an integer >= 0, got {depth!r}")
    for name, v, least in (("max_nodes", max_nodes, 1), ("max_steps", max_steps, 1), ("samples", samples, 0),
                           ("threads", threads, 1), ("shards", 1 if shards is None else shards, 1)):
        if not isinstance(v, int) or v < least:
            raise InvalidArgumentError(f"{name}: expected an integer >= {least}, got {v!r}")
    for name, x in (("max_length", max_length), ("time_limit", time_limit)):
        if x is not None and not (isinstance(x, (int, float)) and math.isfinite(x) and x >= 0
                                  and (x > 0 or name == "time_limit")):
            raise InvalidArgumentError(f"{name}: expected a finite number > 0, got {x!r}")
    scale = max(1.0, float(np.abs(a.coords - a.coords.mean(axis=0)).max()))
    if max_length is None:
        max_length = 10.0 * scale
    ex = _Explorer(a, symmetric, executor, progress, float(max_length), seed, threads, symmetries, int(max_steps),
                   int(samples), shards, symmetry, bool(contact), bool(view_samples))
    ex.deadline = None if time_limit is None else t0 + float(time_limit)
    from .store import open_store
    # the settings that shape the results (not time_limit, nor depth: a deeper run resumes a shallower one's),
    # and the rules that decide them
    ex.store, ex.stop = open_store(store, resume, ex.text, [max_nodes, float(max_length), symmetric,
                                   seed, threads, symmetries is None and len(ex.syms), max_steps, samples, shards,
                                   follow_orbits, symmetry] + ([True] if contact else [])
                                   + [{"rules": tasks.RESULT_RULES}]), stop
    an = a.analyse()
    rec0 = {"m": an.m_internal, "m_rigid": an.m_rigid, "s": an.s,
            "v_r_rel": float(an.v_r / an.v_max) if an.v_max > 0 else 0.0}
    kind0 = node_kind(tasks.BUDGET, rec0)
    ex.add_node(a.coords, kind0, rec0, 0)
    _say(progress, f"start: {kind0}, m = {an.m_internal}, s = {an.s}; {len(ex.syms)} symmetries")
    frontier = [0]
    stopped = None

    def halted() -> Optional[str]:  # why nothing more is started, if so
        if time_limit is not None and time.perf_counter() - t0 > time_limit:
            return "time_limit"
        return "interrupted" if stop is not None and stop() else None
    causes = {"time_limit": "time limit reached", "interrupted": "interrupted"}
    for level in range(depth):
        ex.levels.begin(level, frontier)
        work: List[Work] = []
        images: List[Optional[Tuple[int, int]]] = []  # per work item: None (followed) or (work index, symmetry)
        for nid in frontier:
            node = ex.nodes[nid]
            if node.image_of is not None:
                node.status = f"not expanded: the image of N{node.image_of['node']} by symmetry {node.image_of['symmetry']}"
                continue
            if len(ex.nodes) >= max_nodes:
                node.status = "not expanded: max_nodes reached"
                stopped = stopped or "max_nodes"
                continue
            cause = halted()
            if cause:
                node.status = f"not expanded: {causes[cause]}"
                stopped = stopped or cause
                continue
            ex.learn_symmetries(node)
            try:
                br, rec = ex.branches(node)
            except _Late:
                cause = halted() or "interrupted"
                node.status = f"not expanded: {causes[cause]} during its solve"
                stopped = stopped or cause
                continue
            except KinError as exc:
                node.status = f"branches not enumerated: {type(exc).__name__}: {exc}"
                continue
            node.branches = rec
            node.expanded = True
            node.status = rec.get("reason", f"{len(br)} directed branches")
            if follow_orbits and br:
                stab = ex.stabilizer(node)
                orbits = branch_orbits([d for _, _, _, d in br], [ex.P[j] for j in stab])
                images += [None if j < 0 else (len(work) + rep, stab[j]) for rep, j in orbits]
            else:
                images += [None] * len(br)
            work += [(nid, i, sg, b, d) for i, sg, b, d in br]
        todo = [k for k, im in enumerate(images) if im is None]
        _say(progress, f"level {level + 1}: {len(work)} directed branches from {len(frontier)} node(s)"
             + (f", {len(todo)} followed, the others their images by symmetry" if len(todo) < len(work) else ""))
        n_before, missed = len(ex.nodes), []  # type: int, List[int]

        got: Dict[int, Any] = {}  # the level's results as they come (any order: merge_level sorts them)

        def take(k: int, res: Any) -> None:
            if res is None:  # not followed: the time limit ran out first, or the run was interrupted
                missed.append(work[k][0])
            else:
                got[k] = res
        ex.levels.follow(ex, lambda: follow_level(work, images, lambda w, on: ex.follow_all(w, work, on), ex.syms,
                                                  ex.bars, take))
        merge_level(ex, work, got, level + 1)
        for nid in missed:
            cause = "interrupted" if stop is not None and stop() else "time_limit"
            if "not followed" not in ex.nodes[nid].status:
                ex.nodes[nid].status += f"; some branches not followed: {causes[cause]}"
            stopped = stopped or cause
        ex.levels.end(ex.nodes, n_before)
        frontier = [n.id for n in ex.nodes[n_before:] if n.kind == BIFURCATION]
        if not frontier:
            break
    ex.final_orbits()
    arrived: Dict[int, set[str]] = {}
    for e in ex.edges:
        arrived.setdefault(e.target, set()).add(e.event)
    why = {tasks.BUDGET: "the path-length budget ran out here", tasks.CONTACT: "two parts touch here", tasks.NEAR_MISS:
           "the follower stopped at a dip of v_r here", tasks.FAILURE: "following failed here", tasks.BIFURCATION:
           "located as a bifurcation, but regular at the rank tolerance"}
    for n in (n for n in ex.nodes if not n.expanded and not n.status):
        n.status = ("not expanded: depth reached" if n.kind == BIFURCATION else tasks.UNDECIDED_WHY
                    if n.kind == UNDECIDED else "; ".join(why[ev] for ev in sorted(arrived.get(n.id, ())) if ev in why) or "end point")
    settings = {"depth": depth, "max_nodes": max_nodes, "max_length": float(max_length), "time_limit": time_limit,
                "symmetric": symmetric, "seed": seed, "same_tol": ex.tol, "max_steps": int(max_steps),
                "samples": int(samples), "view_samples": bool(view_samples), "symmetries": ex.symmetry_note or f"{len(ex.syms)} detected",
                "follow_orbits": follow_orbits, "symmetry": symmetry, "contact": bool(contact),
                "executor": None if executor is None else type(executor).__name__}
    stats = {"seconds": round(time.perf_counter() - t0, 3), "follow_cpu_seconds": round(ex.follow_cpu, 3),
             "branches_followed": ex.followed, "branches_mapped": ex.mapped,
             "returns_decided_again": ex.redo, "stopped_by": stopped,
             "partial": stopped in ("interrupted", "time_limit"), "levels": ex.levels.rows,
             "identity_undecided": ex.levels.identity_undecided()}
    if ex.store is not None:
        stats["store"] = ex.store.finish(store is not ex.store)
    atlas = Atlas(ex.doc, ex.nodes, ex.edges, ex.syms, settings, stats)
    stats.update(atlas.summary())
    return atlas

