"""The symmetry search (the C library's kin_symmetries, kin_mechanism_group,
which every function of libkin.symmetry.automorphisms calls) against known groups:
the group order, every element an automorphism of the bar graph (rest
lengths and supports kept) and an isometry of the configuration, the group
on beta orthogonal with the identity first, on sails (3D) and planar
linkages; and its errors."""
import numpy as np
import pytest

import libkin
from libkin.symmetry.automorphisms import detect_symmetries, graph_automorphisms, mechanism_group, symmetries_at
from libkin.errors import InvalidArgumentError, LimitError, NoMechanismError


def same_set(A, B, tol=1e-9):
    """every matrix of A is one of B and the other way round (as many)"""
    return len(A) == len(B) and all(min(np.abs(B - X).max(axis=(1, 2))) < tol for X in A) and all(
        min(np.abs(A - X).max(axis=(1, 2))) < tol for X in B)


def five_bar(apex_x=0.0):
    coords = [[-1, 0], [1, 0], [-1.2, 1], [1.2, 1], [apex_x, 1.8]]
    fixed = [[1, 1], [1, 1], [0, 0], [0, 0], [0, 0]]
    return libkin.Assembly(coords, [[0, 2], [2, 4], [4, 3], [3, 1]], fixed)


def assert_symmetry(a, g, X=None):
    """g maps bars to bars of the same rest length, fixed axes to fixed axes,
    and the configuration X (default: a's) onto itself by an isometry"""
    X = a.coords if X is None else X
    perm = np.asarray(g.perm)
    assert sorted(g.perm) == list(range(a.njoints))
    rest = a.rest_lengths
    bars = {frozenset(map(int, b)): L for b, L in zip(a.bars, rest)}
    for b, L in zip(a.bars, rest):
        image = frozenset(int(perm[i]) for i in b)
        assert image in bars and abs(bars[image] - L) < 1e-9 * max(1.0, L)
    assert np.abs(g.Q.T @ g.Q - np.eye(a.dim)).max() < 1e-12
    fixed = np.asarray(a.fixed, dtype=bool)
    for i, j in enumerate(perm):
        for ax in np.flatnonzero(fixed[i]):
            assert np.abs(g.Q[~fixed[j], ax]).max(initial=0.0) < 1e-9
    assert np.abs(X[perm] - (X @ g.Q.T + g.t)).max() < 1e-9 * max(1.0, np.abs(X).max())
    assert np.abs(g.apply(X) - X).max() < 1e-9 * max(1.0, np.abs(X).max())


def lifted(a):
    """the free coordinates lifted in z by the squared radius: keeps a
    sail's rotations, breaks its mirror z -> -z"""
    X = a.coords
    free = ~np.asarray(a.fixed, dtype=bool)
    D = np.zeros_like(X)
    D[:, 2] = 0.05 * (X[:, 0] ** 2 + X[:, 1] ** 2)
    return X + np.where(free, D, 0.0)


@pytest.mark.parametrize("make,want,proper", [
    (lambda: libkin.Assembly.sail(4, 1), 4, 2),  # C2 about z, times the mirror z -> -z
    (lambda: libkin.Assembly.sail(6, 1), 6, 3),  # C3 about z (centre support), times the mirror
    (lambda: libkin.Assembly.sail(6, 2), 6, 3),
    (lambda: libkin.Assembly.sail(8, 1), 8, 4),
    (lambda: libkin.Assembly.sail(6, 2, support="opposite"), 4, 2),
    (lambda: libkin.Assembly.threebar("RB"), 4, 2),
    (lambda: libkin.Assembly.threebar("RC"), 2, 1),
    (lambda: five_bar(), 2, 1),  # the mirror x -> -x
    (lambda: five_bar(0.1), 1, 1),
])
def test_known_groups(make, want, proper):
    a = make()
    syms = detect_symmetries(a)
    assert len(syms) == want and sum(g.proper for g in syms) == proper
    assert syms[0].is_identity
    for g in syms:
        assert_symmetry(a, g)
    # composition closes: g h is one of the group
    for g in syms:
        for h in syms:
            gh = [k for k in syms if k.perm == tuple(g.perm[p] for p in h.perm)
                  and np.abs(k.Q - g.Q @ h.Q).max() < 1e-9]
            assert len(gh) == 1
    # method="c" is the same search (and moves nothing when coords is None)
    sc = detect_symmetries(a, method="c")
    assert [g.perm for g in sc] == [g.perm for g in syms]
    assert all(np.abs(g.Q - h.Q).max() < 1e-12 and np.abs(g.t - h.t).max() < 1e-12 for g, h in zip(sc, syms))
    assert graph_automorphisms(a) == sorted({g.perm for g in syms}, key=[g.perm for g in syms].index)
    Rp, Rc = mechanism_group(a), mechanism_group(a, method="c")
    m = a.analyse().m_internal
    assert Rp.shape == Rc.shape == (want, m, m)
    assert np.abs(Rp[0] - np.eye(m)).max() < 1e-12 and np.abs(Rc[0] - np.eye(m)).max() < 1e-12
    assert all(np.abs(R.T @ R - np.eye(m)).max() < 1e-10 for R in Rp)
    assert list(np.trace(Rp, axis1=1, axis2=2)) == sorted(np.trace(Rp, axis1=1, axis2=2), reverse=True)
    assert same_set(Rp, Rc)


@pytest.mark.parametrize("sides,want", [(4, 2), (6, 3), (8, 4)])
def test_symmetries_at_another_configuration(sides, want):
    """Lifted off the plane, a sail keeps its rotations about z only; the
    assembly is not moved, and perms restricts the candidates."""
    a = libkin.Assembly.sail(sides, 1)
    X0 = a.coords
    Y = lifted(a)
    syms = symmetries_at(a, None, Y)
    assert len(syms) == want and all(g.proper for g in syms) and syms[0].is_identity
    for g in syms:
        assert_symmetry(a, g, Y)
    assert np.array_equal(a.coords, X0)
    assert [g.perm for g in detect_symmetries(a, Y)] == [g.perm for g in syms]
    assert [g.perm for g in symmetries_at(a, [syms[-1].perm], Y)] == [syms[-1].perm]
    rng = np.random.default_rng(1)
    Z = X0 + np.where(np.asarray(a.fixed, dtype=bool), 0.0, 0.01 * rng.standard_normal(X0.shape))
    assert [g.perm for g in symmetries_at(a, None, Z)] == [tuple(range(a.njoints))]
    with pytest.raises(InvalidArgumentError):
        symmetries_at(a, None, X0[:-1])


def test_errors():
    a = libkin.Assembly.sail(4, 1)
    with pytest.raises(InvalidArgumentError):
        mechanism_group(a, method="fortran")
    with pytest.raises(InvalidArgumentError):
        detect_symmetries(a, method="")
    tri = libkin.Assembly([[0, 0], [2, 0], [1, 1]], [[0, 1], [0, 2], [1, 2]], [[1, 1], [1, 1], [0, 0]])
    assert len(detect_symmetries(tri, method="c")) == 2
    with pytest.raises(NoMechanismError):
        mechanism_group(tri, method="c")
    k = 9  # a star of 9 equal spokes: 9! graph automorphisms, over the cap
    ang = 2 * np.pi * np.arange(k) / k
    coords = np.vstack([[0, 0], np.c_[np.cos(ang), np.sin(ang)]])
    fixed = np.zeros((k + 1, 2), dtype=np.uint8)
    fixed[0] = 1
    star = libkin.Assembly(coords, [[0, i + 1] for i in range(k)], fixed)
    for method in ("python", "c"):
        with pytest.raises(LimitError):
            detect_symmetries(star, method=method)
