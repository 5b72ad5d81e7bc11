"""The proven singular configuration near a located bifurcation (issue 38
item 2; kin_prove_singular, LocateInfo.singular, docs/locate.md "Certified
bifurcations"): the three-bar linkage's R^A, known in closed form, lies within
the proven distance of the located point; a regular point and the sail's flat
state (15 self-stresses) are not proven."""
import numpy as np

from libkin import Assembly, SingularProof


def _on_p1(th):
    a = Assembly.threebar("RC")
    x = a.coords.copy()
    x[0] = (np.cos(th), np.sin(th))  # J1, J2 (then the supports S1, S2)
    x[1] = (np.cos(th) + 1.0, np.sin(th))
    a.coords = x
    return a


def test_located_rc_proven():
    a = _on_p1(1.0)
    info = a.locate(delta=-0.1)
    assert info.located
    p = info.singular
    assert isinstance(p, SingularProof)
    assert p.proven and p.corank == 1
    x = a.coords
    # P1's bifurcations R^A and R^C (rest lengths 1, mu = 0): the proven point is
    # the exact one, so it lies within the bound
    exact = [np.array([[-1.0, 0.0], [0.0, 0.0]]), np.array([[1.0, 0.0], [2.0, 0.0]])]
    assert min(np.abs(x[:2] - e).max() for e in exact) <= p.distance
    assert p.distance <= 1e-8
    assert p.unique >= p.distance
    assert p.dlength <= 64 * np.finfo(float).eps
    again = a.prove_singular()
    assert again.proven and again.distance == p.distance
    assert np.array_equal(a.coords, x)  # the configuration is not changed


def test_regular_point_not_proven():
    p = _on_p1(1.0).prove_singular()
    assert not p.proven and p.corank == 0


def test_flat_sail_corank_15_not_proven():
    p = Assembly.sail(6, 2).prove_singular()
    assert not p.proven and p.corank == 15
