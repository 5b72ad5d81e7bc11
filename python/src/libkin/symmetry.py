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
import numpy as np

from .errors import ModelFormatError, StateError

# a matrix entry or singular value below this (relative) counts as zero: the
# rotation matrices are exact to a few ulps, and eq. 18's Gram-Schmidt keeps
# independent matrices at O(1) norm
_ZERO = 1e-9


def sail_rotation(a, n_sides, shift):
    """The rotation V_k -> V_(k+shift) of a sail built by Assembly.sail, as an
    (nfree, nfree) matrix acting on free-coordinate vectors. Raises
    ModelFormatError if the assembly is not a sail of n_sides with that
    symmetry (joint count, supports, or the configuration itself)."""
    labels = a.labels or []
    off = 1 if labels and labels[0] == "C" else 0
    if a.dim != 3 or (a.njoints - off) % n_sides:
        raise ModelFormatError(f"not a 3D sail with a {n_sides}-gon hub")
    ang = 2.0 * np.pi * shift / n_sides
    R = np.array([[np.cos(ang), -np.sin(ang), 0.0], [np.sin(ang), np.cos(ang), 0.0], [0.0, 0.0, 1.0]])
    perm = np.arange(a.njoints)
    for i in range(off, a.njoints):
        ring, k = divmod(i - off, n_sides)
        perm[i] = off + ring * n_sides + (k + shift) % n_sides
    xyz = a.coords
    if np.abs(xyz[perm] - xyz @ R.T).max() > 1e-9 * max(1.0, np.abs(xyz).max()):
        raise ModelFormatError("the configuration does not have this rotational symmetry")
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
                    raise ModelFormatError("the rotation does not map supports onto supports")
                if fi >= 0:
                    P[fj, fi] = R[bx, ax]
    return P


def symmetric_subspace(U, P):
    """Orthonormal basis G (m, k) of the beta with U beta invariant under P."""
    Gm = U.T @ P @ U - np.eye(U.shape[1])
    _, sv, vt = np.linalg.svd(Gm)
    sv = np.concatenate([sv, np.zeros(U.shape[1] - sv.size)])
    return vt[sv < _ZERO * max(1.0, sv[0] if sv.size else 1.0)].T


def restricted_quadrics(Q, G):
    """The second-order matrices restricted to beta = G gamma and
    orthonormalised again (eq. 18): shape (s', k, k), dependent ones dropped."""
    Qr = np.einsum("ai,jab,bk->jik", G, Q, G)
    M = Qr.reshape(Qr.shape[0], -1)
    _, sv, vt = np.linalg.svd(M, full_matrices=False)
    keep = sv > _ZERO * sv[0] if sv.size and sv[0] > 0 else np.zeros(0, bool)
    Qs = vt[keep].reshape(-1, G.shape[1], G.shape[1])
    return 0.5 * (Qs + Qs.transpose(0, 2, 1))


def symmetric_solutions(a, P, threads=2, seed=1):
    """Second-order solutions at the bifurcation `a` that keep the symmetry P:
    returns (betas (nsol, m_internal), accounting of the restricted
    homotopy, k = dimension of the symmetric subspace, s' = independent
    restricted equations)."""
    from .assembly import solve_quadrics
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
    return gam @ G.T, acc, k, Qs.shape[0]
