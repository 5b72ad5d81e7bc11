"""Benchmark report: how accurately the atlas located its bifurcations where
several singular values vanish together (issue 35 item 3).

  python bench/corank_accuracy.py BEFORE/atlas.json AFTER/atlas.json --out bench/corank_accuracy_depth5.json

reads two atlases of the same model (bench/bench_atlas_depth.py run ...
writes DIR/atlas.json: one with the code before the corank-k locator, one
after) and, for every bifurcation node with m_internal >= 3 (k = m_internal
- 1 >= 2 singular values vanish there) in either, the located v_r / v_max
(the largest of the vanishing group at the located point, the follower's
`accuracy`) and the tolerance it was accepted at, matched to the other
atlas's nearest bifurcation node (max-norm distance of the coordinates
given). Prints per (m, s) class the counts, how many were located only to a
relaxed tolerance (vr_tol > 1e-10) and the worst and median accuracy, the
branches that failed (the follower's refused first steps) with their
messages, and writes every node's row to --out. Not a test.
"""
from __future__ import annotations

import argparse
import collections
import json
from typing import Any, Dict, List

import numpy as np


def load(path: str) -> Dict[str, Any]:
    with open(path) as f:
        return json.load(f)


def bifurcations(d: Dict[str, Any]) -> List[Dict[str, Any]]:
    return [n for n in d["nodes"] if n["kind"] == "bifurcation" and n.get("image_of") is None]


def corank(n: Dict[str, Any]) -> int:
    return n["m"] - n["m_rigid"] - 1


def nearest(nodes: List[Dict[str, Any]]):
    from scipy.spatial import cKDTree
    X = np.array([np.ravel(n["coords"]) for n in nodes])
    tree = cKDTree(X)

    def find(x: Any):
        dist, i = tree.query(np.ravel(x), p=np.inf)
        return nodes[int(i)], float(dist)
    return find


def failures(d: Dict[str, Any]) -> List[Dict[str, Any]]:
    depth = {n["id"]: n["depth"] for n in d["nodes"]}
    out = []
    for e in d["edges"]:
        if e["event"] == "failure":
            out.append({"source": e["source"], "depth": depth.get(e["source"], -1) + 1,
                        "message": (e.get("message") or "")[:120]})
    return out


def classes(nodes: List[Dict[str, Any]]) -> Dict[str, Dict[str, Any]]:
    by = collections.defaultdict(list)
    for n in nodes:
        if corank(n) >= 2:
            by[f"m={n['m'] - n['m_rigid']}, s={n['s']}"].append(n)
    out = {}
    for key, ns in sorted(by.items()):
        acc = np.array([n["located_v_r"] for n in ns])
        out[key] = {"nodes": len(ns), "relaxed": sum(n["located_tol"] > 1e-10 for n in ns),
                    "worst": float(acc.max()), "median": float(np.median(acc)),
                    "above_1e-10": int((acc > 1e-10).sum())}
    return out


def main() -> None:
    p = argparse.ArgumentParser()
    p.add_argument("before")
    p.add_argument("after")
    p.add_argument("--out", required=True)
    args = p.parse_args()
    B, A = load(args.before), load(args.after)
    nb, na = bifurcations(B), bifurcations(A)
    find_a, find_b = nearest(na), nearest(nb)
    rows = []
    for n in nb:
        if corank(n) < 2:
            continue
        m, dist = find_a(n["coords"])
        rows.append({"before": {"id": n["id"], "depth": n["depth"], "m": n["m"] - n["m_rigid"], "s": n["s"],
                                "v_r": n["located_v_r"], "vr_tol": n["located_tol"]},
                     "after": {"id": m["id"], "depth": m["depth"], "m": m["m"] - m["m_rigid"], "s": m["s"],
                               "v_r": m["located_v_r"], "vr_tol": m["located_tol"]},
                     "distance": dist})
    new_after = []
    for n in na:
        if corank(n) < 2:
            continue
        m, dist = find_b(n["coords"])
        if corank(m) < 2 or dist > 1e-6:
            new_after.append({"id": n["id"], "depth": n["depth"], "m": n["m"] - n["m_rigid"], "s": n["s"],
                              "v_r": n["located_v_r"], "vr_tol": n["located_tol"],
                              "nearest_before": {"id": m["id"], "m": m["m"] - m["m_rigid"], "s": m["s"],
                                                 "v_r": m["located_v_r"], "vr_tol": m["located_tol"]},
                              "distance": dist})
    fb, fa = failures(B), failures(A)
    summary = {"before": {"classes": classes(nb), "failures": len(fb),
                          "failures_by_depth": dict(collections.Counter(f["depth"] for f in fb)),
                          "failure_messages": dict(collections.Counter(f["message"][:60] for f in fb)),
                          "relaxed_bifurcations": sum(n["located_tol"] > 1e-10 for n in nb)},
               "after": {"classes": classes(na), "failures": len(fa),
                         "failures_by_depth": dict(collections.Counter(f["depth"] for f in fa)),
                         "failure_messages": dict(collections.Counter(f["message"][:60] for f in fa)),
                         "relaxed_bifurcations": sum(n["located_tol"] > 1e-10 for n in na)},
               "before_file": args.before, "after_file": args.after}
    with open(args.out, "w") as f:
        json.dump({"summary": summary, "corank_nodes_before": rows, "corank_nodes_after_not_before": new_after,
                   "failures_before": fb, "failures_after": fa}, f, indent=1)
    print("| class (m_internal, s) | nodes before / after | relaxed before / after | worst v_r/v_max before / after "
          "| median before / after |")
    print("|---|---|---|---|---|")
    cb, ca = summary["before"]["classes"], summary["after"]["classes"]
    for key in sorted(set(cb) | set(ca)):
        b, a = cb.get(key, {}), ca.get(key, {})
        print(f"| {key} | {b.get('nodes', 0)} / {a.get('nodes', 0)} | {b.get('relaxed', 0)} / {a.get('relaxed', 0)} "
              f"| {b.get('worst', float('nan')):.1e} / {a.get('worst', float('nan')):.1e} "
              f"| {b.get('median', float('nan')):.1e} / {a.get('median', float('nan')):.1e} |")
    print(f"relaxed bifurcations (all coranks): {summary['before']['relaxed_bifurcations']} -> "
          f"{summary['after']['relaxed_bifurcations']}")
    print(f"failed branches: {len(fb)} {summary['before']['failures_by_depth']} -> {len(fa)} "
          f"{summary['after']['failures_by_depth']}")
    for k, v in summary["after"]["failure_messages"].items():
        print(f"  after: {v} x {k}")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
