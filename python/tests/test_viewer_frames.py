"""The viewer draws what moves (atlas/frames.py, issue 36 item 5): every frame
atlas.html animates between a path's stored configurations (the viewer's
Catmull-Rom curve, frames.catmull, decoded from the page's own 16-bit grid)
keeps each bar within frames.VIEW_STRAIN (1 %) of its length. Before, two
samples per path stretched the parallelogram four-bar's bars by 19 % over a
turn and the square sail's by 92 % (a path that comes back to a rigidly
turned copy of its node was drawn to the node instead). The 3D box fitted
to every frame is checked in the browser (test_viewer_browser.py)."""
import json
import pathlib
import sys

import numpy as np
import pytest

import libkin
from libkin.atlas import Atlas, frames, html as atlas_html

sys.path.insert(0, str(pathlib.Path(__file__).parent))
from test_cli_reports import parallelogram  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]
SQUARE = ROOT / "examples" / "atlas" / "square_sail" / "atlas.json"


def drawn_strains(atlas, rest):
    """Per edge, the largest bar strain of the frames the page animates: its
    keyframes decoded from the page's data as viewer.js does (source, samples,
    target unless the last sample is the path's own end)."""
    data, cb, sb = atlas_html.payload(atlas)
    J, D = data["model"]["joints"], data["model"]["dimension"]
    g = data["grid"]
    grid = lambda b: np.asarray(g["centre"]) + g["step"] * np.frombuffer(b, "<i2").reshape(-1, J, D)  # noqa: E731
    conf, samp = grid(cb), grid(sb)
    bars = np.asarray(data["model"]["bars"])
    E = data["edges"]
    out = []
    for e in range(len(E["id"])):
        a, n = E["sample_start"][e], E["samples"][e]
        own = E.get("own_end", [0] * len(E["id"]))[e]
        fr = [conf[E["source"][e]]] + list(samp[a:a + n]) + ([] if own else [conf[E["target"][e]]])
        out.append(frames.strain(np.stack(fr), bars, rest))
    return np.asarray(out)


def test_catmull_passes_through_its_keyframes():
    rng = np.random.default_rng(3)
    f = rng.normal(size=(5, 4, 3))
    for k in range(4):
        ends = frames.catmull(f, k, [0.0, 1.0])
        assert np.allclose(ends[0], f[k], atol=1e-14) and np.allclose(ends[1], f[k + 1], atol=1e-14)


def test_parallelogram_turns_are_drawn_without_stretching(tmp_path):
    """Depth 3 on the parallelogram four-bar: paths of a whole turn (before:
    2 samples each, bars stretched by up to 19 %)."""
    a = libkin.Assembly.from_json(parallelogram(tmp_path / "p.json"))
    at = libkin.explore(a, depth=3)
    s = drawn_strains(at, a.rest_lengths)
    assert len(s) >= 4 and s.max() <= frames.VIEW_STRAIN
    # the viewer's header: depth reached and why it stopped there
    assert atlas_html.reach(at)["reached"] == max(n.depth for n in at.nodes)


def test_stored_square_sail_is_drawn_without_stretching():
    """examples/atlas/square_sail (before: 92 %)."""
    at = Atlas.from_dict(json.loads(SQUARE.read_text()))
    a = libkin.Assembly.from_json(at.model)
    assert drawn_strains(at, a.rest_lengths).max() <= frames.VIEW_STRAIN


def test_choose_splits_until_the_curve_is_true():
    """A crank turning half a revolution recorded every degree: two evenly
    spread samples strain the drawn bar by far more than 1 %; choose() adds
    recorded points until no segment does, and never more than it needs
    (each added one splits a segment that was over)."""
    th = np.radians(np.arange(1, 180))
    rec = np.stack([np.stack([np.zeros(2), [np.cos(t), np.sin(t)]]) for t in th])
    start, end = np.array([[0.0, 0.0], [1.0, 0.0]]), np.array([[0.0, 0.0], [-1.0, 0.0]])
    bars, rest = np.array([[0, 1]]), np.array([1.0])
    first = [59, 119]
    before = frames.strain(np.stack([start, rec[59], rec[119], end]), bars, rest)
    assert before > 5 * frames.VIEW_STRAIN
    got = frames.choose(start, rec, end, first, bars, rest)
    assert set(first) <= set(got) and got == sorted(got)
    assert frames.strain(np.stack([start] + [rec[i] for i in got] + [end]), bars, rest) <= frames.VIEW_STRAIN
    assert len(got) < 20


def test_cli_samples(tmp_path):
    """`libkin explore --samples N`: none with 0; at least N evenly spread otherwise."""
    from libkin.cli import main
    model = parallelogram(tmp_path / "p.json")
    for n in (0, 5):
        out = tmp_path / f"s{n}"
        assert main(["explore", str(model), "--depth", "2", "--samples", str(n), "--out", str(out), "--quiet"]) == 0
        edges = json.loads((out / "atlas.json").read_text())["edges"]
        assert edges and all((len(e["samples"]) == 0) if n == 0 else (len(e["samples"]) >= n) for e in edges)


def test_viewer_samples_only_where_a_viewer_draws(tmp_path):
    """The viewer's extra samples are stored for atlas.html (--html, or
    explore(view_samples=True), the default of the API) and not otherwise:
    without them `libkin explore` stores the evenly spread samples asked for
    (the hexagonal flat state's depth-2 atlas: 151,000 samples instead of
    1.19 million, docs/atlas.md)."""
    import libkin
    model = parallelogram(tmp_path / "p.json")
    plain = libkin.explore(str(model), depth=2, samples=2, view_samples=False)
    viewed = libkin.explore(str(model), depth=2, samples=2)
    assert plain.settings["view_samples"] is False and viewed.settings["view_samples"] is True
    assert all(len(e.samples) <= 2 for e in plain.edges)
    assert sum(len(e.samples) for e in viewed.edges) > sum(len(e.samples) for e in plain.edges)
    # the same paths either way: only what is stored along them differs
    assert [(e.source, e.target, e.event) for e in plain.edges] == [(e.source, e.target, e.event) for e in viewed.edges]
    from libkin.cli import main
    for html in (False, True):
        out = tmp_path / f"h{int(html)}"
        if html:
            pytest.importorskip("plotly")
        args = ["explore", str(model), "--depth", "2", "--out", str(out), "--quiet"] + (["--html"] if html else [])
        assert main(args) == 0
        edges = json.loads((out / "atlas.json").read_text())["edges"]
        assert (max(len(e["samples"]) for e in edges) > 2) == html
