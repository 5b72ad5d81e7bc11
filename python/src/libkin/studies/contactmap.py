"""The study's path map with contact as an event (`libkin study --contact`).

The path map (sailmap.py) is the explorer's symmetric atlas with parts that
pass through each other, as the paper lets them. Here the same atlas is
explored again with the membrane as panels (every bar triangle and the hub
polygon, sailmeasure.sail_panels), bars of radius t/2 and panels of
thickness t, and contact events on (explore(contact=True), docs/contact.md):
every branch stops at its first contact of two parts that share no joint.
Each of the map's nodes then says how many of its paths reach their next
event free of contact, and which parts touch first on the others.

The contact atlas is a separate run, not a filter of the path map: a branch
that touches stops there, so the nodes beyond it are never reached and the
next level is smaller. Its nodes are named after the path map's (R^A, R^B,
X3, ...) where they are the same configuration (SailMap.node_at), so the two
tables read side by side.
"""
import re
import time
from typing import Any, Dict, List

from libkin.atlas import explore

from .common import say
from .contactreport import contact_map_md  # noqa: F401 - the report's section on it
from .sailmeasure import part_name, sail_panels

_PARTS = re.compile(r"(bar|panel) (\d+)")


def contact_parts(a: Any, panels: List[List[int]], message: str) -> List[str]:
    """The two parts a contact edge's message names ('contact: bar 3 /
    panel 7'), by their joints' labels ('bar A0-A1', 'panel A0-B0-B1')."""
    return [part_name(a, panels, kind, int(i)) for kind, i in _PARTS.findall(message)]


def contact_map(a: Any, smap: Any, depth: int, thickness: float = 0.0, executor: Any = None,
                threads: int = 1, progress: bool = False) -> Dict[str, Any]:
    """Explore a's symmetric paths to `depth` levels with contact events on
    (the membrane as panels, thickness t/a = `thickness`) and summarise it
    against the path map `smap` (a SailMap of the same start). Returns a
    JSON-serialisable dict: per expanded node its paths, how many end in
    contact and how many reach their next event free of it, the first
    contacts (parts and path length), and the atlas's counts; "atlas" is the
    contact Atlas itself (not serialisable; drop it before writing)."""
    t0 = time.perf_counter()
    model = a.clone()
    panels = sail_panels(a)
    model.panels = panels
    model.set_thickness(float(thickness))
    say(progress, f"[contact map] the symmetric paths again (depth {depth}), each stopped at its first "
                  f"contact (membrane {len(panels)} panels, t/a = {thickness:g}) ...")
    atlas = explore(model, depth=depth, symmetric=True, executor=executor, threads=threads, contact=True)
    names = smap.names()
    name_of: Dict[int, str] = {}
    for n in atlas.nodes:
        i = smap.node_at(n.coords, n.located_tol)
        name_of[n.id] = names[i] if i is not None else f"new {n.id}"
    by_node: Dict[int, Dict[str, Any]] = {}
    for e in atlas.edges:
        row = by_node.setdefault(e.source, {"node": name_of[e.source], "paths": 0, "contact": 0, "free": 0,
                                            "events": {}, "contacts": {}})
        row["paths"] += 1
        row["events"][e.event] = row["events"].get(e.event, 0) + 1
        if e.event == "contact":
            row["contact"] += 1
            key = " / ".join(contact_parts(a, panels, e.message))
            c = row["contacts"].setdefault(key, {"parts": key, "paths": 0, "l_min": e.length})
            c["paths"] += 1
            c["l_min"] = min(c["l_min"], e.length)
        else:
            row["free"] += 1
    rows: List[Dict[str, Any]] = []
    for sid in sorted(by_node):
        row = by_node[sid]
        row["contacts"] = sorted(row["contacts"].values(), key=lambda c: (c["l_min"], c["parts"]))
        for c in row["contacts"]:
            c["l_min"] = round(c["l_min"], 6)
        rows.append(row)
    ev = dict(atlas.stats["edge_events"])
    res: Dict[str, Any] = {"thickness": float(thickness), "depth": depth, "panels": len(panels),
                           "nodes": len(atlas.nodes), "paths": len(atlas.edges), "edge_events": ev,
                           "free": len(atlas.edges) - ev.get("contact", 0), "by_node": rows,
                           "seconds": round(time.perf_counter() - t0, 1), "atlas": atlas}
    say(progress, f"[contact map] {res['paths']} paths: {ev.get('contact', 0)} end in contact, {res['free']} "
                  f"reach their next event free of it ({res['seconds']} s)")
    return res
