"""The best rigid motion between two point sets (Procrustes): one helper for
the package.

rotation_fit(X, Y) is the proper rotation R (det R = +1, never a
reflection) that minimises the sum of |R (x_i - cx) - (y_i - cy)|^2 over
the joints, cx and cy the centroids: Kabsch's algorithm with its sign
correction. scipy computes it: scipy.linalg.orthogonal_procrustes gives the
best orthogonal fit, which is the answer when it is a rotation (the common
case, and the cheaper call); when it is a reflection, scipy's
Rotation.align_vectors gives the best rotation. In 2D the points are then
embedded at z = 0 and the z axis is pinned (an infinite weight on the pair
(e_z, e_z)), so the fit is a rotation about z: without the pin, the
half-turn about an in-plane axis, a reflection of the plane, could fit
better. When the fit is not unique (every point at the centroid, or all on
one line), any optimal rotation is returned; aligned_distance does not
depend on which.

The symmetry search (including fits that may be reflections) is the C
library's (kin_symmetries; libkin.symmetry.automorphisms).
"""
from __future__ import annotations

import warnings

import numpy as np
from numpy.typing import ArrayLike, NDArray

_EZ = np.array([[0.0, 0.0, 1.0]])


def rotation_fit(X: ArrayLike, Y: ArrayLike) -> NDArray[np.float64]:
    """The proper rotation R (dim, dim) that best maps X onto Y after
    centring both: (X - cx) @ R.T ~ Y - cy. X and Y are (n, dim), dim 2 or
    3. Raises ValueError for other shapes."""
    from scipy.linalg import orthogonal_procrustes
    from scipy.spatial.transform import Rotation
    Xa, Ya = np.asarray(X, dtype=float), np.asarray(Y, dtype=float)
    if Xa.shape != Ya.shape or Xa.ndim != 2 or Xa.shape[1] not in (2, 3) or Xa.shape[0] < 1:
        raise ValueError(f"rotation_fit: expected two (n, 2 or 3) arrays of one shape, got {Xa.shape} and {Ya.shape}")
    Xc, Yc = Xa - Xa.mean(axis=0), Ya - Ya.mean(axis=0)
    if not Xc.any() or not Yc.any():  # coincident points (one, say): every rotation fits
        return np.eye(Xa.shape[1])
    R = orthogonal_procrustes(Xc, Yc)[0].T  # Xc @ R.T ~ Yc
    if np.linalg.det(R) > 0:
        return np.asarray(R)
    with warnings.catch_warnings():
        # some scipy versions warn when the fit is not unique; any optimum will do
        warnings.filterwarnings("ignore", message="Optimal rotation is not uniquely", category=UserWarning)
        if Xa.shape[1] == 3:
            rot, _ = Rotation.align_vectors(Yc, Xc)
            return np.asarray(rot.as_matrix())
        z = np.zeros((len(Xc), 1))
        w = np.r_[np.inf, np.ones(len(Xc))]
        rot, _ = Rotation.align_vectors(np.vstack([_EZ, np.hstack([Yc, z])]), np.vstack([_EZ, np.hstack([Xc, z])]),
                                        w)
    return np.asarray(rot.as_matrix()[:2, :2])


def aligned_distance(X: ArrayLike, Y: ArrayLike) -> float:
    """The largest coordinate difference (max-norm) between Y and X moved
    onto it by the best rigid motion (centroid onto centroid, then
    rotation_fit)."""
    Xa, Ya = np.asarray(X, dtype=float), np.asarray(Y, dtype=float)
    R = rotation_fit(Xa, Ya)
    return float(np.abs((Xa - Xa.mean(axis=0)) @ R.T + Ya.mean(axis=0) - Ya).max())
