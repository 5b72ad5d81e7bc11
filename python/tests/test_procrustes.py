"""libkin.symmetry.procrustes: the package's one Procrustes helper (scipy's
Rotation.align_vectors). Known rotations come back to ~1e-12, a mirror
image is fitted by the best proper rotation (never a reflection), and
degenerate sets (one point, coincident points, a line) give a rotation."""
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from libkin.symmetry.procrustes import aligned_distance, rotation_fit


def plane_rotation(theta):
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, -s], [s, c]])


def assert_rotation(R):
    d = len(R)
    assert np.abs(R.T @ R - np.eye(d)).max() < 1e-13 and abs(np.linalg.det(R) - 1.0) < 1e-13


@pytest.mark.parametrize("seed", range(6))
def test_known_rotations_recovered(seed):
    rng = np.random.default_rng(seed)
    X3 = rng.standard_normal((7, 3)) * 3.0
    R3 = Rotation.random(random_state=seed).as_matrix()
    t3 = rng.standard_normal(3)
    R = rotation_fit(X3, X3 @ R3.T + t3)
    assert np.abs(R - R3).max() < 1e-12
    assert aligned_distance(X3, X3 @ R3.T + t3) < 1e-12
    X2 = rng.standard_normal((5, 2))
    for theta in (rng.uniform(-np.pi, np.pi), 0.0, np.pi, np.pi / 2, -1e-9):
        R2 = plane_rotation(theta)
        R = rotation_fit(X2, X2 @ R2.T - 4.0)
        assert_rotation(R)
        assert np.abs(R - R2).max() < 1e-12, theta
        assert aligned_distance(X2, X2 @ R2.T - 4.0) < 1e-12


def kabsch_residual_2d(X, Y):
    """the best proper fit in the plane by brute force: the rotation angle
    that maximises sum(x . y) is atan2(sum(x cross y), sum(x . y))"""
    Xc, Yc = X - X.mean(axis=0), Y - Y.mean(axis=0)
    theta = np.arctan2((Xc[:, 0] * Yc[:, 1] - Xc[:, 1] * Yc[:, 0]).sum(), (Xc * Yc).sum())
    return float(np.abs(Xc @ plane_rotation(theta).T - Yc).max())


@pytest.mark.parametrize("dim", [2, 3])
def test_reflections_are_not_fitted(dim):
    """A mirror image is matched by the best rotation only: the residual
    stays, and R is proper (today's Kabsch sign correction)."""
    rng = np.random.default_rng(11 + dim)
    X = rng.standard_normal((8, dim))
    M = np.eye(dim)
    M[0, 0] = -1.0
    Y = X @ M.T
    R = rotation_fit(X, Y)
    assert_rotation(R)
    assert aligned_distance(X, Y) > 0.1
    if dim == 2:
        assert abs(aligned_distance(X, Y) - kabsch_residual_2d(X, Y)) < 1e-12
    else:  # no proper rotation does better: compare with many random ones
        Xc, Yc = X - X.mean(axis=0), Y - Y.mean(axis=0)
        best = ((Xc @ R.T - Yc) ** 2).sum()
        for Q in Rotation.random(2000, random_state=5).as_matrix():
            assert ((Xc @ Q.T - Yc) ** 2).sum() >= best - 1e-12
    # a planar set in 3D and its mirror through that plane: the half-turn fits exactly
    P = np.c_[rng.standard_normal((6, 2)), np.zeros(6)]
    assert aligned_distance(P, P * [1, 1, -1]) < 1e-12


def test_degenerate_sets():
    for dim in (2, 3):
        one = np.ones((1, dim))
        assert_rotation(rotation_fit(one, 2 * one))
        assert aligned_distance(one, 2 * one) == 0.0
        same = np.zeros((4, dim))
        assert_rotation(rotation_fit(same, same + 1.0))
        assert aligned_distance(same, same + 1.0) < 1e-15
        # points on one line: the fit is not unique, the distance is
        line = np.outer(np.arange(5.0), np.eye(dim)[0])
        R = rotation_fit(line, line @ np.eye(dim)[::-1].T)
        assert_rotation(R)
        assert aligned_distance(line, line @ np.eye(dim)[::-1].T) < 1e-12
    with pytest.raises(ValueError):
        rotation_fit(np.zeros((3, 2)), np.zeros((3, 3)))
    with pytest.raises(ValueError):
        rotation_fit(np.zeros((3, 4)), np.zeros((3, 4)))
    with pytest.raises(ValueError):
        rotation_fit(np.zeros((0, 3)), np.zeros((0, 3)))
