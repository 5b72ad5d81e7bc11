"""Node identity with a margin (issue 35 item 4, atlas/identity.py): an end
joins a node within the pair window w, and the decision is reported as
decided only with a factor IDENTITY_MARGIN of room on both sides: an end
moved to a few windows from its node (where another machine's rounding
could put it on either side) is counted and listed as undecided, in the
stats and the report; an end moved far away starts a node of its own,
decided; the unperturbed atlas has no undecided end."""
import numpy as np
import pytest

import libkin
from libkin.atlas import explorer, report
from libkin.atlas.identity import IDENTITY_MARGIN
from libkin.atlas.model import pair_window

SPEC = "sail:4:1"


def _explore(monkeypatch, factor):
    """explore(SPEC, depth 2) with the first non-loop end of level 1 moved
    by factor x its own pair window along one free coordinate (None: as
    computed)."""
    real = explorer.follow_level
    moved = []

    def follow_level(work, images, follow, syms, bars, take=None):
        def take_moved(k, res):
            if factor is not None and res is not None and not moved and res["event"] != "loop":
                X = np.array(res["coords"], dtype=float)
                scale = max(1.0, float(np.abs(X - X.mean(axis=0)).max()))
                tol = float(res.get("vr_tol", 0.0))
                j = int(np.argmax(np.abs(X - X.mean(axis=0)).max(axis=1)))  # a joint that moves
                X[j, -1] += factor * pair_window(scale, tol, tol)
                res = dict(res, coords=X.tolist())
                moved.append(k)
            take(k, res)
        return real(work, images, follow, syms, bars, take_moved)
    monkeypatch.setattr(explorer, "follow_level", follow_level)
    at = libkin.explore(SPEC, depth=2, samples=0, view_samples=False)
    return at, moved


def test_the_unperturbed_atlas_is_decided(monkeypatch):
    at, _ = _explore(monkeypatch, None)
    assert at.stats["identity_undecided"] == 0
    rows = [r["identity"] for r in at.stats["levels"]]
    assert all(r["worst_join_ratio"] <= 1.0 / IDENTITY_MARGIN for r in rows)
    assert "identified with a margin" in report.text(at)


@pytest.mark.parametrize("factor", [0.5, 3.0])
def test_an_end_near_the_window_is_undecided(monkeypatch, factor):
    ref, _ = _explore(monkeypatch, None)
    at, moved = _explore(monkeypatch, factor)
    assert moved
    assert at.stats["identity_undecided"] >= 1
    listed = [u for r in at.stats["levels"] for u in r["identity"]["undecided_ends"]]
    assert any(u["work"] == moved[0] for u in listed)
    u = next(u for u in listed if u["work"] == moved[0])
    # the numbers say why: joined at more than 1/margin of its window, or another node within margin windows
    assert (u["joined_ratio"] is not None and u["joined_ratio"] > 1.0 / IDENTITY_MARGIN) \
        or u["nearest_other_ratio"] <= IDENTITY_MARGIN
    assert "without that margin" in report.text(at)
    # the merge rule itself is unchanged: within the window joins, beyond it starts a node
    assert len(at.nodes) == len(ref.nodes) + (0 if factor <= 1.0 else 1)


def test_an_end_far_away_is_a_decided_new_node(monkeypatch):
    ref, _ = _explore(monkeypatch, None)
    at, moved = _explore(monkeypatch, 1e3)
    assert moved and len(at.nodes) == len(ref.nodes) + 1
    assert at.stats["identity_undecided"] == 0
