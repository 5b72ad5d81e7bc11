"""The interference study (issue 23 item 4; studies/contactstudy.py): the
sail's membrane as panels, one clearance curve for every thickness, and the
certified search for the first contact along a fold."""
import json
import subprocess
import sys

import numpy as np
import pytest

from libkin import Assembly
from libkin.studies.contactstudy import S_TOL, TOUCH, _Search, member_study, sail_panels
from libkin.studies.sequential import sequential_fold


@pytest.fixture(scope="module")
def fold61():
    r = sequential_fold(6, 1, keep_states=True)
    a = r["assembly"]
    model = a.clone()
    model.panels = sail_panels(a)
    model.set_thickness(0.0)
    return r, model


def test_the_membrane_is_every_bar_triangle_and_the_hub():
    a = Assembly.sail(6, 2)
    panels = sail_panels(a)
    bars = {frozenset(map(int, b)) for b in a.bars}
    labels = a.labels
    tris = [p for p in panels if len(p) == 3]
    assert len(tris) == 2 * 6 * 2  # two triangles per hub side per loop
    for t in tris:  # every edge of a triangle is a bar; the centre node is no part of the membrane
        assert all(frozenset((t[i], t[(i + 1) % 3])) in bars for i in range(3))
        assert "C" not in [labels[j] for j in t]
    hub = [p for p in panels if len(p) > 3]
    assert [[labels[j] for j in p] for p in hub] == [[f"V{k}" for k in range(6)]]


def test_one_clearance_curve_serves_every_thickness(fold61):
    # bars of radius t/2 and panels of thickness t: clearance(t) = clearance(0) - t
    r, model = fold61
    thick = model.clone()
    rng = np.random.default_rng(3)
    for x in [r["samples"].coords[i] for i in rng.choice(len(r["samples"].coords), 6, replace=False)]:
        c0 = model.clearance(x).value
        for t in (0.001, 0.01, 0.03):
            thick.set_thickness(t)
            ct = thick.clearance(x).value
            assert abs(ct - (c0 - t)) <= 64 * np.finfo(float).eps * max(1.0, abs(c0)), (t, c0, ct)


def test_the_first_contact_is_certified(fold61):
    r, model = fold61
    s = _Search(model, r["samples"])
    L = np.asarray(r["samples"].l)
    for t in (0.003, 0.01, 0.03):
        hit = s.first(t)
        assert hit is not None
        c = model.clearance(hit["coords"]).value
        assert c <= t  # a contact ...
        assert c >= t - 2 * S_TOL  # ... located to the search's resolution (|dc/dl| <= sqrt 2)
        before = L < hit["l"] - 1e-12
        assert np.all(np.asarray(s.c0)[before] > t)  # no recorded point before it touches
        # thicker membranes touch earlier
    ls = [s.first(t)["l"] for t in (0.001, 0.003, 0.01, 0.03)]
    assert all(a > b for a, b in zip(ls, ls[1:]))


def test_a_bare_one_loop_sail_touches_where_loop_1_is_wrapped(fold61):
    # at the bifurcation, loop 1's nodes stand over the hub's vertices
    # alternately up and down, so each outer edge A_k A_k+1 crosses the line
    # of the hub edge V_k V_k+1: the bare membrane touches exactly there
    r, model = fold61
    s = _Search(model, r["samples"])
    hit = s.first(0.0)
    assert hit is not None and abs(hit["l"] - r["legs"][0]["l_end"]) <= 1e-9
    c = model.clearance(hit["coords"])
    assert c.value <= TOUCH and [k for k, _ in c.parts] == ["bar", "bar"]


def test_member_study_reports_each_thickness():
    m = member_study(6, 1, thicknesses=(0.0, 0.01))
    assert [c["t"] for c in m["contacts"]] == [0.0, 0.01]
    assert all(c["contact"] for c in m["contacts"])
    assert m["contacts"][1]["fold_fraction"] < m["contacts"][0]["fold_fraction"] <= 1.0
    assert m["bifurcations"] == 1
    json.dumps(m)  # JSON-serialisable as it is


def test_the_cli_writes_the_report_and_refuses_bad_members(tmp_path):
    out = tmp_path / "inter"
    cmd = [sys.executable, "-m", "libkin", "study", "--interference", "--members", "6/1",
           "--thickness", "0,0.01", "--quiet", "--out", str(out)]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    assert {f.name for f in out.iterdir()} >= {"report.md", "summary.json", "interference.png"}
    summary = json.loads((out / "summary.json").read_text())
    assert [m["n_loops"] for m in summary["members"]] == [1]
    for bad in ("6", "5/1", "6/0", "x/y"):
        p = subprocess.run(cmd[:5] + [bad, "--out", str(tmp_path / "bad")], capture_output=True, text=True,
                           timeout=60)
        assert p.returncode == 2 and not (tmp_path / "bad").exists()
