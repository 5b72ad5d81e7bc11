"""Cyclic symmetry of the solar-sail family, and the second-order analysis
restricted to motions that keep it.

A sail with an n-gon hub is mapped onto itself by the rotation about the z
axis that takes hub vertex V_k to V_(k+shift), provided the supports are
mapped onto supports: shift = 2 for the CENTRE support (V0, V2, ... fixed)
and shift = n/2 for the OPPOSITE support (V0 and V(n/2) fixed).

If beta is a second-order solution that keeps the symmetry, every
second-order equation that is not itself symmetric vanishes at beta on its
own; so the symmetric solutions of the full system are exactly the solutions
of the system restricted to the symmetric subspace of U_m (with the
restricted matrices orthonormalised again, eq. 18). For the hexagonal sail
that turns 2^15 = 32768 homotopy paths into 2^5 = 32.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Dict, Tuple

import numpy as np
import numpy.typing as npt

from ..errors import InvalidArgumentError, StateError

if TYPE_CHECKING:
    from ..assembly import Assembly

FloatArray = npt.NDArray[np.float64]

# a matrix entry or singular value below this (relative) counts as zero: the
# rotation matrices are exact to a few ulps, and eq. 18's Gram-Schmidt keeps
# independent matrices at O(1) norm
_ZERO = 1e-9


def sail_rotation(a: "Assembly", n_sides: int, shift: int) -> FloatArray:
    """The rotation V_k -> V_(k+shift) of a sail built by `Assembly.sail`.

    Parameters
    ----------
    a : Assembly
        A sail (its labels say whether there is a centre node).
    n_sides : int
        Sides of its hub.
    shift : int
        How many hub vertices the rotation advances.

    Returns
    -------
    ndarray, shape (nfree, nfree)
        The rotation acting on free-coordinate vectors.

    Raises
    ------
    InvalidArgumentError
        The assembly is not a sail of `n_sides` with that symmetry (joint
        count, supports, or the configuration itself); a ValueError.
    """
    labels = a.labels or []
    off = 1 if labels and labels[0] == "C" else 0
    if a.dim != 3 or (a.njoints - off) % n_sides:
        raise InvalidArgumentError(f"not a 3D sail with a {n_sides}-gon hub")
    ang = 2.0 * np.pi * shift / n_sides
    R = np.array([[np.cos(ang), -np.sin(ang), 0.0], [np.sin(ang), np.cos(ang), 0.0], [0.0, 0.0, 1.0]])
    perm = np.arange(a.njoints)
    for i in range(off, a.njoints):
        ring, k = divmod(i - off, n_sides)
        perm[i] = off + ring * n_sides + (k + shift) % n_sides
    xyz = a.coords
    if np.abs(xyz[perm] - xyz @ R.T).max() > 1e-9 * max(1.0, np.abs(xyz).max()):
        raise InvalidArgumentError("the configuration does not have this rotational symmetry")
    fm = a.free_map()
    P = np.zeros((a.nfree, a.nfree))
    for i in range(a.njoints):
        j = perm[i]
        for ax in range(3):
            for bx in range(3):
                if abs(R[bx, ax]) < _ZERO:
                    continue
                fi, fj = fm[i, ax], fm[j, bx]
                if (fi < 0) != (fj < 0):
                    raise InvalidArgumentError("the rotation does not map supports onto supports")
                if fi >= 0:
                    P[fj, fi] = R[bx, ax]
    return P


def symmetric_subspace(U: FloatArray, P: FloatArray) -> FloatArray:
    """The second-order unknowns that keep a symmetry.

    Parameters
    ----------
    U : ndarray, shape (nfree, m)
        Orthonormal internal mechanisms.
    P : ndarray, shape (nfree, nfree)
        The symmetry (e.g. from `sail_rotation`).

    Returns
    -------
    ndarray, shape (m, k)
        Orthonormal basis G of the beta with ``U @ beta`` invariant under P.
    """
    Gm = U.T @ P @ U - np.eye(U.shape[1])
    _, sv, vt = np.linalg.svd(Gm)
    sv = np.concatenate([sv, np.zeros(U.shape[1] - sv.size)])
    return vt[sv < _ZERO * max(1.0, sv[0] if sv.size else 1.0)].T


def restricted_quadrics(Q: FloatArray, G: FloatArray) -> FloatArray:
    """The second-order matrices restricted to ``beta = G @ gamma``.

    Parameters
    ----------
    Q : ndarray, shape (s, m, m)
        Second-order matrices.
    G : ndarray, shape (m, k)
        Orthonormal basis of the subspace.

    Returns
    -------
    ndarray, shape (s', k, k)
        The restricted matrices orthonormalised again (eq. 18), dependent
        ones dropped.
    """
    Qr = np.einsum("ai,jab,bk->jik", G, Q, G)
    M = Qr.reshape(Qr.shape[0], -1)
    _, sv, vt = np.linalg.svd(M, full_matrices=False)
    keep = sv > _ZERO * sv[0] if sv.size and sv[0] > 0 else np.zeros(0, bool)
    Qs = vt[keep].reshape(-1, G.shape[1], G.shape[1])
    return 0.5 * (Qs + Qs.transpose(0, 2, 1))


def symmetric_solutions(a: "Assembly", P: FloatArray, threads: int = 2,
                        seed: int = 1) -> Tuple[FloatArray, Dict[str, int], int, int]:
    """Second-order solutions at a bifurcation that keep a symmetry.

    Parameters
    ----------
    a : Assembly
        At a bifurcation.
    P : ndarray, shape (nfree, nfree)
        The symmetry.
    threads, seed : int, optional
        Passed to the homotopy solver.

    Returns
    -------
    betas : ndarray, shape (nsol, m_internal)
        The symmetric solutions.
    accounting : dict
        The restricted homotopy's counts.
    k : int
        Dimension of the symmetric subspace.
    s_restricted : int
        Independent restricted equations.

    Raises
    ------
    StateError
        Fewer than 2 symmetric mechanisms, or a restricted system the
        solvers cannot take (they need k - 1 equations).
    """
    from ..assembly import canonical, solve_quadrics
    an = a.analyse()
    G = symmetric_subspace(an.internal_mechanisms, P)
    k = G.shape[1]
    if k < 2:
        raise StateError(f"only {k} symmetric first-order mechanism(s): nothing to choose")
    Qs = restricted_quadrics(a.second_order(), G)
    if Qs.shape[0] != k - 1:
        raise StateError(f"restricted system has {Qs.shape[0]} equations in {k} unknowns; "
                         "the solvers need k - 1")
    gam, acc = solve_quadrics(Qs, "homotopy", seed=seed, threads=threads)
    # in the canonical order and sign of the directions U beta, not of G's basis
    return canonical(gam @ G.T, an.internal_mechanisms), acc, k, Qs.shape[0]
