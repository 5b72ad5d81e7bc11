"""A node's stabiliser at work: the symmetries of the structure that fix a
node, acting on its internal mechanisms (the group the complete solver
takes, so that it tracks one homotopy path per orbit of start roots), and
the branches that keep the node's symmetry (explore(symmetric=True)).

symmetry=True (the default of explore and Assembly.branches) gives the
complete solve at a node the group R_g = U^T P_g U of its stabiliser (U the
internal mechanisms, P_g a symmetry's action on the free coordinates) where
that helps: s >= SYMMETRIC_SOLVE_MIN_S (below, 2^s paths take milliseconds)
and a cyclic subgroup permutes the mechanisms and the equations alike
(kin_quadrics_equivariant_form finds one: the equivariant route, whose
roots are the plain solver's, docs/performance.md). Otherwise the plain
solver, as with symmetry=False.
"""
from __future__ import annotations

from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np
from numpy.typing import NDArray

from ..assembly._branching import SYMMETRIC_SOLVE_MIN_S, equivariant_order
from .solving import OVERDETERMINED_TOL

# R_g = U^T P_g U must be orthogonal to this (U's span kept by g)
ORTHOGONAL_TOL = 1e-8


def fixing(syms: Sequence[Any], coords: NDArray[np.float64], tol: float, proper_only: bool = False) -> List[int]:
    """Indices of the symmetries (not the identity) that map coords onto
    itself to tol (max-norm); proper_only: the rotations only."""
    return [j for j, g in enumerate(syms)
            if not g.is_identity and (g.proper or not proper_only)
            and np.abs(g.apply(coords) - coords).max() <= tol]


def mechanism_action(U: NDArray[np.float64], P: Sequence[NDArray[np.float64]]) -> Optional[NDArray[np.float64]]:
    """The stabiliser acting on beta: (k, m, m) with the identity first and
    R_g = U^T P_g U for each P_g (duplicates up to sign dropped, as the C
    solver counts them once); None if some R_g is not orthogonal to
    ORTHOGONAL_TOL (U's span not kept: a point located too coarsely)."""
    m = U.shape[1]
    out = [np.eye(m)]
    for Pg in P:
        R = U.T @ Pg @ U
        if np.abs(R.T @ R - np.eye(m)).max() > ORTHOGONAL_TOL:
            return None
        if not any(np.abs(R - S).max() <= ORTHOGONAL_TOL or np.abs(R + S).max() <= ORTHOGONAL_TOL for S in out):
            out.append(R)
    return np.array(out)


def useful_group(Q: NDArray[np.float64], R: Optional[NDArray[np.float64]], seed: int) -> bool:
    """True if the symmetric solver pays on Q with the group R: s large
    enough, R more than +-identity, and a cyclic subgroup that permutes
    mechanisms and equations alike (the equivariant route, the plain
    solver's roots with 1/order of its paths)."""
    if R is None or len(R) < 2 or Q.shape[0] < SYMMETRIC_SOLVE_MIN_S:
        return False
    return equivariant_order(Q, R, seed) >= 2


def subspace_branches(U: NDArray[np.float64], Q: NDArray[np.float64], P: Sequence[NDArray[np.float64]],
                      solve_system: Any) -> Tuple[Optional[NDArray[np.float64]], Dict[str, Any]]:
    """explore(symmetric=True): the betas (n, m) of the branches whose U beta
    is invariant under the rotations P that fix the node (the second-order
    system restricted to that subspace, symmetry/cyclic.py), and a record;
    None with a reason if there are none. solve_system(Q', k) solves the
    restricted system."""
    from ..symmetry.automorphisms import invariant_subspace
    from ..symmetry.cyclic import restricted_quadrics
    G = invariant_subspace(U, list(P))
    k = G.shape[1]
    rec: Dict[str, Any] = {"mode": "symmetric", "group_order": len(P) + 1, "k": k}
    if k == 0:
        return None, dict(rec, solutions=0, reason="no first-order mechanism keeps the symmetry")
    if k == 1:
        # one symmetric mechanism g: a branch if it solves every
        # second-order equation (the Q_j have unit norm, eq. 18)
        g = G[:, 0]
        resid = float(np.abs(np.einsum("x,jxy,y->j", g, Q, g)).max()) if len(Q) else 0.0
        rec["residual"] = resid
        if resid > OVERDETERMINED_TOL:
            return None, dict(rec, solutions=0, reason="the one symmetric mechanism does not extend to "
                                                       "second order")
        return G.T.copy(), dict(rec, solutions=1)
    Qs = restricted_quadrics(Q, G)
    rec["s_restricted"] = int(Qs.shape[0])
    gam, more = solve_system(Qs, k)
    rec.update(more)
    return (None if gam is None else gam @ G.T), rec
