"""The C library's symmetry finder (kin_symmetries, kin_mechanism_group;
method="c") against the Python one (networkx VF2): the same symmetries and
the same group on beta, on sails (3D) and planar linkages, and its errors."""
import numpy as np
import pytest

import libkin
from libkin.symmetry.automorphisms import detect_symmetries, mechanism_group
from libkin.errors import InvalidArgumentError, LimitError, NoMechanismError


def same_set(A, B, tol=1e-9):
    """every matrix of A is one of B and the other way round (as many)"""
    return len(A) == len(B) and all(min(np.abs(B - X).max(axis=(1, 2))) < tol for X in A) and all(
        min(np.abs(A - X).max(axis=(1, 2))) < tol for X in B)


def five_bar(apex_x=0.0):
    coords = [[-1, 0], [1, 0], [-1.2, 1], [1.2, 1], [apex_x, 1.8]]
    fixed = [[1, 1], [1, 1], [0, 0], [0, 0], [0, 0]]
    return libkin.Assembly(coords, [[0, 2], [2, 4], [4, 3], [3, 1]], fixed)


@pytest.mark.parametrize("make,want", [
    (lambda: libkin.Assembly.sail(4, 1), 4),
    (lambda: libkin.Assembly.sail(6, 1), 6),
    (lambda: libkin.Assembly.sail(6, 2), 6),
    (lambda: libkin.Assembly.sail(8, 1), 8),
    (lambda: five_bar(), 2),
    (lambda: five_bar(0.1), 1),
])
def test_same_as_python(make, want):
    a = make()
    sp, sc = detect_symmetries(a), detect_symmetries(a, method="c")
    assert len(sp) == len(sc) == want
    assert sc[0].is_identity
    for p, c in zip(sp, sc):  # the same order: identity, then by permutation and Q
        assert p.perm == c.perm
        assert np.abs(p.Q - c.Q).max() < 1e-12 and np.abs(p.t - c.t).max() < 1e-9
    Rp, Rc = mechanism_group(a), mechanism_group(a, method="c")
    m = a.analyse().m_internal
    assert Rc.shape == (want, m, m)
    assert np.abs(Rc[0] - np.eye(m)).max() < 1e-12
    assert same_set(Rp, Rc)


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
    with pytest.raises(LimitError):
        detect_symmetries(star, method="c")
