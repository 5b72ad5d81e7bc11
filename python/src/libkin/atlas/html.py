"""atlas.html: one self-contained page to walk an atlas in a browser.

`libkin explore ... --html` (and the sail study's report) writes it. The page
works offline: it carries plotly.js inline (taken from the installed plotly
package, never from a network), the viewer's own script and style (viewer.js
and viewer.css next to this module) and the atlas itself as data:

- the graph: per node its place on the map (computed here, layout()), kind,
  m, s, depth, orbit, v_r, status, and its compactness and contact (shape():
  x-y extent, height, clearance, contact); per edge its ends, event,
  length, solution and sign; how deep the run went and why it stopped
  (reach());
- the configurations (every node's, and the samples along every edge, with
  the edge's own end where it reached a rigidly moved copy of its target
  node, Edge.end, flagged own_end) as 16-bit integers on one grid (about 3e-5 of the model's extent), in base64;
  the page decodes only what a click needs.

The map is drawn with WebGL (plotly's scattergl), so tens of thousands of
nodes and paths pan and zoom smoothly; a click on a node draws its
configuration in 3D (rotatable), a click on a path animates the structure
along it, from the source through the edge's samples to the target (or
to its own end), on the curve frames.py describes; the 3D box is fitted
to every frame of that curve.
"""
from __future__ import annotations

import base64
import collections
import html as _html
import json
import math
import os
import sys
import time
from importlib import resources
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
from numpy.typing import NDArray

from ..atomic import write_text
from . import model as _atlas
from . import tasks

# the page carries at most this many sample coordinates (16-bit each):
# beyond it every edge keeps as many evenly spaced samples as fit (none:
# the animation goes straight from the source to the target)
MAX_SAMPLE_VALUES = 8_000_000
# the width of a depth's ring of nodes (rings are one unit apart)
RING_WIDTH = 0.55
FORMAT = "libkin-atlas-view"


def require_plotly() -> None:
    """ImportError naming the extra when plotly (whose plotly.js the page
    carries) is not installed."""
    try:
        import plotly  # noqa: F401
    except ImportError:
        raise ImportError("atlas.html carries plotly.js from the plotly package: "
                          "pip install 'libkin[viewer]' (or plotly)") from None


def parents(atlas: _atlas.Atlas) -> NDArray[np.int64]:
    """For each node (by position in atlas.nodes) the position of the node it
    was first reached from (the source of the first edge into it from a
    smaller depth), -1 for none."""
    pos = {n.id: k for k, n in enumerate(atlas.nodes)}
    depth = [n.depth for n in atlas.nodes]
    par = np.full(len(atlas.nodes), -1, dtype=np.int64)
    for e in atlas.edges:
        s, t = pos.get(e.source), pos.get(e.target)
        if s is None or t is None or s == t or par[t] >= 0:
            continue
        if depth[s] < depth[t]:
            par[t] = s
    return par


def layout(atlas: _atlas.Atlas) -> Tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(x, y) of every node: the start at the centre, the nodes of depth d on
    a ring of radius d (an annulus RING_WIDTH wide when they are many),
    ordered by the angle of the node they were first reached from, then by
    kind, m, s and orbit, so that the members of an orbit sit side by side;
    on the first ring a sector holds one class (kind, m, s), with a gap
    before the next.""" 
    nodes = atlas.nodes
    N = len(nodes)
    x, y = np.zeros(N), np.zeros(N)
    ang = np.zeros(N)
    par = parents(atlas)
    kind_rank = {k: i for i, k in enumerate(_atlas.NODE_KINDS)}
    by_depth: Dict[int, List[int]] = collections.defaultdict(list)
    for k, n in enumerate(nodes):
        by_depth[n.depth].append(k)
    for d in sorted(by_depth):
        ks = by_depth[d]
        if d == 0 and len(ks) == 1:
            continue  # the start: the centre
        r0 = float(d) if d > 0 else 0.3

        def key(k: int) -> Tuple[float, int, int, int, int, int]:
            n = nodes[k]
            pa = float(ang[par[k]]) if d >= 2 and par[k] >= 0 else 0.0
            return (round(-pa, 9), kind_rank.get(n.kind, 99), n.m, n.s, n.orbit, n.id)
        ks.sort(key=key)
        n_at = len(ks)
        rows = 1 if n_at <= 80 else max(1, int(round(math.sqrt(n_at * RING_WIDTH / (2 * math.pi * max(r0, 0.3))))))
        gap = max(1, int(0.004 * n_at / rows))  # columns left empty between classes
        col = np.zeros(n_at, dtype=np.int64)
        row = np.zeros(n_at, dtype=np.int64)
        c, r, prev = 0, 0, None
        for i, k in enumerate(ks):
            # the first level groups by class (kind, m, s), each after a gap;
            # the deeper ones follow the angle of the node they came from
            cls = key(k)[1:4] if d <= 1 else None
            if prev is not None and cls != prev:
                c, r = c + 1 + gap, 0
            elif r == rows:
                c, r = c + 1, 0
            col[i], row[i] = c, r
            r += 1
            prev = cls
        ncol = int(col[-1]) + 1 + gap  # and a gap before the first column again
        theta = 0.5 * math.pi - 2 * math.pi * (col + 0.5) / ncol
        rad = r0 + (RING_WIDTH * row / (rows - 1) if rows > 1 else 0.0)
        idx = np.asarray(ks)
        ang[idx] = theta
        x[idx], y[idx] = rad * np.cos(theta), rad * np.sin(theta)
    return x, y


# a node whose smallest clearance between parts sharing no joint is at most
# this times the RMS bar length is in contact (as the follower's contact events)
CONTACT_TOL = 1e-6
# clearances are resolved up to this times the model size (kin_clearance's
# cutoff: much cheaper); larger ones are shown as "over" it
CLEARANCE_CUTOFF = 0.25


def shape(atlas: _atlas.Atlas, progress: bool = False) -> Dict[str, List[Optional[float]]]:
    """Per node (by position): "xy_extent" (the radius of the package seen
    from above: the largest distance of a joint from the vertical axis
    through the start's x-y centroid, as the sail study measures it: its
    hub is there), "height" (the z extent; 0 for
    a plane model), "clearance" (the smallest clearance between parts that
    share no joint, kin_clearance, None where above CLEARANCE_CUTOFF times
    the model size or not measurable) and "contact" (1 where the clearance
    is within CONTACT_TOL of the RMS bar length or a path ended there in
    contact). progress: a line on stderr every few seconds (how many are done)."""
    from ..assembly import Assembly
    from ..errors import KinError
    nodes = atlas.nodes
    contact_in = {e.target for e in atlas.edges if e.event == tasks.CONTACT}
    try:
        a: Optional[Assembly] = Assembly.from_json(atlas.model)
    except (KinError, ValueError, TypeError, KeyError):
        a = None
    rms = float(np.sqrt(np.mean(a.rest_lengths ** 2))) if a is not None and a.nbars else 0.0
    size, axis = 1.0, np.zeros(2)
    if nodes:
        c0 = np.asarray(nodes[0].coords, dtype=float)
        size = max(1e-300, float(np.abs(c0 - c0.mean(axis=0)).max()))
        axis = c0[:, :2].mean(axis=0)
    out: Dict[str, List[Optional[float]]] = {"xy_extent": [], "height": [], "clearance": [], "contact": []}
    bar = _Ticker(progress, len(nodes), "the viewer's nodes measured (shape, clearance)")
    for k, n in enumerate(nodes):
        bar.update(k)
        X = np.asarray(n.coords, dtype=float)
        xy = X[:, :2]
        out["xy_extent"].append(float(np.hypot(*(xy - axis).T).max()) if np.isfinite(xy).all() else None)
        out["height"].append(float(np.ptp(X[:, 2])) if X.shape[1] > 2 and np.isfinite(X).all() else 0.0)
        c: Optional[float] = None
        if a is not None and np.isfinite(X).all():
            try:
                v = a.clearance(X, cutoff=CLEARANCE_CUTOFF * size).value
                c = float(v) if math.isfinite(v) else None
            except KinError:
                c = None
        out["clearance"].append(c)
        touching = n.id in contact_in or (c is not None and c <= CONTACT_TOL * max(rms, 1e-300))
        out["contact"].append(1.0 if touching else 0.0)
    bar.close()
    return out


class _Ticker:
    """Lines on stderr while a loop over many items runs: "k of N" at most
    every TICK seconds (none for a loop that ends sooner), then the last."""
    TICK = 5.0

    def __init__(self, on: bool, total: int, what: str) -> None:
        self.on, self.total, self.what = on, total, what
        self.t = time.perf_counter()
        self.said = False

    def update(self, k: int) -> None:
        if self.on and time.perf_counter() - self.t >= self.TICK:
            print(f"[write] {self.what}: {k:,} of {self.total:,}", file=sys.stderr, flush=True)
            self.t, self.said = time.perf_counter(), True

    def close(self) -> None:
        if self.on and self.said:
            print(f"[write] {self.what}: {self.total:,} of {self.total:,}", file=sys.stderr, flush=True)


def reach(atlas: _atlas.Atlas) -> Dict[str, Any]:
    """How deep the run went and why it stopped there: "depth" asked for,
    "reached" (the deepest node's depth), "stopped" (limits.limits_hit's
    sentences: which limit stopped it and how to lift it, and whether it
    was interrupted; empty when nothing did)."""
    from .limits import limits_hit
    stopped = list(limits_hit(atlas).values())
    if atlas.stats.get("stopped_by") == "interrupted":  # a signal or a stop: no limit sentence says it
        stopped.append("interrupted: the atlas so far (partial); continue with --resume")
    return {"depth": atlas.settings.get("depth"), "reached": max((n.depth for n in atlas.nodes), default=0),
            "stopped": stopped}


def _quantise(arrays: Sequence[NDArray[np.float64]], centre: NDArray[np.float64], step: float) -> bytes:
    if not arrays:
        return b""
    q = np.rint((np.asarray(arrays, dtype=np.float64) - centre) / step)
    q = np.nan_to_num(q, nan=0.0)  # a configuration that is not finite is drawn at the centre
    return np.clip(q, -32767, 32767).astype("<i2").tobytes()


def _samples_kept(edges: Sequence[_atlas.Edge], per_config: int, budget: int) -> int:
    """How many samples per edge fit the budget (the most any edge has if all fit)."""
    most = max((len(e.samples) for e in edges), default=0)
    total = sum(len(e.samples) + (e.end is not None) for e in edges) * per_config
    if total <= budget:
        return most
    ends = sum(e.end is not None for e in edges) * per_config  # always kept
    return int(max(0, budget - ends) // max(1, len(edges) * per_config))


def payload(atlas: _atlas.Atlas, names: Optional[Dict[int, str]] = None, title: Optional[str] = None,
            max_sample_values: int = MAX_SAMPLE_VALUES, progress: bool = False) -> Tuple[Dict[str, Any], bytes, bytes]:
    """(data, node configurations, edge samples): the page's JSON payload
    and the two binary blocks (little-endian int16, config after config,
    each joints x dimension values: coordinate = centre + step * value)."""
    nodes, edges = atlas.nodes, atlas.edges
    if not nodes:
        raise ValueError("an atlas without nodes has nothing to show")
    pos = {n.id: k for k, n in enumerate(nodes)}
    J, D = np.asarray(nodes[0].coords).shape
    keep = _samples_kept(edges, J * D, max_sample_values)
    samples: List[NDArray[np.float64]] = []
    s_start: List[int] = []
    s_count: List[int] = []
    own_end: List[int] = []
    for e in edges:
        ss = e.samples
        if len(ss) > keep:
            ss = [ss[int(i)] for i in np.round(np.linspace(0, len(ss) - 1, keep))] if keep else []
        if e.end is not None:  # the path went to a rigidly moved copy of its node: drawn to where it went
            ss = list(ss) + [e.end]
        own_end.append(int(e.end is not None))
        s_start.append(len(samples))
        s_count.append(len(ss))
        samples.extend(np.asarray(s, dtype=np.float64) for s in ss)
    configs = [np.asarray(n.coords, dtype=np.float64) for n in nodes]
    allc = np.concatenate([np.reshape(configs, (-1, D))] + ([np.reshape(samples, (-1, D))] if samples else []))
    finite = np.isfinite(allc).all(axis=1)
    lo = allc[finite].min(axis=0) if finite.any() else np.zeros(D)
    hi = allc[finite].max(axis=0) if finite.any() else np.ones(D)
    centre = 0.5 * (lo + hi)
    step = max(float((hi - lo).max()), 1e-12) / 2.0 / 32000.0
    x, y = layout(atlas)
    statuses: Dict[str, int] = {}
    kinds = list(_atlas.NODE_KINDS)
    events = list(tasks.EVENT_KINDS)
    for n in nodes:
        if n.kind not in kinds:
            kinds.append(n.kind)
    for e in edges:
        if e.event not in events:
            events.append(e.event)
    m = atlas.model
    names = names or {}

    def num(v: float, digits: int = 4) -> Optional[float]:
        return float(f"{v:.{digits}g}") if v is not None and math.isfinite(v) else None
    data: Dict[str, Any] = {
        "format": FORMAT, "version": 1,
        "title": title or f"Atlas of {m.get('name', 'model')}",
        "model": {"name": m.get("name", "model"), "dimension": D, "joints": J,
                  "labels": [j.get("label", str(k)) for k, j in enumerate(m.get("joints", []))],
                  "fixed": [not any(j.get("free", [True])) for j in m.get("joints", [])],
                  "bars": [list(map(int, b["joints"])) for b in m.get("bars", [])]},
        "summary": atlas.summary(),
        "settings": {k: atlas.settings.get(k) for k in ("depth", "max_nodes", "symmetric", "samples", "symmetries")},
        "seconds": atlas.stats.get("seconds"),
        "kinds": kinds, "events": events,
        "nodes": {
            "id": [n.id for n in nodes],
            "name": [names.get(n.id, f"N{n.id}") for n in nodes],
            "x": [round(float(v), 5) for v in x], "y": [round(float(v), 5) for v in y],
            "kind": [kinds.index(n.kind) for n in nodes],
            "m": [int(n.m) for n in nodes], "s": [int(n.s) for n in nodes],
            "depth": [int(n.depth) for n in nodes],
            "orbit": [pos.get(n.orbit, k) for k, n in enumerate(nodes)],
            "v_r": [num(n.v_r_rel, 3) for n in nodes],
            "expanded": [1 if n.expanded else 0 for n in nodes],
            "status": [statuses.setdefault(n.status, len(statuses)) for n in nodes],
            **{k: [num(v, 4) if v is not None else None for v in vs] for k, vs in shape(atlas, progress).items()},
        },
        "reach": reach(atlas),
        "statuses": list(statuses),
        "edges": {
            "id": [e.id for e in edges],
            "source": [pos[e.source] for e in edges], "target": [pos[e.target] for e in edges],
            "event": [events.index(e.event) for e in edges],
            "length": [num(e.length) for e in edges],
            "solution": [int(e.solution) for e in edges], "sign": [int(e.sign) for e in edges],
            "sample_start": s_start, "samples": s_count, "own_end": own_end,
        },
        "grid": {"centre": [float(v) for v in centre], "step": step,
                 "samples_dropped": sum(len(e.samples) + (e.end is not None) for e in edges) - len(samples)},
    }
    return data, _quantise(configs, centre, step), _quantise(samples, centre, step)


def _asset(name: str) -> str:
    return resources.files(__name__.rpartition(".")[0]).joinpath(name).read_text(encoding="utf-8")


def _script_safe(text: str) -> str:
    """Text that cannot end the <script> element it sits in."""
    return text.replace("</", "<\\/")


def page(atlas: _atlas.Atlas, names: Optional[Dict[int, str]] = None, title: Optional[str] = None,
         max_sample_values: int = MAX_SAMPLE_VALUES, progress: bool = False) -> str:
    """The whole HTML page as text (see write())."""
    require_plotly()
    from plotly.offline import get_plotlyjs
    data, node_bytes, sample_bytes = payload(atlas, names, title, max_sample_values, progress)
    # "<" written as its JSON escape: no text of the atlas can open or close a tag
    text = json.dumps(data, separators=(",", ":"), allow_nan=False).replace("<", "\\u003c")
    plotly_js = get_plotlyjs()
    if "</script" in plotly_js.lower():  # never so far; kept safe if it ever is
        plotly_js = plotly_js.replace("</script", "<\\/script").replace("</SCRIPT", "<\\/SCRIPT")
    parts = [
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n",
        "<meta name=\"generator\" content=\"libkin atlas viewer\">\n",
        f"<title>{_html.escape(data['title'])}</title>\n<style>\n{_asset('viewer.css')}\n</style>\n</head>\n",
        _asset("viewer.html"),
        f"<script type=\"application/json\" id=\"libkin-data\">{text}</script>\n",
        "<script type=\"application/octet-stream\" id=\"libkin-configs\">",
        base64.b64encode(node_bytes).decode("ascii"), "</script>\n",
        "<script type=\"application/octet-stream\" id=\"libkin-samples\">",
        base64.b64encode(sample_bytes).decode("ascii"), "</script>\n",
        f"<script>\n{plotly_js}\n</script>\n",
        f"<script>\n{_script_safe(_asset('viewer.js'))}\n</script>\n</body>\n</html>\n",
    ]
    return "".join(parts)


def write(atlas: _atlas.Atlas, path: Union[str, os.PathLike[str]], names: Optional[Dict[int, str]] = None,
          title: Optional[str] = None, max_sample_values: int = MAX_SAMPLE_VALUES, progress: bool = False) -> None:
    """Write the viewer page of atlas to path, whole or not at all
    (libkin.atomic). names: {node id: name} to show instead of N<id> (the
    sail study's R^A, R^B, ...); max_sample_values: how many sample
    coordinates the page may carry (MAX_SAMPLE_VALUES); progress: lines
    on stderr while it measures the nodes. ImportError without plotly,
    ValueError for an atlas without nodes."""
    write_text(path, page(atlas, names, title, max_sample_values, progress))
