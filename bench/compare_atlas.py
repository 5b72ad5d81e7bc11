"""Compare two atlas.json files node for node and edge for edge.

  python bench/compare_atlas.py A/atlas.json B/atlas.json [--list 10]

Nodes (in id order): kind, m, s, orbit, expanded, and the coordinates to the
identification tolerance (settings["same_tol"], the model size times
SAME_TOL, or wider for a coarsely located node, as the explorer's
pair_tol); edges (in id order): source, target, solution, sign, event, the
steps, the path length (relative 1e-9) and the located accuracy (v_r / v_max
at the end: both within the tolerance they were located to, or equal to
1e-3 relative). Prints the counts of differences of each kind, the first
few, and the two runs' stats side by side. Exit status 1 when they differ.
--renumber matches B's nodes to A's by configuration before comparing.
"""
from __future__ import annotations

import argparse
import collections
import json
import math
import sys
from typing import Any, Dict, List

import numpy as np

from libkin.atlas.model import LOCATION_FACTOR, SAME_TOL


def _load(path: str) -> Dict[str, Any]:
    with open(path) as f:
        return json.load(f)


def renumber(a: Dict[str, Any], b: Dict[str, Any]) -> Dict[str, Any]:
    """b with its nodes renumbered as a's: each b node takes the id of the
    nearest a node (max-norm of the coordinates; a k-d tree), the nodes
    put in that order, the edges' source and target and the nodes' orbit
    and image_of mapped. For atlases whose nodes were identified in
    another order (the symmetric run takes the images whose mapping is not
    certain last, orbits.follow_level); an a node that is no b node's
    nearest leaves a gap the comparison reports."""
    from scipy.spatial import cKDTree
    tree = cKDTree(np.array([np.ravel(n["coords"]) for n in a["nodes"]]))
    _, near = tree.query(np.array([np.ravel(n["coords"]) for n in b["nodes"]]), p=np.inf)
    to = {n["id"]: int(i) for n, i in zip(b["nodes"], near)}
    orbit: Dict[int, int] = {}  # an orbit is named by its smallest member
    for n in b["nodes"]:
        orbit[n["orbit"]] = min(orbit.get(n["orbit"], to[n["id"]]), to[n["id"]])
    nodes = []
    for n in b["nodes"]:
        n = dict(n, id=to[n["id"]], orbit=orbit[n["orbit"]])
        if n.get("image_of"):
            n["image_of"] = dict(n["image_of"], node=to[n["image_of"]["node"]])
        nodes.append(n)
    edges = [dict(e, source=to[e["source"]], target=to[e["target"]]) for e in b["edges"]]
    return dict(b, nodes=sorted(nodes, key=lambda n: n["id"]), edges=edges)


def compare(a: Dict[str, Any], b: Dict[str, Any], tol: float) -> Dict[str, List[Any]]:
    diff: Dict[str, List[Any]] = collections.defaultdict(list)
    if len(a["nodes"]) != len(b["nodes"]):
        diff["node count"].append((len(a["nodes"]), len(b["nodes"])))
    if [n["id"] for n in b["nodes"]] != list(range(len(b["nodes"]))):
        diff["node ids (renumbered: not one b node per a node)"].append(len(b["nodes"]))
    for x, y in zip(a["nodes"], b["nodes"]):
        for k in ("kind", "m", "s", "orbit", "expanded"):
            if x[k] != y[k]:
                diff[f"node {k}"].append((x["id"], x[k], y[k]))
        d = float(np.abs(np.asarray(x["coords"]) - np.asarray(y["coords"])).max())
        # the explorer's own pair tolerance (_Explorer.pair_tol): wider for a coarsely located point
        located = max(float(x.get("located_tol", 0.0)), float(y.get("located_tol", 0.0)), 0.0)
        if d > max(tol, tol / SAME_TOL * LOCATION_FACTOR * math.sqrt(located)):
            diff["node coords beyond the identification tolerance"].append((x["id"], d))
    if len(a["edges"]) != len(b["edges"]):
        diff["edge count"].append((len(a["edges"]), len(b["edges"])))
    for e, f in zip(a["edges"], b["edges"]):
        for k in ("source", "target", "solution", "sign", "event", "steps"):
            if e[k] != f[k]:
                diff[f"edge {k}"].append((e["id"], e[k], f[k]))
        if abs(e["length"] - f["length"]) > 1e-9 * max(1.0, e["length"]):
            diff["edge length"].append((e["id"], e["length"], f["length"]))
        ea, fa = e["accuracy"], f["accuracy"]
        if e["event"] == "bifurcation" and not (ea <= e["vr_tol"] and fa <= f["vr_tol"]) \
                and not abs(ea - fa) <= 1e-3 * max(abs(ea), abs(fa)):
            diff["edge accuracy"].append((e["id"], ea, fa))
    return diff


def main(argv: List[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("a")
    p.add_argument("b")
    p.add_argument("--list", type=int, default=10, help="differences shown per kind")
    p.add_argument("--renumber", action="store_true",
                   help="match B's nodes to A's by configuration first (renumber()): for atlases whose "
                        "nodes were numbered in another order")
    args = p.parse_args(argv)
    a, b = _load(args.a), _load(args.b)
    if args.renumber:
        b = renumber(a, b)
    tol = float(a["settings"].get("same_tol", 1e-6))
    diff = compare(a, b, tol)
    print(f"{len(a['nodes'])} / {len(b['nodes'])} nodes, {len(a['edges'])} / {len(b['edges'])} edges; "
          f"identification tolerance {tol:.3g}")
    ev = [collections.Counter(e["event"] for e in d["edges"]) for d in (a, b)]
    print("events:", dict(ev[0]), "/", dict(ev[1]))
    acc = [sum(1 for e in d["edges"] if e["event"] == "bifurcation" and e["accuracy"] <= 1e-10) for d in (a, b)]
    print(f"located to <= 1e-10: {acc[0]} / {acc[1]}")
    for k in ("seconds", "follow_cpu_seconds", "branches_followed", "returns_decided_again"):
        print(f"stats {k}: {a['stats'].get(k)} / {b['stats'].get(k)}")
    if not diff:
        print("the same atlas: every node and edge")
        return 0
    for k, v in diff.items():
        print(f"{k}: {len(v)} differ, e.g. {v[:args.list]}")
    return 1


if __name__ == "__main__":
    sys.exit(main())
