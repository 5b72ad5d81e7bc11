"""A large atlas made from a small real one, as load for the viewer
(test_viewer_browser.py, bench/bench_viewer.py).

Synthetic load, not a result: replicate() keeps the real atlas's start node
and copies its other nodes (with their configurations, kinds, m, s and depth)
and the edges among them and from the start (with their samples) under new
ids, as many times as it takes to reach n_nodes; the last copy is cut to fit
(its edges to nodes cut off are left out). Orbits map to the copy's ids. So
the page carries as many nodes, paths and configurations as a real atlas of
that size (the hexagonal sail's depth-one atlas has 23,359 nodes), with the
geometry of real ones.
"""
from __future__ import annotations

import dataclasses

from libkin.atlas import Atlas


def replicate(atlas: Atlas, n_nodes: int) -> Atlas:
    """n_nodes nodes made from atlas (the atlas itself for its own size)."""
    if n_nodes == len(atlas.nodes):
        return atlas
    start = atlas.nodes[0]
    others = atlas.nodes[1:]
    if not others:
        raise ValueError("the atlas has only its start")
    nodes = [start]
    edges = [dataclasses.replace(e, id=0) for e in atlas.edges if e.source == start.id and e.target == start.id]
    copy = 0
    while len(nodes) < n_nodes:
        base = 1 + copy * len(others)
        room = n_nodes - len(nodes)
        new = {n.id: base + k for k, n in enumerate(others) if k < room}
        new[start.id] = start.id
        for n in others[:room]:
            nodes.append(dataclasses.replace(n, id=new[n.id], orbit=new.get(n.orbit, new[n.id]), image_of=None))
        for e in atlas.edges:
            if e.source == start.id and e.target == start.id:
                continue
            if e.source in new and e.target in new:
                edges.append(dataclasses.replace(e, source=new[e.source], target=new[e.target]))
        copy += 1
    edges = [dataclasses.replace(e, id=k) for k, e in enumerate(edges)]
    stats = dict(atlas.stats, nodes=len(nodes), edges=len(edges), synthetic=f"{copy} copies of {atlas.model.get('name')}")
    return Atlas(atlas.model, nodes, edges, atlas.symmetries, atlas.settings, stats)
