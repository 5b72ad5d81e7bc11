"""Arrival order does not matter (issue 35 item 2): the branch results of a
level are merged in whatever order they come in (the explorer's merge is
fed the results shuffled), and the atlas - its nodes, their points, kinds
and labels, the edges, the JSON written - is the same; a node's point is
its best-located end (model.arrival_rank), and two ends are one node within
SAME_TOL plus the error bound of each (model.pair_window)."""
import json

import numpy as np
import pytest

import libkin
from libkin.atlas import explorer


def _shuffled(monkeypatch, seed):
    """explore()'s merge gets each level's results in a random order (seed;
    None: as they come): the results are held back and handed on shuffled,
    after the level's following."""
    real = explorer.follow_level

    def follow_level(work, images, follow, syms, bars, take=None):
        held = []
        out = real(work, images, follow, syms, bars, lambda k, res: held.append((k, res)))
        if seed is not None:
            held = [held[i] for i in np.random.default_rng(seed).permutation(len(held))]
        for k, res in held:
            take(k, res)
        return out
    monkeypatch.setattr(explorer, "follow_level", follow_level)


def _atlas(at):
    d = json.loads(at.to_json())
    d["stats"] = at.summary()  # the rest of the stats are timings
    return d


@pytest.mark.parametrize("spec,kw,seeds", [
    ("sail:4:1", {"depth": 2}, (1, 2, 3, 4)),
    ("sail:6:2", {"depth": 2, "symmetric": True}, (5, 6, 7)),
])
def test_the_atlas_does_not_depend_on_the_merge_order(monkeypatch, spec, kw, seeds):
    with monkeypatch.context() as mp:
        _shuffled(mp, None)
        ref = _atlas(libkin.explore(spec, samples=1, **kw))
    assert len(ref["nodes"]) > 3 and len(ref["edges"]) > 30
    for seed in seeds:
        with monkeypatch.context() as mp:
            _shuffled(mp, seed)
            got = _atlas(libkin.explore(spec, samples=1, **kw))
        assert got["nodes"] == ref["nodes"], seed
        assert got["edges"] == ref["edges"], seed
        assert got == ref, seed


def test_a_node_is_its_best_located_end():
    """The hexagonal sail's symmetric map, depth 2: where ends located to
    different tolerances reach one node, the node has the point, accuracy
    and tolerance of the best-located, and every end is within pair_window
    of it. (Its collapsed-hub nodes were reached at 1e-8 along some paths
    and 1e-7 along others, issue 35; since the corank-k locator, docs/locate.md,
    every bifurcation end here is located to 1e-10, which this checks too:
    the mixed case is left to test_the_identity_window and the shuffles.)"""
    from libkin.atlas.model import pair_window
    held = {}
    real = explorer.follow_level

    def follow_level(work, images, follow, syms, bars, take=None):
        def keep(k, res):
            if res is not None:
                held.setdefault(len(held), (work[k][0], res))
            take(k, res)
        return real(work, images, follow, syms, bars, keep)
    explorer.follow_level = follow_level
    try:
        at = libkin.explore("sail:6:2", depth=2, symmetric=True, samples=0)
    finally:
        explorer.follow_level = real
    ends = [held[i] for i in range(len(held))]
    assert len(ends) == len(at.edges)  # the edges are in work order, as the ends were taken
    scale = max(1.0, float(np.abs(at.nodes[0].coords - at.nodes[0].coords.mean(axis=0)).max()))
    coarse = 0
    for e, (src, res) in zip(at.edges, ends):
        assert e.source == src
        if e.event == "loop":
            continue
        n = at.nodes[e.target]
        X = np.asarray(res["coords"])
        assert np.abs(X - n.coords).max() <= pair_window(scale, res["vr_tol"], n.located_tol)
        if n.depth == at.nodes[src].depth + 1 and e.event == "bifurcation":  # reached in the node's own level
            assert (res["accuracy"], res["vr_tol"]) >= (n.located_v_r, n.located_tol)
            coarse += res["vr_tol"] > n.located_tol
        if e.event == "bifurcation":
            assert res["vr_tol"] <= 1e-10, (e.source, e.target, res["vr_tol"])
    assert coarse == 0  # issue 35 item 3: no end at a relaxed tolerance is left


def test_the_identity_window():
    from libkin.atlas.model import LOCATION_FACTOR, SAME_TOL, arrival_rank, location_error, pair_window
    # the error bound of each end, added: symmetric, SAME_TOL for unlocated points
    assert pair_window(2.0, 0.0, 0.0) == 2.0 * SAME_TOL
    assert pair_window(2.0, 1e-7, 1e-8) == pair_window(2.0, 1e-8, 1e-7)
    assert pair_window(2.0, 1e-7, 1e-8) == pytest.approx(2.0 * (SAME_TOL + LOCATION_FACTOR * (1e-7 ** 0.5 + 1e-4)))
    assert location_error(1e-10) == pytest.approx(LOCATION_FACTOR * 1e-5)
    # the rank of an end: a located bifurcation before a near miss, then the accuracy, then the point
    X = [[0.0, 1.0]]
    bif = {"accuracy": 5e-9, "vr_tol": 1e-8, "coords": X}
    assert arrival_rank("bifurcation", bif) < arrival_rank("near_miss", dict(bif, accuracy=1e-12))
    assert arrival_rank("bifurcation", bif) < arrival_rank("bifurcation", dict(bif, accuracy=6e-9))
    assert arrival_rank("bifurcation", bif) < arrival_rank("bifurcation", dict(bif, coords=[[0.0, 1.5]]))
    assert arrival_rank("failure", {"accuracy": float("nan"), "coords": X})[1] == float("inf")
