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
