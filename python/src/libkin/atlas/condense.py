"""A readable view of a large atlas.

A depth-1 atlas of the hexagonal sail's flat state has tens of thousands of
nodes: drawn one per row, the map would be metres tall, and a report listing
every node would be read by nobody. The condensed view keeps the nodes that
matter most for a reader (the start and every expanded node, then the nodes
most paths arrive at, whole symmetry orbits at a time) and merges the rest
into one node per depth and kind ("+n other bifurcations, m 2..6"), with
their paths redirected to it, so the map stays a page and still accounts for
every path. The atlas itself (atlas.json, GraphML) is never condensed.
"""
from __future__ import annotations

import collections
import dataclasses
from typing import Dict, List, Tuple

import numpy as np

from . import model as _atlas


def condense(atlas: _atlas.Atlas, max_nodes: int = 40) -> Tuple[_atlas.Atlas, Dict[int, str]]:
    """(view, labels): the atlas itself when it has at most max_nodes nodes,
    else a view with at most about max_nodes of its nodes plus one merged
    node per (depth, kind) of the others, and the labels of the merged nodes
    by id."""
    if len(atlas.nodes) <= max_nodes:
        return atlas, {}
    arrivals = collections.Counter(e.target for e in atlas.edges if e.target != e.source)
    keep = {n.id for n in atlas.nodes if n.depth == 0 or n.expanded}
    # whole orbits, ranked by the paths arriving at them (ties: first reached)
    orbit_in: Dict[int, int] = collections.Counter()
    members: Dict[int, List[int]] = collections.defaultdict(list)
    for n in atlas.nodes:
        orbit_in[n.orbit] += arrivals.get(n.id, 0)
        members[n.orbit].append(n.id)
    for orb in sorted(members, key=lambda o: (-orbit_in[o], o)):
        if len(keep) + len(members[orb]) > max_nodes:
            break
        keep.update(members[orb])
    next_id = max(n.id for n in atlas.nodes) + 1
    merged: Dict[Tuple[int, str], List[_atlas.Node]] = collections.defaultdict(list)
    for n in atlas.nodes:
        if n.id not in keep:
            merged[(n.depth, n.kind)].append(n)
    where: Dict[int, int] = {i: i for i in keep}
    nodes = [n for n in atlas.nodes if n.id in keep]
    labels: Dict[int, str] = {}
    for (depth, kind), ns in sorted(merged.items()):
        nid = next_id
        next_id += 1
        for n in ns:
            where[n.id] = nid
        ms = sorted({n.m for n in ns})
        ss = sorted({n.s for n in ns})
        paths_in = sum(arrivals.get(n.id, 0) for n in ns)
        orbits = len({n.orbit for n in ns})
        what = kind.replace("_", "-")
        rng = (f", m {ms[0]}..{ms[-1]}, s {ss[0]}..{ss[-1]}" if kind == _atlas.BIFURCATION and len(ns) > 1 else
               f", m {ms[0]}, s {ss[0]}" if kind == _atlas.BIFURCATION else "")
        labels[nid] = f"+{len(ns):,} other {what} nodes ({orbits:,} up to symmetry{rng}; {paths_in:,} paths in)"
        nodes.append(_atlas.Node(nid, kind, np.zeros_like(ns[0].coords), ms[0], ns[0].m_rigid, ss[0], float("nan"),
                                 depth, orbit=nid, status="merged"))
    edges = [dataclasses.replace(e, source=where[e.source], target=where[e.target]) for e in atlas.edges]
    return _atlas.Atlas(atlas.model, nodes, edges, atlas.symmetries, atlas.settings, atlas.stats), labels
