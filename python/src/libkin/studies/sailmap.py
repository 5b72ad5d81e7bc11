"""The sail study's path map, read from the explorer's atlas (libkin.atlas).

The study does not follow the map's paths itself: explore() in symmetric
mode maps every path out of the flat state R^A that keeps the rotational
symmetry, and (depth 2) every such path out of the bifurcations they reach,
among them the run's R^B and R^C. What is sail-specific is here: the names
(R^A, R^B, R^C for the run's points, X1, X2, ... for the others, a prime
for the image of a node under a symmetry of the structure, which for these
rotationally symmetric configurations is the mirror z -> -z), the measures
of compactness, and which of the atlas's nodes are the run's points.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Dict, List, Optional, Tuple

import numpy as np
from numpy.typing import ArrayLike

from libkin.atlas import BIFURCATION, Atlas, Edge, Node, explore
from libkin.atlas.model import pair_window
from libkin.atlas.report import identity_sentence

if TYPE_CHECKING:
    from libkin.assembly import Assembly

# levels of the atlas: the flat state's branches, then every bifurcation they
# reach (R^B and R^C are among them for the hexagonal sail)
MAP_DEPTH = 2
# the run's bifurcations are located to v_r / v_max <= this
RUN_VR_TOL = 1e-10


def explore_symmetric(a: Assembly, depth: int = MAP_DEPTH, executor: Any = None, threads: int = 1,
                      progress: bool = False) -> Atlas:
    """The atlas of the symmetric paths out of a's configuration."""
    return explore(a, depth=depth, symmetric=True, executor=executor, threads=threads,
                          progress=True if progress else None)


class SailMap:
    """An atlas seen by the sail study: node names, the run's points, the
    paths out of a node (also of a node the atlas did not expand because it
    is the image of another), and the summary the report prints."""

    def __init__(self, atlas: Atlas) -> None:
        self.atlas = atlas
        # the same map explored again with contact as an event, when the
        # study is asked for it (contactmap.py; `libkin study --contact`)
        self.contact_atlas: Optional[Atlas] = None
        self.nodes = atlas.nodes
        x0 = self.nodes[0].coords
        self.scale = max(1.0, float(np.abs(x0 - x0.mean(axis=0)).max()))
        self.run: Dict[int, str] = {0: "R^A"}  # node id -> the run's name

    # -- which node a configuration is
    def _tol(self, located_a: float, located_b: float) -> float:
        # as the explorer identifies points (libkin.atlas.model.pair_window)
        return pair_window(self.scale, located_a, located_b)

    def node_at(self, X: ArrayLike, located: float = RUN_VR_TOL) -> Optional[int]:
        """The id of the node at configuration X (None if none is)."""
        best: Optional[Tuple[float, int]] = None
        for n in self.nodes:
            d = float(np.abs(np.asarray(X) - n.coords).max())
            if d <= self._tol(located, n.located_tol) and (best is None or d < best[0]):
                best = (d, n.id)
        return None if best is None else best[1]

    def mark(self, X: ArrayLike, name: str) -> Tuple[Optional[int], bool]:
        """Name the node at X after the run's point `name`: (its id, True).
        If X is not a node but the image of one under a symmetry (the
        atlas keeps one node of each orbit it does not expand), that node
        is named as the image, name + "'": (its id, False). (None, False)
        if neither."""
        i = self.node_at(X)
        if i is not None:
            self.run[i] = name
            return i, True
        for n in self.nodes:
            for g in self.atlas.symmetries:
                if not g.is_identity and float(np.abs(g.apply(n.coords) - np.asarray(X)).max()) <= self._tol(
                        RUN_VR_TOL, n.located_tol):
                    self.run[n.id] = name + "'"
                    return n.id, False
        return None, False

    # -- paths out of a node
    def paths_from(self, i: int) -> List[Tuple[Edge, Optional[int]]]:
        """[(edge, target id)] out of node i. A node the atlas did not
        expand because it is the image g . k of node k has k's paths mapped
        by g (target None where the image of k's target is not a node)."""
        n = self.nodes[i]
        if n.expanded or n.image_of is None:
            return [(e, int(e.target)) for e in self.atlas.edges if e.source == i]
        k, g = n.image_of["node"], self.atlas.symmetries[n.image_of["symmetry"]]
        out: List[Tuple[Edge, Optional[int]]] = []
        for e in self.atlas.edges:
            if e.source == k:
                t = self.nodes[e.target]
                out.append((e, i if e.target == k else self.node_at(g.apply(t.coords), t.located_tol)))
        return out

    def branches_record(self, i: int) -> Optional[Dict[str, Any]]:
        """How the branches at node i were enumerated (its orbit
        representative's record for an image)."""
        n = self.nodes[i]
        if n.branches is None and n.image_of is not None:
            n = self.nodes[n.image_of["node"]]
        return n.branches

    # -- names and measures
    def names(self) -> Dict[int, str]:
        """{node id: name}: the run's names, X1, X2, ... for the others in
        order of their orbit, primes for the other members of an orbit."""
        orbits: Dict[int, List[int]] = {}
        for n in self.nodes:
            orbits.setdefault(n.orbit, []).append(n.id)
        out: Dict[int, str] = {}
        k = 0
        for rep in sorted(orbits):
            members = orbits[rep]
            named = [i for i in members if i in self.run]
            if named:
                base, first = self.run[named[0]], named[0]
            else:
                k += 1
                base, first = f"X{k}", members[0]
            out[first] = base
            # the other members: primed (the image of a primed name is unprimed)
            stem, primes = (base[:-1], 0) if base.endswith("'") and base[:-1] not in self.run.values() else (base, 1)
            for i in members:
                if i == first:
                    continue
                out[i] = self.run.get(i) or stem + "'" * primes
                primes += 0 if i in self.run else 1
        return out

    def write_html(self, path: Any, title: Optional[str] = None, progress: bool = False) -> bool:
        """The atlas as a page to walk in a browser (libkin.atlas.html), with
        the run's names; False (nothing written) when plotly, whose plotly.js
        the page carries, is not installed. progress: a bar over the nodes."""
        from libkin.atlas import html
        try:
            html.require_plotly()
        except ImportError:
            return False
        html.write(self.atlas, path, names=self.names(), title=title, progress=progress)
        return True

    @staticmethod
    def measures(n: Node) -> Dict[str, float]:
        x = n.coords
        return {"xy_extent": float(np.hypot(x[:, 0], x[:, 1]).max()), "height": float(np.ptp(x[:, 2]))}

    def more_compact(self, i: int) -> List[Tuple[str, float]]:
        """The mapped nodes more compact than node i (smaller x-y extent, by
        more than 1e-9 a) as (name, x-y extent), most compact first: the
        node table's own numbers."""
        names = self.names()
        ext = self.measures(self.nodes[i])["xy_extent"]
        out = [(names[n.id], self.measures(n)["xy_extent"]) for n in self.nodes]
        return sorted(((nm, e) for nm, e in out if e < ext - 1e-9), key=lambda t: (t[1], t[0]))

    def relaxed(self, n: Node) -> bool:
        """A bifurcation the follower located only to a coarser v_r than the
        run's points (its m, s counted at ten times that tolerance)."""
        return n.kind == BIFURCATION and n.located_tol > RUN_VR_TOL

    def summary(self, a: Optional[Assembly] = None) -> Dict[str, Any]:
        """{"nodes": [...], "edges": [...], "atlas": {...}} for summary.json:
        edges grouped by (from, to, event), their lengths sorted. Given
        the Assembly a, a bifurcation located only to a coarser v_r is also
        analysed at a's own rank tolerance (m_default, s_default) and its
        lowest singular values recorded (relative to v_max)."""
        names = self.names()
        nodes: List[Dict[str, Any]] = []
        for n in self.nodes:
            rec = self.branches_record(n.id) or {}
            d = dict({"name": names[n.id], "id": n.id, "kind": n.kind, "m": n.m, "s": n.s,
                      "located_tol": n.located_tol, "expanded": n.expanded,
                      "image_of": None if n.image_of is None else names[n.image_of["node"]],
                      "symmetric_branches": rec.get("solutions"), "status": n.status}, **self.measures(n))
            if a is not None and self.relaxed(n):
                c = a.clone()
                c.coords = n.coords
                an = c.analyse()
                sv = np.sort(an.singular_values) / an.v_max
                d.update({"m_default": an.m_internal, "s_default": an.s,
                          "lowest_sv_rel": [float(v) for v in sv[: n.m + 1]]})
            nodes.append(d)
        agg: Dict[Tuple[int, int, str], Dict[str, Any]] = {}
        for e in self.atlas.edges:
            key = (e.source, e.target, e.event)
            g = agg.setdefault(key, {"from": names[e.source], "to": names[e.target], "event": e.event,
                                     "paths": 0, "l": []})
            g["paths"] += 1
            g["l"].append(round(e.length, 6))
        for g in agg.values():
            g["l"] = sorted(set(g["l"]))
        st = self.atlas.stats
        info = {"depth": self.atlas.settings["depth"], "nodes": st["nodes"], "edges": st["edges"],
                "node_kinds": st["node_kinds"], "edge_events": st["edge_events"], "seconds": st["seconds"],
                "identity": identity_sentence(st)}
        return {"nodes": nodes, "edges": list(agg.values()), "atlas": info}
