"""The atlas level by level: what each depth of an explore() cost and found.

explore() records one row per level it ran (Levels, in stats["levels"]):
the frontier it started from, the nodes it expanded (the others are images
of expanded ones, or were left by a bound), the directed branches, how many
were followed and how many mapped by symmetry, the nodes the level added,
and where the wall time went: enumerating the branches (the node's
analysis, its symmetries and the complete solve: in the client, apart from
the solver's shards), following them (the executor; the client identifies
the ends as they come in, orbits.follow_level) and what is left of the
merge after that (counts, the next frontier). by_depth() gives the per-depth table of a
finished atlas (events, new nodes and new orbits per depth) from its nodes
and edges alone, so it also reads an atlas.json written before the rows
existed.
"""
from __future__ import annotations

import time
from typing import Any, Callable, Dict, List, Sequence, Tuple


class Levels:
    """Per-level counts and times of one explore() (Levels.rows)."""

    def __init__(self) -> None:
        self.rows: List[Dict[str, Any]] = []
        self._t = 0.0

    def begin(self, level: int, frontier: Sequence[int]) -> None:
        self._t = time.perf_counter()
        self.rows.append({"depth": level + 1, "frontier": len(frontier)})

    def follow(self, ex: Any, run: Callable[[], Tuple[List[Any], int, int]]) -> List[Any]:
        """run() -> (results, followed, mapped) of the level's branches;
        counts them on the explorer and in the row, timing the enumeration
        before and the following."""
        row, t = self.rows[-1], time.perf_counter()
        row["enumerate_seconds"] = round(t - self._t, 3)
        results, followed, mapped = run()
        ex.followed += followed
        ex.mapped += mapped
        self._t = time.perf_counter()
        row.update(follow_seconds=round(self._t - t, 3), directed_branches=len(results), followed=followed,
                   mapped=mapped, not_followed=sum(1 for r in results if r is None))
        return results

    def end(self, nodes: Sequence[Any], before: int) -> None:
        """After the merge: the nodes the level added (nodes[before:])."""
        row, t = self.rows[-1], time.perf_counter()
        row["merge_seconds"] = round(t - self._t, 3)
        new = nodes[before:]
        row["expanded"] = sum(1 for n in nodes if n.expanded and n.depth == row["depth"] - 1)
        row["new_nodes"] = len(new)
        row["new_bifurcation_nodes"] = sum(1 for n in new if n.kind == "bifurcation")
        row["new_bifurcation_nodes_not_images"] = sum(1 for n in new if n.kind == "bifurcation"
                                                      and n.image_of is None)

    def identity_undecided(self) -> int:
        """Branch ends whose node was not decided with a margin (identity.py)."""
        return sum(int(r.get("identity", {}).get("undecided", 0)) for r in self.rows)


def by_depth(d: Dict[str, Any]) -> List[Dict[str, Any]]:
    """Per depth of a finished atlas (its to_dict() / atlas.json): the
    directed branches out of the nodes one level up and their events, the
    nodes first reached at that depth and their orbits (an orbit is new at
    the depth of its smallest-id member: orbits are numbered by it), the
    new bifurcation orbits (the next level's work) and the nodes expanded."""
    nodes = d["nodes"]
    depth_of = {n["id"]: n["depth"] for n in nodes}
    deepest = max([n["depth"] for n in nodes] + [n["depth"] + 1 for n in nodes if n["expanded"]])
    rows: List[Dict[str, Any]] = []
    for k in range(1, deepest + 1):
        edges = [e for e in d["edges"] if depth_of[e["source"]] == k - 1]
        events: Dict[str, int] = {}
        for e in edges:
            events[e["event"]] = events.get(e["event"], 0) + 1
        new = [n for n in nodes if n["depth"] == k]
        orbits = {n["orbit"] for n in new if depth_of[n["orbit"]] == k}
        kinds: Dict[str, int] = {}
        for o in orbits:
            kinds[nodes[o]["kind"]] = kinds.get(nodes[o]["kind"], 0) + 1
        rows.append({"depth": k, "sources_expanded": sum(1 for n in nodes if n["depth"] == k - 1 and n["expanded"]),
                     "directed_branches": len(edges), "events": events,
                     "back_to_earlier_nodes": sum(1 for e in edges if depth_of[e["target"]] < k),
                     "new_nodes": len(new), "new_orbits": len(orbits), "new_orbits_by_kind": kinds,
                     "new_bifurcation_orbits": kinds.get("bifurcation", 0)})
    return rows
