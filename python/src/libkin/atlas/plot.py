"""The map of an atlas as a picture (matplotlib).

Nodes are laid out in columns by depth (the level at which they were first
reached), grouped by symmetry orbit within a column; the vertical spacing
is set so that the labels, written to the right of each node, never overlap.
Shape and colour say what a node is; a regular point or a near-miss is never
drawn as a bifurcation. Parallel paths are drawn once with their count, a
path and the paths back along it as one line with two heads ("a/b": a
paths one way, b the other); paths within a column are arcs; closed loops
and other paths back to their start are counted in the node's label.
"""
from __future__ import annotations

import os
from typing import Any, Dict, List, Optional, Tuple, Union

import numpy as np

from ..atomic import replacing
from . import model as _atlas

STYLE = {  # kind: (marker, face colour, size, legend text)
    _atlas.BIFURCATION: ("D", "#d62728", 110, "bifurcation (m, s)"),
    _atlas.REGULAR: ("o", "#bbbbbb", 50, "regular point (budget, contact, start)"),
    _atlas.NEAR_MISS: ("^", "#ff7f0e", 80, "near-miss (regular)"),
    _atlas.MULTI_DOF: ("s", "#9467bd", 80, "several freedoms (s = 0)"),
    _atlas.RIGID: ("P", "#333333", 80, "rigid"),
    _atlas.FAILURE: ("X", "#8c564b", 90, "following failed"),
    _atlas.UNDECIDED: ("v", "#bcbd22", 80, "undecided (v_r near its floor, or tangent branches)"),
}
EVENT_COLOUR = {"bifurcation": "#d62728", "near_miss": "#ff7f0e", "loop": "#2ca02c", "budget": "#999999",
                "failure": "#8c564b", "contact": "#e377c2"}


def _label(atlas: _atlas.Atlas, n: _atlas.Node) -> str:
    name = atlas.node_name(n.id)
    if n.kind == _atlas.BIFURCATION:
        txt = f"{name}  m={n.m} s={n.s}"
    elif n.kind == _atlas.NEAR_MISS:
        txt = f"{name}  near-miss, v_r={n.v_r_rel:.1e}"
    elif n.kind == _atlas.REGULAR and n.status.startswith("the path-length budget"):
        txt = f"{name}  regular (budget)"
    else:
        txt = f"{name}  {n.kind.replace('_', '-')}"
    if n.image_of is not None:
        txt += f"  (image of {atlas.node_name(n.image_of['node'])})"
    return txt


def layout(atlas: _atlas.Atlas) -> Dict[int, Tuple[float, float]]:
    """{node id: (x, y)}: x the depth, y the rank within the column (orbit-grouped)."""
    cols: Dict[int, List[_atlas.Node]] = {}
    for n in atlas.nodes:
        cols.setdefault(n.depth, []).append(n)
    pos = {}
    for d, ns in cols.items():
        ns.sort(key=lambda n: (n.orbit, n.id))
        h = len(ns)
        for k, n in enumerate(ns):
            pos[n.id] = (float(d), (h - 1) / 2.0 - k)
    return pos


def draw_map(atlas: _atlas.Atlas, path: Union[None, str, os.PathLike[str]] = None,
             title: Optional[str] = None, max_nodes: int = 40) -> Any:
    """Draw the map; write a PNG to path (if given). Returns the figure.
    An atlas of more than max_nodes nodes is drawn condensed
    (condense.py): its most-reached nodes, the others merged."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    from .condense import condense
    summ = atlas.summary()
    atlas, merged = condense(atlas, max_nodes)

    pos = layout(atlas)
    ncol = max(p[0] for p in pos.values()) + 1
    nrow = max(sum(1 for n in atlas.nodes if n.depth == d) for d in range(int(ncol)))
    # 0.32 inch per row keeps 9 pt labels apart; 4.2 inch per column leaves room for them
    W, H = 2.8 + 4.2 * ncol, 1.2 + 0.32 * max(nrow, 4)
    fig, ax = plt.subplots(figsize=(W, H))
    # fixed margins (not tight_layout): edge-count labels are placed in
    # display coordinates, which must not move afterwards
    fig.subplots_adjust(left=0.2 / W, right=1.0 - 2.6 / W, bottom=0.5 / H, top=1.0 - 0.4 / H)
    ax.set_xlim(-0.3, ncol - 1 + 1.2)
    # a path and the path back along it (reached from the other end) are one
    # line with two heads; what is left to bend is paths within a column
    groups: Dict[Tuple[int, int, str], Dict[Tuple[int, int], List[_atlas.Edge]]] = {}
    for e in atlas.edges:
        key = (min(e.source, e.target), max(e.source, e.target), e.event)
        groups.setdefault(key, {}).setdefault((e.source, e.target), []).append(e)
    same_col = any(pos[a][0] == pos[b][0] and a != b for a, b, _ in groups)
    # arcs within a column bow sideways; leave a little room above and below
    pad = 0.3 + (min(0.1 * nrow, 1.5) if same_col else 0.0)
    ax.set_ylim(-(nrow / 2.0) - pad, nrow / 2.0 + pad)
    loops: Dict[int, int] = {}
    to_data = ax.transData.inverted()
    for (lo, hi, ev), dirs in sorted(groups.items()):
        col = EVENT_COLOUR.get(ev, "k")
        if lo == hi:
            loops[lo] = loops.get(lo, 0) + len(dirs[(lo, lo)])
            continue
        # draw from the node further left (or higher up) to the other
        s, t = sorted((lo, hi), key=lambda i: (pos[i][0], -pos[i][1]))
        fwd, bwd = len(dirs.get((s, t), [])), len(dirs.get((t, s), []))
        (x0, y0), (x1, y1) = pos[s], pos[t]
        rad = 0.0 if x1 != x0 else 0.35
        style = "<|-|>" if fwd and bwd else ("-|>" if fwd else "<|-")
        ax.annotate("", xy=(x1, y1), xytext=(x0, y0),
                    arrowprops=dict(arrowstyle=style, color=col, lw=0.8 + 0.3 * min(fwd + bwd, 4), alpha=0.7,
                                    shrinkA=6, shrinkB=7, connectionstyle=f"arc3,rad={rad}"))
        if fwd + bwd > 1:
            # the count sits on the edge: near the end of a straight edge
            # (where edges fan apart), at the middle of an arc (arc3 bends
            # in display space: its Bezier midpoint is the chord's middle
            # moved by rad/2 times the chord turned by -90 degrees)
            p0, p1 = ax.transData.transform((x0, y0)), ax.transData.transform((x1, y1))
            if rad == 0.0:
                q = p0 + 0.8 * (p1 - p0)
            else:
                d = p1 - p0
                q = 0.5 * (p0 + p1) + 0.5 * rad * np.array([d[1], -d[0]])
            fx, fy = to_data.transform(q)
            txt = f"{fwd}/{bwd}" if fwd and bwd else f"\u00d7{fwd + bwd}"
            ax.text(fx, fy, txt, fontsize=7, color=col, ha="center", va="center",
                    bbox=dict(boxstyle="round,pad=0.1", fc="white", ec="none", alpha=0.8))
    for n in atlas.nodes:
        mk, fc, sz, _ = STYLE[n.kind]
        x, y = pos[n.id]
        ax.scatter([x], [y], marker=mk, s=sz, c=fc, edgecolors="k", linewidths=1.8 if n.id == 0 else 0.6,
                   zorder=3)
        txt = merged.get(n.id) or _label(atlas, n)
        if n.id in loops:
            txt += f"  [{loops[n.id]} path(s) back to itself]"
        ax.text(x + 0.06, y, txt, fontsize=8.5, va="center", ha="left", zorder=4,
                bbox=dict(boxstyle="square,pad=0.05", fc="white", ec="none", alpha=0.75))
    kinds = sorted({n.kind for n in atlas.nodes}, key=list(STYLE).index)
    handles = [Line2D([], [], marker=STYLE[k][0], color="w", markerfacecolor=STYLE[k][1], markeredgecolor="k",
                      markersize=8, label=STYLE[k][3]) for k in kinds]
    events = sorted({e.event for e in atlas.edges})
    handles += [Line2D([], [], color=EVENT_COLOUR.get(ev, "k"), label=f"path ending in: {ev.replace('_', '-')}")
                for ev in events]
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8, frameon=False)
    ax.set_xticks(range(int(ncol)))
    ax.set_xticklabels(["start"] + [f"depth {d}" for d in range(1, int(ncol))])
    ax.set_yticks([])
    for side in ("left", "right", "top"):
        ax.spines[side].set_visible(False)
    ax.set_title(title or f"atlas of {atlas.model.get('name', 'model')}: {summ['nodes']:,} nodes, "
                          f"{summ['edges']:,} directed paths"
                          + (f"\n({len(atlas.nodes) - len(merged)} shown: the start, the expanded nodes and "
                             "the most reached; the others merged by depth and kind)" if merged else ""), fontsize=10)
    if path is not None:
        try:
            with replacing(path) as tmp:  # whole or not at all
                fig.savefig(tmp, dpi=110)
        finally:
            plt.close(fig)
    return fig


def draw_nodes(atlas: _atlas.Atlas, path: Union[str, os.PathLike[str]], limit: int = 12) -> None:
    """The configurations of the first `limit` nodes (xy projection), a panel
    each, all on the same scale; joints shown as dots (folded bars overlap)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    bars = np.array([b["joints"] for b in atlas.model["bars"]])
    ns = atlas.nodes[:limit]
    cols = min(4, len(ns))
    rows = (len(ns) + cols - 1) // cols
    fig, axs = plt.subplots(rows, cols, figsize=(3.0 * cols, 3.0 * rows), squeeze=False)
    for ax in axs.ravel():
        ax.axis("off")
    # one frame for every panel, padded: flat and folded configurations
    # (zero extent in y) keep their scale and stay visible
    allxy = np.vstack([n.coords[:, :2] for n in ns])
    mid = 0.5 * (allxy.min(axis=0) + allxy.max(axis=0))
    half = 0.54 * max(float((allxy.max(axis=0) - allxy.min(axis=0)).max()), 1e-9)
    lo, hi = mid - half, mid + half
    for ax, n in zip(axs.ravel(), ns):
        X = n.coords
        for i, j in bars:
            ax.plot(X[[i, j], 0], X[[i, j], 1], "-", color="#1f77b4", lw=1)
        ax.plot(X[:, 0], X[:, 1], "k.", ms=3)
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[1], hi[1])
        ax.set_aspect("equal")
        ax.set_title(_label(atlas, n), fontsize=7)
    fig.tight_layout()
    try:
        with replacing(path) as tmp:  # whole or not at all
            fig.savefig(tmp, dpi=100)
    finally:
        plt.close(fig)
