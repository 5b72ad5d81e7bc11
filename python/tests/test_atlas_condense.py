"""atlas_condense: a large atlas drawn and reported as a page, every path
still accounted for."""
import json
import pathlib

import numpy as np

from libkin.atlas import plot as atlas_plot
from libkin.atlas import report as atlas_report
from libkin.atlas import Atlas
from libkin.atlas.condense import condense

STORED = pathlib.Path(__file__).resolve().parents[2] / "examples" / "sail_study" / "hex_quick" / "atlas.json"


def _atlas():
    return Atlas.from_dict(json.loads(STORED.read_text()))


def test_small_atlas_is_not_condensed():
    at = _atlas()
    view, labels = condense(at, max_nodes=len(at.nodes))
    assert view is at and labels == {}


def test_condensed_view_keeps_every_path():
    at = _atlas()
    view, labels = condense(at, max_nodes=12)
    kept = [n for n in view.nodes if n.id not in labels]
    assert len(view.nodes) < len(at.nodes)
    # the start and every expanded node stay, then whole orbits up to the budget
    ids = {n.id for n in kept}
    must = {n.id for n in at.nodes if n.depth == 0 or n.expanded}
    assert must <= ids and len(ids) <= max(12, len(must))
    # every path is still there, redirected to a merged node if its end was merged
    assert len(view.edges) == len(at.edges)
    merged_in = sum(1 for e in view.edges if e.target in labels)
    assert merged_in == sum(1 for e in at.edges if e.target not in ids)
    # one merged node per (depth, kind) of the others, its label counting them
    n_merged = sum(int(labels[i].split()[0].lstrip("+").replace(",", "")) for i in labels)
    assert n_merged == len(at.nodes) - len(kept)
    assert len(labels) == len({(n.depth, n.kind) for n in at.nodes if n.id not in ids})


def test_condensed_map_and_report(tmp_path):
    at = _atlas()
    fig = atlas_plot.draw_map(at, tmp_path / "map.png", max_nodes=12)
    h = fig.get_size_inches()[1]
    assert h < atlas_plot.draw_map(at, None, max_nodes=100).get_size_inches()[1]
    txt = atlas_report.text(at, max_listed=12)
    assert "by kind and counts" in txt
    rows = [ln for ln in txt.splitlines() if ln.startswith("| N")]
    assert len(rows) < len(at.nodes) + len(at.edges)
    assert np.isfinite(h)
