"""report.md (and the files it shows) for an atlas of any structure."""
from __future__ import annotations

import collections
import contextlib
import math
import os
import pathlib
import sys
import time
from typing import Any, Dict, Iterator, List, Optional, Tuple, Union

import numpy as np

from ..atomic import staged_folder, write_text
from ..cliargs import require_extras
from . import model as _atlas
from . import tasks
from .limits import limits_hit as limits_hit  # noqa: F401 - `libkin explore` prints them


def _f(v: Any, fmt: str = ".4g") -> str:
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "-"
    return format(v, fmt)


# what the files need beyond the core package: module -> the extra that brings it
OUTPUT_MODULES = {"networkx": "atlas", "matplotlib": "plot"}


def identity_sentence(st: Dict[str, Any]) -> str:
    """How clearly the ends were identified with nodes (identity.py)."""
    rows = [r["identity"] for r in st.get("levels", []) if "identity" in r]
    if not rows:
        return ""
    undecided = sum(r["undecided"] for r in rows)
    margin = rows[0]["margin"]
    if not undecided:
        # no measured ratio in the words: they differ in the last digits between machines
        return (f"Every one of the {sum(r['ends'] for r in rows):,} end points was identified with a margin of "
                f"{margin:g} on both sides (each within 1/{margin:g} of its window of the node it joined, and "
                f"every other node more than {margin:g} windows away).")
    return (f"**{undecided} end point(s) were identified without that margin** (undecided: within "
            f"{margin:g} windows of a node they did not join, or further than 1/{margin:g} of the window from "
            "the node they joined); they are listed with their distances in the stats' levels (`identity`).")


def require_output_modules() -> None:
    """Check that write() can write every file (atlas.graphml needs networkx,
    the PNGs matplotlib); ImportError naming the extras if not, before
    anything is done."""
    require_extras("the atlas's files", OUTPUT_MODULES)


class _Phases:
    """Progress of write(): one phase per file. progress True: a line on
    stderr as each file starts (what it holds) and as it is done (its size
    and seconds), so a long write is never silent; a callable gets
    (files done, files in all, what) before each file and at the end."""

    def __init__(self, progress: Any, total: int) -> None:
        self.progress, self.total, self.done = progress, total, 0

    @contextlib.contextmanager
    def phase(self, path: pathlib.Path, what: str) -> Iterator[None]:
        if callable(self.progress):
            self.progress(self.done, self.total, f"{path.name}: {what}")
        elif self.progress is True:
            print(f"[write] {path.name} ({self.done + 1}/{self.total}): {what} ...", file=sys.stderr, flush=True)
        t = time.perf_counter()
        yield
        self.done += 1
        if self.progress is True:
            size = path.stat().st_size if path.exists() else 0
            print(f"[write] {path.name}: {size / 1e6:,.1f} MB in {time.perf_counter() - t:.1f} s",
                  file=sys.stderr, flush=True)
        elif callable(self.progress) and self.done == self.total:
            self.progress(self.done, self.total, "written")


def write(atlas: _atlas.Atlas, out: Union[str, os.PathLike[str]], map_png: str = "atlas_map.png",
          nodes_png: str = "atlas_nodes.png", graphml: str = "atlas.graphml",
          json_name: str = "atlas.json", html: Optional[str] = None, progress: Any = None) -> pathlib.Path:
    """Write json_name, graphml, the PNGs, report.md and (if html names it)
    the viewer page (atlas/html.py, needs plotly) into the folder out,
    committed whole: written aside and made out's outputs in one step (a
    staging folder swapped with out, or in place the switch of a link; out's
    other files and folders are kept); on a failure out is as it was
    (libkin.atomic.staged_folder). Returns the path of report.md. ImportError (nothing written) without
    networkx or matplotlib. progress: None, True (a line on stderr as each
    file starts and ends) or a callable (files done, files in all, what)."""
    require_output_modules()
    if html:
        from .html import require_plotly
        require_plotly()
    from . import plot as atlas_plot
    out = pathlib.Path(out)
    # the five files are written aside and take their place together: a
    # reader never sees a new atlas.json next to an old report, and a
    # failure leaves the folder as it was (libkin.atomic.staged_folder)
    nsamples = sum(len(e.samples) for e in atlas.edges)
    held = f"{len(atlas.nodes):,} nodes, {len(atlas.edges):,} paths, {nsamples:,} samples"
    ph = _Phases(progress, 6 if html else 5)
    with staged_folder(out) as stage:
        with ph.phase(stage / json_name, held):
            atlas.to_json(stage / json_name)
        with ph.phase(stage / graphml, held):
            atlas.to_graphml(stage / graphml)
        with ph.phase(stage / map_png, "the map"):
            atlas_plot.draw_map(atlas, stage / map_png)
        with ph.phase(stage / nodes_png, "the nodes' configurations"):
            atlas_plot.draw_nodes(atlas, stage / nodes_png)
        if html:
            from . import html as atlas_html
            with ph.phase(stage / html, f"the viewer page, {held}"):
                atlas_html.write(atlas, stage / html, progress=progress is True)
        with ph.phase(stage / "report.md", "the report"):
            write_text(stage / "report.md", text(atlas, map_png, nodes_png, graphml, json_name, html=html))
    return out / "report.md"


def text(atlas: _atlas.Atlas, map_png: str = "atlas_map.png", nodes_png: str = "atlas_nodes.png",
         graphml: str = "atlas.graphml", json_name: str = "atlas.json", max_listed: int = 40,
         html: Optional[str] = None) -> str:
    """report.md's text. Atlases of more than max_listed nodes (or path
    groups) get counts of all of them and a table of the max_listed that
    most paths reach."""
    m = atlas.model
    st, se = atlas.stats, atlas.settings
    n0 = atlas.nodes[0]
    nb = len(m["bars"])
    nj = len(m["joints"])
    L = []
    L.append(f"# Atlas of {m.get('name', 'model')}\n")
    L.append(f"{m['dimension']}D, {nj} joints, {nb} bars. Start: a {n0.kind.replace('_', '-')} point with "
             f"m = {n0.m} internal mechanisms ({n0.m_rigid} rigid), s = {n0.s} self-stresses.\n")
    L.append(f"Explored to depth {se['depth']} (max {se['max_nodes']} nodes, path length budget "
             f"{_f(se['max_length'])} per branch, symmetric = {se['symmetric']}) in {_f(st['seconds'], '.3g')} s "
             f"on {se['executor'] or 'one process'}"
             + (f"; stopped by {st['stopped_by']}" if st.get("stopped_by") else "") + ".\n")
    nk = ", ".join(f"{v} {k.replace('_', '-')}" for k, v in sorted(st["node_kinds"].items()))
    ek = ", ".join(f"{v} {k.replace('_', '-')}" for k, v in sorted(st["edge_events"].items()))
    L.append(f"**{st['nodes']} nodes** ({nk}); **{st['edges']} directed paths** ending in: {ek}.\n")
    if str(se.get("symmetries", "")).startswith("not detected"):
        L.append(f"**Symmetries {se['symmetries']}**: the atlas is explored as if the structure had none.\n")
    L.append("Files: " + ", ".join(f"`{x}`" for x in (json_name, graphml, map_png, nodes_png)) + ".\n")
    if html:
        L.append(f"**[{html}]({html})**: the atlas to walk in a browser (offline, one file): every node on a map "
                 "that pans, zooms and filters by kind, event, m, s, depth and orbit; a click on a node shows its "
                 "configuration in 3D, a click on a path moves the structure along it.\n")
    L.append(f"![map]({map_png})\n")
    L.append("## What the nodes are\n")
    L.append("A node is a configuration where a path ended or started. Its kind comes from the analysis "
             "there, not from how the path got there: *bifurcation* (m >= 2 internal mechanisms and s >= 1 "
             "self-stress: paths cross), *regular* (m = 1: one path passes; the start, or where the length "
             "budget ran out), *near-miss* (the follower stopped at a dip of v_r, but m = 1 here), "
             "*multi-dof* (m >= 2 with s = 0), *rigid* (m = 0), *failure* (following failed). Two "
             "end points are one node when their coordinates agree to "
             f"{_f(se['same_tol'], '.1e')} plus the error bound of each (10 sqrt(tol) times the model size for "
             "a point located to v_r <= tol v_max; up to the rigid motions the supports allow); a node that is "
             "the image of an earlier one under a symmetry of the structure is marked so and not "
             "expanded again (its paths are the images of the earlier node's). "
             + identity_sentence(st) + "\n")
    nout = collections.Counter(e.source for e in atlas.edges)
    nin = collections.Counter(e.target for e in atlas.edges)
    listed = atlas.nodes
    if len(atlas.nodes) > max_listed:
        from .condense import condense
        view, _ = condense(atlas, max_listed)
        keep = {n.id for n in view.nodes}
        listed = [n for n in atlas.nodes if n.id in keep]
        L.append(f"The atlas has {len(atlas.nodes):,} nodes; by kind and counts (all of them):\n")
        L.append("| kind | m | s | nodes | up to symmetry | paths arriving |")
        L.append("|---|---|---|---|---|---|")
        rows: Dict[Tuple[str, int, int], List[_atlas.Node]] = {}
        for n in atlas.nodes:
            rows.setdefault((n.kind, n.m, n.s), []).append(n)
        for (k, m_, s_), ns in sorted(rows.items(), key=lambda kv: (-len(kv[1]), kv[0])):
            L.append(f"| {k.replace('_', '-')} | {m_} | {s_} | {len(ns):,} | {len({n.orbit for n in ns}):,} | "
                     f"{sum(nin.get(n.id, 0) for n in ns):,} |")
        L.append("")
        L.append(f"The {len(listed)} nodes listed below are the start, the expanded nodes and the orbits most "
                 "paths arrive at (the map shows the same ones; the others are merged there); every node is in "
                 f"`{json_name}`.\n")
    L.append("| node | kind | m | s | v_r/v_max | located to | depth | orbit | paths in | paths out | status |")
    L.append("|---|---|---|---|---|---|---|---|---|---|---|")
    for n in listed:
        L.append(f"| N{n.id} | {n.kind.replace('_', '-')} | {n.m} | {n.s} | {_f(n.v_r_rel, '.2e')} | {_f(n.located_v_r, '.1e') if n.depth and n.kind != 'regular' else '-'} | {n.depth} | "
                 f"N{n.orbit} | {nin.get(n.id, 0)} | {nout.get(n.id, 0)} | {n.status} |")
    L.append("")
    L.append("v_r/v_max: the lowest non-zero singular value of the equilibrium matrix (relative to the largest) "
             "at the node, at the rank tolerance; located to: the vanishing singular value (relative) where "
             "the follower located the event.\n")
    L.append("## Branch enumeration at the expanded nodes\n")
    for n in atlas.nodes:
        if not n.expanded or not n.branches:
            continue
        b = n.branches
        acc = b.get("accounting")
        extra = ""
        if acc:
            extra = (f"; homotopy: {acc.get('paths')} paths, {acc.get('real_distinct')} distinct real, "
                     f"{acc.get('nonreal')} non-real, {acc.get('singular')} singular, {acc.get('failed')} failed")
            if "proven_real" in acc:
                extra += (f" (proven: {acc['proven_real']} real, {acc['proven_nonreal']} non-real, "
                          f"{acc['unproven']} unproven)")
        if b.get("combined"):
            extra += f"; more equations than unknowns: {b['combined']}, {b.get('candidates')} candidate(s) checked"
        if b.get("mode") == "symmetric":
            extra += f"; symmetric subspace k = {b.get('k')} (stabilizer of order {b.get('group_order')})"
        L.append(f"- N{n.id}: {b.get('mode')}, {b.get('solutions', 0)} solution(s) beta -> "
                 f"{2 * b.get('solutions', 0)} directed branches{extra}."
                 + (f" {b['reason']}." if b.get("reason") else ""))
    L.append("")
    L.append("## Paths\n")
    L.append("Grouped by end points and event; lengths are path lengths (sum of chords).\n")
    L.append("| from | to | event | paths | (solution, sign) | length |")
    L.append("|---|---|---|---|---|---|")
    groups: Dict[Tuple[int, int, str], List[_atlas.Edge]] = {}
    for e in atlas.edges:
        groups.setdefault((e.source, e.target, e.event), []).append(e)
    shown = sorted(groups.items())
    if len(shown) > max_listed:
        shown = sorted(sorted(groups.items(), key=lambda kv: (-len(kv[1]), kv[0]))[:max_listed])
    for (s, t, ev), es in shown:
        ls = [e.length for e in es]
        lr = _f(min(ls)) if np.ptp(ls) < 1e-9 * max(1.0, max(ls)) else f"{_f(min(ls))} - {_f(max(ls))}"
        who = ", ".join(f"({e.solution}, {'+' if e.sign > 0 else '-'})" for e in es[:8])
        if len(es) > 8:
            who += ", ..."
        L.append(f"| N{s} | N{t} | {ev.replace('_', '-')} | {len(es)} | {who} | {lr} |")
    if len(shown) < len(groups):
        L.append(f"\n(The {len(shown)} groups with the most paths of {len(groups):,}; every path is in `{json_name}`.)")
    L.append("")
    if len(atlas.symmetries) > 1:
        L.append("## Symmetries\n")
        npr = sum(1 for g in atlas.symmetries if g.proper)
        L.append(f"{len(atlas.symmetries)} symmetries of the structure ({npr} rotations, "
                 f"{len(atlas.symmetries) - npr} reflections), found at the start and at the expanded nodes: "
                 "permutations of the joints that keep bars, rest lengths and supports, each with an isometry "
                 "that maps that configuration onto itself (the C library's kin_symmetries: nauty on the bar "
                 "graph, libkin/symmetry/); each maps every configuration to another, so images of a node are "
                 "marked and not explored twice.\n")
        for j, g in enumerate(atlas.symmetries):
            moved = sum(1 for i, p in enumerate(g.perm) if i != p)
            L.append(f"- g{j}: {'rotation' if g.proper else 'reflection'}, moves {moved} joint(s), "
                     f"det Q = {np.linalg.det(g.Q):+.0f}")
        L.append("")
    L.append(f"![configurations of the first nodes (xy projection)]({nodes_png})\n")
    return "\n".join(L) + "\n"
