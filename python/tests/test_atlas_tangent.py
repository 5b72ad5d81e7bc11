"""Tangent branches are undecided, on every machine (issue 35 items 4 and 5).

A corank-1 bifurcation (m = 2, s = 1) is two branches crossing only where its
second-order form Q is indefinite with a margin: the ratio rho of its smaller
eigenvalue to its larger is below -sqrt(tau), tau the tolerance the point was
located to (tasks.crossing_verdict). The fixture is the one follow task of
the hexagonal sail's depth-5 atlas whose end depended on the BLAS kernel: a
proven singular point under the default kernel (v_r / v_max 2.9e-16), a
strict location 6e-5 away under Haswell (2.3e-11), undecided under Prescott.
Q there has rho = +1.2e-10 .. +2e-9: positive semi-definite to within what
the point's location decides, so no crossing can be told from a tangency.
Now the atlas's node is undecided under every kernel, with its numbers."""
import json
import math
import pathlib
import sqlite3

import numpy as np
import pytest

import libkin
from libkin.atlas import model, store as atlas_store, tasks

DATA = pathlib.Path(__file__).parent / "data"


def _task(name):
    t = json.loads((DATA / name).read_text())
    t["model"] = json.dumps(t["model"], sort_keys=True)
    return t


def test_the_kernel_dependent_end_is_undecided():
    """whichever way this machine's kernel ends the follow (a located point
    or a minimum of v_r), the node is undecided, never a bifurcation to
    expand; where located, the ratio is within 1e-6 of zero, far inside the
    margin (tau = 1e-10 asks for below -1e-5)"""
    res = tasks.follow_branch(_task("tangent_sail62.json"))
    assert model.node_kind(res["event"], res) == model.UNDECIDED
    if res["event"] == tasks.BIFURCATION:
        assert (res["m"], res["s"]) == (2, 1) and res["accuracy"] <= 1e-10
        assert abs(res["crossing_ratio"]) <= 1e-6 and res["undecided"] is True
    else:
        assert res["event"] == tasks.NEAR_MISS and res["undecided"] is True
    why = tasks.undecided_why(res)
    assert why.startswith("undecided") and why != tasks.UNDECIDED_WHY


def test_a_crossing_stays_a_bifurcation():
    """the proven crossing of test_follow_rounding_crossing.py: rho = -0.045,
    4500 times beyond the margin, a bifurcation"""
    res = tasks.follow_branch(_task("rounding_crossing_sail62.json"))
    assert res["event"] == tasks.BIFURCATION and (res["m"], res["s"]) == (2, 1)
    assert res["crossing_ratio"] <= -100 * math.sqrt(res["vr_tol"])
    assert "undecided" not in res
    assert model.node_kind(res["event"], res) == model.BIFURCATION


def _end():
    return {"event": tasks.BIFURCATION, "m": 2, "m_rigid": 0, "s": 1, "v_r_rel": 1e-12,
            "accuracy": 1e-12, "vr_tol": 1e-10, "coords": [[0.0, 0.0]]}


@pytest.mark.parametrize("lam,decided", [((-0.3, 0.4), True), ((-0.4, 0.4), True), ((0.4, -0.4), True),
                                         ((-4e-5, 0.4), True), ((-4e-7, 0.4), False), ((0.0, 0.4), False),
                                         ((4e-11, 0.37), False), ((0.3, 0.4), False), ((-0.4, 4e-6), True),
                                         ((-0.4, 4e-7), False)])
def test_crossing_verdict_decides_on_the_ratio(lam, decided):
    """the verdict on a given form: a crossing needs opposite signs and the
    smaller eigenvalue at least sqrt(tau) = 1e-5 of the larger, whichever
    sign the larger has; a definite form (no second branch) or a nearly
    singular one is undecided. The ratio is basis-free: Q is rotated by a
    random orthogonal matrix (the mechanism basis an SVD returns)"""
    rng = np.random.default_rng(7)
    R = np.linalg.qr(rng.standard_normal((2, 2)))[0]
    Q = R @ np.diag(lam) @ R.T

    class _Fake:
        def second_order(self, normalise=False):
            return Q[None, :, :]

    v = tasks.crossing_verdict(_Fake(), 1e-10)
    small, big = sorted(lam, key=abs)
    assert v["crossing_ratio"] == pytest.approx(small / big, rel=1e-9, abs=1e-15)
    assert ("undecided" not in v) == decided
    res = dict(_end(), **v)
    assert model.node_kind(tasks.BIFURCATION, res) == (model.BIFURCATION if decided else model.UNDECIDED)


def test_no_form_no_verdict():
    """where second order has no form (a self-stress of bars between fixed
    joints only: StateError) the end keeps its kind"""
    from libkin.errors import StateError

    class _NoForm:
        def second_order(self, normalise=False):
            raise StateError("not a bifurcation point")

    assert tasks.crossing_verdict(_NoForm(), 1e-10) == {}


def test_a_store_decided_by_other_rules_is_refused(tmp_path, monkeypatch):
    """a run resumed from a store whose results were decided by other rules
    (before crossing_verdict) is refused, not mixed with the new verdicts;
    the store is left as it was"""
    path = tmp_path / "run.sqlite"
    monkeypatch.setattr(tasks, "RESULT_RULES", 1)
    libkin.explore("sail:4:1", depth=1, store=path)
    before = _recorded(path)
    assert before > 0
    monkeypatch.setattr(tasks, "RESULT_RULES", 2)
    with pytest.raises(atlas_store.StoreMismatchError):
        libkin.explore("sail:4:1", depth=1, store=path, resume=True)
    assert _recorded(path) == before


def _recorded(path):
    db = sqlite3.connect(str(path))
    try:
        return db.execute("SELECT COUNT(*) FROM results").fetchone()[0]
    finally:
        db.close()
