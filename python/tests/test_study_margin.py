"""Thresholds that decide a reported fact are judged with a margin (issue 35
item 4, studies/margin.py): the loop-1 wrap test of the sail study decides
"yes" or "no" only where the x-y offset, with the uncertainty of the point it
was measured at, is a factor MARGIN clear of WRAP_TOL, and is "undecided"
(with the numbers) otherwise; no verdict flips between "yes" and "no" under
a perturbation the size of the uncertainty."""
import numpy as np
import pytest

from libkin import Assembly
from libkin.studies import margin
from libkin.studies.sequential import WRAP_TOL, wrap_verdict, wraps_loop1


def _wrapped(offset):
    """the hexagonal sail with loop 1 over its hub vertices (alternately up
    and down) but for an x-y offset `offset` of one node"""
    a = Assembly.sail(6, 2)
    labels = list(a.labels)
    x = a.coords.copy()
    from libkin.studies.sailmeasure import loop_of
    V = [i for i, lab in enumerate(labels) if loop_of(lab) == 0]
    A = [i for i, lab in enumerate(labels) if loop_of(lab) == 1]
    for k, (v, ai) in enumerate(zip(V, A)):
        x[ai, :2] = x[v, :2]
        x[ai, 2] = x[v, 2] + (0.5 if k % 2 else -0.5)
    x[A[0], 0] += offset
    return x, labels


def test_below_decides_only_with_margin():
    t = 1e-5
    assert margin.below(1e-7, t) == margin.YES
    assert margin.below(1e-3, t) == margin.NO
    for v in (t / 9, t, t * 9, t * (1 + 1e-12), t * (1 - 1e-12)):
        assert margin.below(v, t) == margin.UNDECIDED
    # the uncertainty widens the undecided band
    assert margin.below(1e-7, t, uncertainty=1e-6) == margin.UNDECIDED
    assert margin.below(1.5e-4, t, uncertainty=1e-4) == margin.UNDECIDED


@pytest.mark.parametrize("offset,tol,want", [
    (3e-8, 1e-10, margin.YES),       # a fully located wrap (issue 35: 3e-8..3e-7)
    (3e-7, 1e-10, margin.YES),
    (7e-6, 1e-7, margin.UNDECIDED),  # issue 35's coarse nodes: 7e-6..5e-5 at 1e-7
    (5e-5, 1e-7, margin.UNDECIDED),
    (1e-5, 0.0, margin.UNDECIDED),   # at the threshold itself
    (0.2, 1e-10, margin.NO),
])
def test_wrap_verdict(offset, tol, want):
    x, labels = _wrapped(offset)
    r = wrap_verdict(x, labels, 6, tol)
    assert r["verdict"] == want
    assert r["threshold"] == WRAP_TOL and r["value"] == pytest.approx(offset, rel=1e-6, abs=1e-15)
    # no flip under a perturbation of the size of its uncertainty (or of
    # rounding): the verdict stays or becomes undecided, never the opposite
    u = max(r["uncertainty"], 1e-15)
    for d in (-u, u, -1e-12 * offset, 1e-12 * offset):
        r2 = wrap_verdict(*_wrapped(offset + d), 6, tol)
        assert {r["verdict"], r2["verdict"]} != {margin.YES, margin.NO}


def test_wraps_loop1_refuses_to_guess():
    x, labels = _wrapped(1e-5)
    with pytest.raises(ValueError, match="undecided"):
        wraps_loop1(x, labels, 6)
    assert wraps_loop1(*_wrapped(1e-9), 6) is True
    assert wraps_loop1(*_wrapped(0.3), 6) is False
    # not alternating: no
    x, labels = _wrapped(0.0)
    x[:, 2] = np.abs(x[:, 2])
    assert wrap_verdict(x, labels, 6)["verdict"] == margin.NO
