"""atlas.html without a browser (atlas/html.py): one self-contained page (no
script or style from elsewhere), a valid JSON payload that holds the atlas,
configurations that decode to the atlas's within the page's grid, a layout
that keeps nodes apart, the size budget for samples, a write that is whole
or not at all, and `libkin explore --html`. The browser test is
test_viewer_browser.py."""
import base64
import errno
import html.parser
import json
import os
import pathlib
import sys

import numpy as np
import pytest

from libkin.atlas import Atlas, html as atlas_html
from libkin.atlas.report import write as write_report
from libkin.cli import main

pytest.importorskip("plotly", reason="atlas.html carries plotly.js: pip install plotly")

ROOT = pathlib.Path(__file__).resolve().parents[2]
SQUARE = ROOT / "examples" / "atlas" / "square_sail" / "atlas.json"


@pytest.fixture(scope="module")
def square():
    return Atlas.from_dict(json.loads(SQUARE.read_text()))


class _Scripts(html.parser.HTMLParser):
    """Every <script> (attributes, text) and every attribute that points elsewhere."""

    def __init__(self):
        super().__init__()
        self.scripts, self.links, self._open = [], [], None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        for k in ("src", "href"):
            if k in a:
                self.links.append((tag, k, a[k]))
        if tag == "script":
            self._open = [a, []]

    def handle_data(self, data):
        if self._open is not None:
            self._open[1].append(data)

    def handle_endtag(self, tag):
        if tag == "script" and self._open is not None:
            self.scripts.append((self._open[0], "".join(self._open[1])))
            self._open = None


def _parse(text):
    p = _Scripts()
    p.feed(text)
    p.close()
    return p


def _decode(b64, shape, grid):
    q = np.frombuffer(base64.b64decode(b64), dtype="<i2").reshape(shape)
    return np.asarray(grid["centre"]) + grid["step"] * q


def test_page_is_self_contained_and_carries_the_atlas(square, tmp_path):
    path = tmp_path / "atlas.html"
    atlas_html.write(square, path)
    text = path.read_text(encoding="utf-8")
    p = _parse(text)
    # nothing is loaded from elsewhere: no src or href at all, every script inline
    assert p.links == []
    ids = {a.get("id"): body for a, body in p.scripts}
    assert {"libkin-data", "libkin-configs", "libkin-samples"} <= set(ids)
    assert len(p.scripts) == 5  # the data, two binary blocks, plotly.js, the viewer
    assert any("plotly.js v" in body[:300] for a, body in p.scripts if not a)
    data = json.loads(ids["libkin-data"])
    assert data["format"] == "libkin-atlas-view" and data["version"] == 1
    N, E = len(square.nodes), len(square.edges)
    assert len(data["nodes"]["id"]) == N and len(data["edges"]["source"]) == E
    assert data["summary"] == json.loads(json.dumps(square.summary()))
    for k, n in enumerate(square.nodes):
        assert data["kinds"][data["nodes"]["kind"][k]] == n.kind
        assert (data["nodes"]["m"][k], data["nodes"]["s"][k], data["nodes"]["depth"][k]) == (n.m, n.s, n.depth)
    pos = {n.id: k for k, n in enumerate(square.nodes)}
    for k, e in enumerate(square.edges):
        assert (data["edges"]["source"][k], data["edges"]["target"][k]) == (pos[e.source], pos[e.target])
        assert data["events"][data["edges"]["event"][k]] == e.event
    # the configurations: every node's and every sample, to half a grid step
    J, D = square.nodes[0].coords.shape
    grid = data["grid"]
    tol = 0.5 * grid["step"] * (1 + 1e-9) + 64 * np.finfo(float).eps * np.abs(grid["centre"]).max()
    got = _decode(ids["libkin-configs"], (N, J, D), grid)
    want = np.array([n.coords for n in square.nodes])
    assert np.abs(got - want).max() <= tol
    # each edge's samples, then its own end where it reached a rigidly moved copy of its node (own_end)
    drawn = [list(e.samples) + ([e.end] if e.end is not None else []) for e in square.edges]
    samples = [np.asarray(s) for d in drawn for s in d]
    assert any(e.end is not None for e in square.edges)
    assert data["edges"]["own_end"] == [int(e.end is not None) for e in square.edges]
    assert samples and sum(data["edges"]["samples"]) == len(samples) and grid["samples_dropped"] == 0
    got = _decode(ids["libkin-samples"], (len(samples), J, D), grid)
    assert np.abs(got - np.array(samples)).max() <= tol
    k = 0
    for i, d in enumerate(drawn):  # each edge's samples where its record says
        assert data["edges"]["sample_start"][i] == k
        k += len(d)


def test_text_cannot_end_a_script(square):
    """A status or a model name with '</script>' in it stays data."""
    evil = "</script><script>alert(1)</script>"
    at = Atlas(dict(square.model, name=evil), square.nodes, square.edges, square.symmetries,
               square.settings, square.stats)
    at.nodes[0].status, old = evil, at.nodes[0].status
    try:
        text = atlas_html.page(at)
    finally:
        at.nodes[0].status = old
    p = _parse(text)
    assert len(p.scripts) == 5
    data = json.loads(dict((a.get("id"), b) for a, b in p.scripts)["libkin-data"])
    assert evil in data["statuses"] and data["model"]["name"] == evil
    assert "<title>Atlas of &lt;/script&gt;&lt;script&gt;" in text and "<script>alert" not in text


def test_layout_keeps_nodes_apart_on_their_rings(square):
    sys.path.insert(0, str(pathlib.Path(__file__).parent))
    from atlas_synthetic import replicate
    for at in (square, replicate(square, 5000)):
        x, y = atlas_html.layout(at)
        r = np.hypot(x, y)
        depth = np.array([n.depth for n in at.nodes])
        assert np.isfinite(x).all() and np.isfinite(y).all()
        assert r[depth == 0].max() < 0.31  # the start at the centre
        for d in range(1, depth.max() + 1):
            ring = r[depth == d]
            assert ring.min() >= d - 1e-12 and ring.max() <= d + atlas_html.RING_WIDTH + 1e-12
        # no two nodes on one spot
        P = np.round(np.c_[x, y] / 1e-6).astype(np.int64)
        assert len({tuple(p) for p in P}) == len(at.nodes)


def test_samples_beyond_the_budget_are_thinned(square):
    J, D = square.nodes[0].coords.shape
    # an edge's own end (Edge.end) is always kept: the path is drawn to where it went
    total = sum(len(e.samples) for e in square.edges)
    ends = [int(e.end is not None) for e in square.edges]
    assert min(len(e.samples) for e in square.edges) >= 2 and 0 < sum(ends) < len(ends)
    room = (len(square.edges) + sum(ends)) * J * D  # one sample each besides the ends
    data, _, blob = atlas_html.payload(square, max_sample_values=room)
    assert data["edges"]["samples"] == [1 + k for k in ends]
    assert data["grid"]["samples_dropped"] == total - len(square.edges)
    assert len(blob) == room * 2
    data, _, blob = atlas_html.payload(square, max_sample_values=0)
    assert data["edges"]["samples"] == ends and len(blob) == sum(ends) * J * D * 2
    assert data["grid"]["samples_dropped"] == total


def test_write_is_whole_or_not_at_all(square, tmp_path, monkeypatch):
    path = tmp_path / "atlas.html"
    path.write_text("the previous page")

    def full_disk(fd, data):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
    monkeypatch.setattr(os, "write", full_disk)
    with pytest.raises(OSError):
        atlas_html.write(square, path)
    monkeypatch.undo()
    assert path.read_text() == "the previous page" and sorted(os.listdir(tmp_path)) == ["atlas.html"]


def test_bad_input(square, monkeypatch):
    with pytest.raises(ValueError):
        atlas_html.page(Atlas(square.model, [], [], [], square.settings, square.stats))
    monkeypatch.setitem(sys.modules, "plotly", None)  # as if not installed
    with pytest.raises(ImportError, match="viewer"):
        atlas_html.page(square)


def test_explore_html_writes_the_page_with_the_report(tmp_path):
    out = tmp_path / "atl"
    assert main(["explore", "threebar:RC", "--depth", "1", "--out", str(out), "--quiet", "--html"]) == 0
    page = (out / "atlas.html").read_text(encoding="utf-8")
    atlas = json.loads((out / "atlas.json").read_text())
    data = json.loads(dict((a.get("id"), b) for a, b in _parse(page).scripts)["libkin-data"])
    assert len(data["nodes"]["id"]) == len(atlas["nodes"]) and len(data["edges"]["id"]) == len(atlas["edges"])
    assert "(atlas.html)" in (out / "report.md").read_text()
    assert "atlas.html" in json.loads((out / ".libkin-manifest.json").read_text())["files"]


def test_report_without_html_writes_no_page(square, tmp_path):
    write_report(square, tmp_path / "r")
    assert not (tmp_path / "r" / "atlas.html").exists()
    assert "atlas.html" not in (tmp_path / "r" / "report.md").read_text()


def test_explore_html_refuses_without_plotly_before_any_work(tmp_path, monkeypatch, capsys):
    from libkin.atlas import explorer
    started = []
    monkeypatch.setattr(explorer, "explore", lambda *a, **k: started.append(1))
    monkeypatch.setitem(sys.modules, "plotly", None)
    out = tmp_path / "atl"
    assert main(["explore", "threebar:RC", "--out", str(out), "--quiet", "--html"]) == 1
    assert not started and not out.exists()
    assert "plotly" in capsys.readouterr().err
