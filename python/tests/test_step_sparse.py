"""The sparse LU mode (kin_options.factorization = KIN_STEP_SPARSE) through
the wrapper: the same points as the SVD mode, and invalid values rejected."""
import dataclasses

import numpy as np
import pytest

import libkin
from libkin._native._lib import lib


def _in_mode(a, factorization, step_control=0):
    b = a.clone()
    b.options = dataclasses.replace(b.options, factorization=factorization, step_control=step_control)
    return b


def test_sparse_mode_follows_the_svd_mode():
    a = libkin.Assembly.threebar("RC")
    xyz = a.coords
    xyz[:2] = [[0.6, 0.8], [1.6, 0.8]]
    a.coords = xyz
    s = _in_mode(a, lib.KIN_STEP_SPARSE)
    assert s.options.factorization == 2
    for _ in range(8):
        a.step(0.05)
        s.step(0.05)
    np.testing.assert_allclose(s.coords, a.coords, atol=8 * 1e-12 * 2)
    assert s.max_strain <= 1e-12


@pytest.mark.parametrize("field, value", [("factorization", 3), ("step_control", 2)])
def test_invalid_mode_values(field, value):
    a = libkin.Assembly.threebar("RC")
    with pytest.raises(libkin.errors.error_class(lib.KIN_EINVAL)):
        a.options = dataclasses.replace(a.options, **{field: value})


def _mast(sides, bays):
    """tests/mast_model.h's deployable mast: the base ring fixed, the middle
    bay's first face diagonal left out (one internal mechanism)"""
    r = 0.5 / np.sin(np.pi / sides)
    xyz = [[r * np.cos(2 * np.pi * i / sides), r * np.sin(2 * np.pi * i / sides), l]
           for l in range(bays + 1) for i in range(sides)]
    bars = []
    for l in range(1, bays + 1):
        for i in range(sides):
            i1, bot, top = (i + 1) % sides, (l - 1) * sides, l * sides
            bars += [(bot + i, top + i), (top + i, top + i1)]
            if not (l == bays // 2 and i == 0):
                bars.append((bot + i, top + i1) if l % 2 else (bot + i1, top + i))
    fixed = np.zeros((len(xyz), 3), dtype=bool)
    fixed[:sides] = True
    return libkin.Assembly(xyz, bars, fixed)


def test_sparse_mode_analysis_matches_the_svd_mode():
    """kin_analyse in the sparse mode, answered by the sparse route (no dense
    SVD) where it is cheaper: the same counts, v_max and v_r to rounding, the
    same mechanism and self-stress subspaces; no spectrum (an empty array)
    instead of made-up values."""
    a = _mast(3, 100)
    d, s = a.analyse(), _in_mode(a, lib.KIN_STEP_SPARSE).analyse()
    assert (d.route, s.route) == ("dense", "sparse")
    assert (s.rank, s.m, s.m_rigid, s.m_internal, s.s) == (d.rank, d.m, d.m_rigid, d.m_internal, d.s) == \
        (a.nbars, 1, 0, 1, 0)
    eps = np.finfo(float).eps
    assert abs(s.v_max - d.v_max) <= 128 * eps * d.v_max
    assert abs(s.v_r - d.v_r) <= 128 * eps * d.v_max
    assert s.singular_values.shape == (0,) and d.singular_values.shape == (min(a.nfree, a.nbars),)
    tol = 128 * eps * d.v_max / d.v_r
    for x, y in ((d.internal_mechanisms, s.internal_mechanisms), (d.self_stresses, s.self_stresses)):
        # sine of the largest principal angle
        assert np.linalg.norm(y - x @ (x.T @ y), 2) <= tol


def test_sparse_mode_takes_the_dense_route_where_cheaper():
    """A small sail in the sparse mode: the dense SVD is cheaper and fits, so
    it answers, says so, and gives the whole spectrum."""
    a = libkin.Assembly.sail(6, 2)
    d, s = a.analyse(), _in_mode(a, lib.KIN_STEP_SPARSE).analyse()
    assert s.route == "dense"
    assert (s.rank, s.m, s.m_rigid, s.m_internal, s.s) == (d.rank, d.m, d.m_rigid, d.m_internal, d.s)
    np.testing.assert_array_equal(s.singular_values, d.singular_values)
