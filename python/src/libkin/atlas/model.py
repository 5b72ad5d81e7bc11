"""The atlas's data: its nodes, directed edges and the Atlas that holds them
(written and read back as JSON, GraphML through networkx), the node kinds
and the tolerances that make two configurations one node.
"""
from __future__ import annotations

import dataclasses
import json
import math
import os
import re
from typing import TYPE_CHECKING, Any, Dict, List, Optional, Tuple, Union

import numpy as np
from numpy.typing import NDArray

from ..atomic import replacing, write_text
from . import tasks

if TYPE_CHECKING:
    from ..symmetry.automorphisms import Symmetry

# node kinds: what a node of the map is
BIFURCATION = "bifurcation"  # m_internal >= 2 and s >= 1 (branches can be enumerated)
REGULAR = "regular"          # on a single path (m_internal = 1): the start, or a budget end
NEAR_MISS = "near_miss"      # a v_r dip the follower stopped at, but regular here
MULTI_DOF = "multi_dof"      # m_internal >= 2 with s = 0: a mechanism of several freedoms
RIGID = "rigid"              # m_internal = 0
FAILURE = "failure"          # where following failed
UNDECIDED = "undecided"      # a minimum of v_r neither at the strict tolerance nor clearly above
                             # the floor a crossing would leave there (tasks.NEAR_MARGIN), or a corank-1
                             # point whose branches may be tangent (tasks.crossing_verdict): not expanded
NODE_KINDS = (BIFURCATION, REGULAR, NEAR_MISS, MULTI_DOF, RIGID, FAILURE, UNDECIDED)

# two configurations are one node when they agree to this times the model size
SAME_TOL = 1e-6
# a point located to v_r <= tau v_max is known to within LOCATION_FACTOR
# sqrt(tau) times the model size (its error bound, location_error); two
# points are one node within SAME_TOL plus both error bounds (pair_window)
LOCATION_FACTOR = 10.0


def location_error(located: float) -> float:
    """The error bound of a point located to v_r <= located v_max, relative
    to the model size: at a tangency v_r ~ |l - l*|^2, so such a point is
    within about sqrt(located) of the true one (times LOCATION_FACTOR: the
    arrivals at the hexagonal sail's m = 4, s = 3 nodes located to 1e-7 lie
    up to 9.7 sqrt(1e-7) x the model size from the best-located arrival at
    1e-8, docs/atlas.md "Identification"). 0 for a point not located (a
    near miss, a budget end, the start: known to the follower's rounding)."""
    return LOCATION_FACTOR * math.sqrt(max(located, 0.0))


def pair_window(scale: float, located_a: float, located_b: float) -> float:
    """How close two points located to located_a and located_b (their
    vr_tol) must be to be one node: scale x (SAME_TOL + the error bound of
    each), symmetric in a and b and the same whichever arrived first."""
    lo, hi = sorted((location_error(located_a), location_error(located_b)))  # the same sum either way round
    return scale * (SAME_TOL + lo + hi)


# the rank of a branch end as its node's point: the node kinds in this order
# (a located bifurcation before a near miss at the same point: the node is
# then a bifurcation whichever arrived first), then the better located
_KIND_RANK = {BIFURCATION: 0, UNDECIDED: 1, NEAR_MISS: 1, MULTI_DOF: 2, RIGID: 2, REGULAR: 2, FAILURE: 3}


def arrival_rank(kind: str, res: Dict[str, Any]) -> Tuple[int, float, float, Tuple[float, ...]]:
    """The canonical order of the branch ends that reach one node: the first
    is the node's point (explorer.merge_level). Its kind's rank, the located
    accuracy (v_r / v_max where located: smaller is better), the tolerance
    it was located to, then the end's coordinates themselves: a key of the
    result alone, never of the order results arrive in or of the branch's
    number."""
    acc = float(res.get("accuracy", math.inf))
    acc = acc if math.isfinite(acc) else math.inf
    X = np.asarray(res["coords"], dtype=float).ravel()
    return (_KIND_RANK.get(kind, 3), acc, float(res.get("vr_tol", 0.0)), tuple(X.tolist()))


@dataclasses.dataclass
class Node:
    id: int
    kind: str
    coords: NDArray[np.float64]
    m: int
    m_rigid: int
    s: int
    v_r_rel: float
    depth: int
    located_v_r: float = 0.0      # v_r / v_max of the vanishing singular value where located
    located_tol: float = 0.0      # the tolerance it was located to (vr_tol, or up to vr_floor)
    orbit: int = -1               # smallest node id of its symmetry orbit
    image_of: Optional[Dict[str, int]] = None        # {"node": k, "symmetry": j}: this is g_j . node k
    expanded: bool = False
    status: str = ""              # why not expanded, or what enumeration found
    branches: Optional[Dict[str, Any]] = None        # how its branches were enumerated

    def arrived(self, kind: str, res: Dict[str, Any]) -> int:
        """Another branch's end identified with this node (of kind `kind`,
        its follower's result res): a bifurcation located there makes a
        node first reached as a near miss (the minimum of v_r along another
        path, which the locator could not pin) a bifurcation, with that
        analysis, so the kind does not depend on which branch came first.
        Only before the node is expanded; its coordinates and location
        tolerance (its index entry) stay. Returns the node's id."""
        if kind == BIFURCATION and self.kind in (NEAR_MISS, UNDECIDED) and not self.expanded:
            self.kind, self.m, self.m_rigid, self.s = kind, int(res["m"]), int(res["m_rigid"]), int(res["s"])
            self.v_r_rel, self.located_v_r = float(res["v_r_rel"]), float(res.get("accuracy", 0.0))
            self.status = ""  # an undecided node's reason no longer applies
        return self.id

    def to_dict(self) -> Dict[str, Any]:
        d = dataclasses.asdict(self)
        d["coords"] = self.coords.tolist()
        return d


def _edge_fields(e: Dict[str, Any]) -> Dict[str, Any]:
    """An edge record as Edge's fields. An atlas written before issue 35
    stored `beta` (in its node's mechanism basis, which it did not store) in
    place of `direction`: that beta cannot be turned into a direction, so it is
    dropped and the direction left empty."""
    if "direction" in e or "beta" not in e:
        return e
    e = {k: v for k, v in e.items() if k != "beta"}
    e["direction"] = []
    return e


@dataclasses.dataclass
class Edge:
    id: int
    source: int
    target: int
    solution: int        # index of beta among the node's solutions (0 at a regular point)
    sign: int            # +1 / -1: which sense of U_m beta
    # sign * U_m beta: the branch's unit first direction in the node's free
    # coordinates. Physical, so the same on every machine; beta itself is in
    # the coordinates of an SVD's mechanism basis, which is not (issue 35).
    direction: List[float]
    event: str           # tasks.EVENT_KINDS
    length: float
    accuracy: float
    samples: List[Any]
    message: str = ""
    steps: int = 0
    vr_tol: float = 0.0  # BIFURCATION: the tolerance it was located to
    # the configuration the path reached where it is not the target node's
    # own coordinates (an end identified with the node up to a rigid motion
    # the supports allow): the viewer draws the path to where it went
    end: Optional[List[Any]] = None

    def to_dict(self) -> Dict[str, Any]:
        return dataclasses.asdict(self)


class Atlas:
    """The result of explore(): nodes, directed edges, the symmetries used,
    the settings and statistics. to_dict()/to_json()/to_graphml() write it;
    Atlas.from_dict() reads to_dict() back."""

    def __init__(self, model: Dict[str, Any], nodes: List[Node], edges: List[Edge], symmetries: List[Symmetry],
                 settings: Dict[str, Any], stats: Dict[str, Any]) -> None:
        self.model, self.nodes, self.edges = model, nodes, edges
        self.symmetries, self.settings, self.stats = symmetries, settings, stats

    def node_name(self, i: int) -> str:
        return f"N{i}"

    def to_dict(self) -> Dict[str, Any]:
        return {"format": "libkin-atlas", "version": 1, "model": self.model, "settings": self.settings,
                "symmetries": [g.to_dict() for g in self.symmetries],
                "nodes": [n.to_dict() for n in self.nodes], "edges": [e.to_dict() for e in self.edges],
                "stats": self.stats}

    def to_json(self, path: Union[None, str, os.PathLike[str]] = None) -> str:
        """The atlas as JSON text (and written to path, whole or not at all):
        indented one space a level, but each node's coordinates and each
        edge's direction, samples and end on one line (the configurations are
        most of a large atlas: one number a line took 1.5x the room)."""
        d = self.to_dict()
        held: List[str] = []
        mark = f"\x00{os.urandom(8).hex()}:"  # no text of the atlas holds it

        def hold(v: Any) -> str:
            held.append(json.dumps(v, separators=(",", ":"), default=_jsonable, allow_nan=True))
            return f"{mark}{len(held) - 1}"
        for n in d["nodes"]:
            n["coords"] = hold(n["coords"])
        for e in d["edges"]:
            for k in ("direction", "samples", "end"):
                e[k] = hold(e[k])
        text = json.dumps(d, indent=1, default=_jsonable, allow_nan=True) + "\n"
        quoted = json.dumps(mark)[:-1]  # the mark as json.dumps writes it, without the closing quote
        text = re.sub(re.escape(quoted) + r'(\d+)"', lambda m: held[int(m.group(1))], text)
        if path is not None:  # whole or not at all
            write_text(path, text)
        return text

    @classmethod
    def from_dict(cls, d: Dict[str, Any]) -> Atlas:
        from ..symmetry.automorphisms import Symmetry
        nodes = [Node(**dict(n, coords=np.asarray(n["coords"]))) for n in d["nodes"]]
        edges = [Edge(**_edge_fields(e)) for e in d["edges"]]
        syms = [Symmetry(tuple(g["perm"]), np.asarray(g["Q"]), np.asarray(g["t"])) for g in d["symmetries"]]
        return cls(d["model"], nodes, edges, syms, d["settings"], d["stats"])

    def to_networkx(self) -> Any:
        """A networkx MultiDiGraph with scalar attributes (lists as JSON text)."""
        import networkx as nx
        G = nx.MultiDiGraph(name=str(self.model.get("name", "model")))
        for n in self.nodes:
            G.add_node(self.node_name(n.id), kind=n.kind, m=n.m, m_rigid=n.m_rigid, s=n.s, v_r_rel=n.v_r_rel,
                       depth=n.depth, orbit=self.node_name(n.orbit), expanded=n.expanded, status=n.status,
                       coords=json.dumps(n.coords.tolist()))
        for e in self.edges:
            G.add_edge(self.node_name(e.source), self.node_name(e.target), key=e.id, solution=e.solution,
                       sign=e.sign, event=e.event, length=e.length,
                       accuracy=e.accuracy if math.isfinite(e.accuracy) else -1.0,
                       direction=json.dumps(e.direction), samples=json.dumps(e.samples), message=e.message,
                       end=json.dumps(e.end))
        return G

    def to_graphml(self, path: Union[str, os.PathLike[str]]) -> None:
        import networkx as nx
        with replacing(path) as tmp:  # whole or not at all
            nx.write_graphml(self.to_networkx(), tmp)

    def summary(self) -> Dict[str, Any]:
        """Counts by node kind and by edge event."""
        nk: Dict[str, int] = {}
        ek: Dict[str, int] = {}
        for n in self.nodes:
            nk[n.kind] = nk.get(n.kind, 0) + 1
        for e in self.edges:
            ek[e.event] = ek.get(e.event, 0) + 1
        return {"nodes": len(self.nodes), "edges": len(self.edges), "node_kinds": nk, "edge_events": ek}

    def same_as(self, other: Atlas, tol: float = 1e-9) -> bool:
        """True if other has the same nodes (kind, m, s, orbit, coordinates to
        tol times the model size) and edges (endpoints, solution, sign, event,
        length to tol, first direction to max(tol, 1e-8) where both have one)."""
        if len(self.nodes) != len(other.nodes) or len(self.edges) != len(other.edges):
            return False
        for a, b in zip(self.nodes, other.nodes):
            if (a.kind, a.m, a.s, a.orbit, a.expanded) != (b.kind, b.m, b.s, b.orbit, b.expanded):
                return False
            if np.abs(a.coords - b.coords).max() > tol * max(1.0, np.abs(a.coords).max()):
                return False
        for e, f in zip(self.edges, other.edges):
            if (e.source, e.target, e.solution, e.sign, e.event) != (f.source, f.target, f.solution, f.sign, f.event):
                return False
            if abs(e.length - f.length) > tol * max(1.0, e.length):
                return False
            # first directions (unit vectors) where both atlases stored them; two
            # complete solves agree to their last digits (1e-13), not to tol's 1e-9
            if e.direction and f.direction and \
                    np.abs(np.asarray(e.direction) - np.asarray(f.direction)).max() > max(tol, 1e-8):
                return False
        return True


def _jsonable(v: Any) -> Any:
    if isinstance(v, np.integer):
        return int(v)
    if isinstance(v, np.floating):
        return float(v)
    if isinstance(v, np.ndarray):
        return v.tolist()
    if isinstance(v, np.bool_):
        return bool(v)
    return str(v)


def node_kind(event: str, res: Dict[str, Any]) -> str:
    """The kind of the node a branch ends at, from its event and the analysis
    there (m, s)."""
    if event == tasks.FAILURE:
        return FAILURE
    m, s = res["m"], res["s"]
    if event == tasks.NEAR_MISS and m >= 1:
        # the follower's minimum of v_r, decided with a margin (tasks.near_verdict): never a
        # bifurcation to expand, whatever a rank tolerance counts there (issue 35 item 4)
        return UNDECIDED if res.get("undecided") else NEAR_MISS
    if event == tasks.BIFURCATION and res.get("undecided"):
        return UNDECIDED  # tangent branches (tasks.crossing_verdict): never expanded
    if m == 0:
        return RIGID
    if m >= 2:
        return BIFURCATION if s >= 1 else MULTI_DOF
    # m = 1: regular here, whatever the follower reported
    return NEAR_MISS if event in (tasks.NEAR_MISS, tasks.BIFURCATION) else REGULAR
