"""Directed branches related by a symmetry of the node they leave.

A symmetry g of the structure that fixes a node (g.apply(node) = node) maps
every path out of it onto another: the branch along P_g d is the image under
g of the branch along d (P_g: g acting on the free coordinates), so its next
event is the same and its end is g applied to the other's end. With
`explore(..., follow_orbits=True)` one branch per orbit is followed and the
others are mapped, which divides the following by up to the order of the
node's stabilizer (6 at the hexagonal sail's flat state, where the mirror
z -> -z maps each branch onto its opposite sense).

The branches are matched through index.ConfigIndex (a sorted scalar key
of the unit directions), so n branches cost O(n log n) rather than n^2
comparisons.
"""
from __future__ import annotations

from typing import Any, Dict, List, Sequence, Tuple

import numpy as np
from numpy.typing import NDArray

from .index import ConfigIndex

# two unit directions are the same branch when they agree to this (max-norm);
# the complete solver's roots are certified far below it, and distinct
# branches are far apart
SAME_DIRECTION = 1e-6


def branch_orbits(directions: Sequence[NDArray[np.float64]], P: Sequence[NDArray[np.float64]],
                  seed: int = 20261123) -> List[Tuple[int, int]]:
    """For every directed branch k: (rep, j) with direction k = P[j] @
    direction rep, rep the smallest index of its orbit; (k, -1) for a
    representative. P: the stabilizer's matrices on the free coordinates
    (the identity may be among them)."""
    if not len(directions):
        return []
    D = np.array([d / np.linalg.norm(d) for d in directions])
    index = ConfigIndex((D.shape[1], 1), rigid=False, seed=seed)
    for i, d in enumerate(D):
        index.add(d.reshape(-1, 1), i)
    out: List[Any] = [None] * len(D)
    for k in range(len(D)):
        if out[k] is not None:
            continue
        out[k] = (k, -1)
        for j, Pj in enumerate(P):
            img = Pj @ D[k]
            for i in index.near(img.reshape(-1, 1), SAME_DIRECTION):
                if out[i] is None and np.abs(D[i] - img).max() <= SAME_DIRECTION:
                    out[i] = (k, j)
                    break
    return out


def mapped_result(res: Dict[str, Any], g: Any) -> Dict[str, Any]:
    """The follower's result of a branch mapped by the symmetry g: the same
    event, length and accuracies, the end and the samples moved by g."""
    out = dict(res)
    out["coords"] = g.apply(np.asarray(res["coords"], dtype=float)).tolist()
    out["samples"] = [g.apply(np.asarray(X, dtype=float)).tolist() for X in res.get("samples", [])]
    out["cpu_seconds"] = 0.0
    out["mapped"] = True
    return out
