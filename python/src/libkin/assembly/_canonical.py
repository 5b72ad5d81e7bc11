"""The canonical order and sign of second-order solutions (issue 35).

The complete solver returns one beta of each +-beta pair in the order of
its paths, in the coordinates of the mechanism basis U that the SVD gave.
That basis is arbitrary: another OpenBLAS kernel or thread count rotates it
(a 1e-15 change of H turned the hexagonal sail's 16-dimensional basis by
up to 1.1 rad), and with it Q, the solver's paths, their order and the
sign of each beta. What does not change is the physical direction
d = U beta / |U beta| in joint coordinates. So the solutions are put in an
order and given a sign decided from d alone, never from beta:

* sign: d . w_0 > 0 for a fixed unit vector w_0 of generic entries; where
  |d . w_0| <= SIGN_TOL, the first of w_1, w_2, ... with |d . w_k| >
  SIGN_TOL decides;
* order: increasing d . w_1 (after the sign); solutions whose keys lie
  within ORDER_TOL of each other (a chain of such gaps) are ordered among
  themselves by d . w_2, then w_3, ...

The w_k are the same on every machine: their entries come from integer
arithmetic (splitmix64 of the index), not from a random generator whose
stream could change with NumPy. They are "generic": no structure's
symmetry maps them onto themselves, so d . w_k is a continuous function
of d with no reason to vanish or to tie. For unit d in R^n, d . w_k is
spread over about +-1/sqrt(n) (0.15 for the hexagonal sail's 46 free
coordinates). The directions agree between machines far closer: on the
sail's flat state (16 mechanisms, 14,914 real solutions) the Haswell and
the default kernel's U differed by 1.38 and the 14,914 directions by
6e-12 at most. So a sign is ambiguous only if |d . w_0| lies within about
1e-11 of SIGN_TOL (there the smallest |d . w_0| was 1.4e-5), and an order
only if two neighbouring keys d . w_1 lie within about 1e-11 of each other
or of ORDER_TOL: with N keys spread over a width D, about N^2 * 1e-11 / D,
2e-8 for the 32 of the sail's symmetric motions and 3e-3 for the 14,914 of
its flat state's complete solve (there the smallest gap was 2e-10), and
even then only two neighbours in the numbering swap, not the whole list
as before. A tie that survives every key is broken by the solver's order
(a stable sort).
"""
from __future__ import annotations

from functools import lru_cache
from typing import List, Optional, Tuple

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]

# |d . w_k| at or below this: w_k does not decide the sign, the next does
SIGN_TOL = 1e-6
# keys d . w_k closer than this: ordered by the next key
ORDER_TOL = 1e-7
# how many generic vectors: w_0 the sign, w_1.. the order and its tie-breaks
KEYS = 4
_MASK = (1 << 64) - 1


def _splitmix64(x: int) -> int:
    x = (x + 0x9E3779B97F4A7C15) & _MASK
    x = ((x ^ (x >> 30)) * 0xBF58476D1CE4E5B9) & _MASK
    x = ((x ^ (x >> 27)) * 0x94D049BB133111EB) & _MASK
    return x ^ (x >> 31)


@lru_cache(maxsize=16)
def generic_vectors(n: int, count: int = KEYS) -> FloatArray:
    """count fixed unit vectors of n generic entries (count, n), the same
    on every machine: entry i of vector k is splitmix64(k * 2^32 + i)
    mapped to [-1, 1) exactly (53 bits), then the row normalised."""
    W = np.empty((count, n))
    for k in range(count):
        for i in range(n):
            W[k, i] = (_splitmix64((k << 32) + i) >> 11) / float(1 << 52) - 1.0
    W /= np.linalg.norm(W, axis=1)[:, None]
    W.setflags(write=False)
    return W


def _order(keys: FloatArray, idx: npt.NDArray[np.intp], k: int) -> List[int]:
    """idx ordered by keys[:, k], runs closer than ORDER_TOL by the next key."""
    idx = idx[np.argsort(keys[idx, k], kind="stable")]
    if k + 1 >= keys.shape[1] or len(idx) < 2:
        return [int(i) for i in idx]
    out: List[int] = []
    gaps = np.diff(keys[idx, k]) > ORDER_TOL
    start = 0
    for j in range(1, len(idx) + 1):
        if j == len(idx) or gaps[j - 1]:
            run = idx[start:j]
            out.extend(_order(keys, run, k + 1) if len(run) > 1 else [int(run[0])])
            start = j
    return out


def canonical_order(betas: npt.ArrayLike, basis: Optional[npt.ArrayLike] = None) -> Tuple[FloatArray,
                                                                                        npt.NDArray[np.intp],
                                                                                        npt.NDArray[np.int_]]:
    """The solutions in the canonical order with the canonical sign.

    Parameters
    ----------
    betas : array_like, shape (nsol, m)
        Second-order solutions (one of each +-beta pair), in any order.
    basis : array_like, shape (n, m), optional
        The mechanism basis U (``analyse().internal_mechanisms``): the key
        is the physical direction U beta, the same whichever basis of the
        mechanism space U is. None: beta itself (canonical for this Q, in
        its coordinates).

    Returns
    -------
    betas : ndarray, shape (nsol, m)
        ``sign[j] * betas[perm[j]]``.
    perm : ndarray of int, shape (nsol,)
        Where each came from.
    sign : ndarray of int, shape (nsol,)
        +1 or -1: the sign applied.
    """
    b = np.atleast_2d(np.asarray(betas, dtype=np.float64))
    if b.size == 0:
        return b.reshape(0, b.shape[1] if b.ndim == 2 else 0), np.zeros(0, dtype=np.intp), np.zeros(0, dtype=int)
    D = b if basis is None else b @ np.asarray(basis, dtype=np.float64).T
    norms = np.linalg.norm(D, axis=1)
    D = D / np.where(norms > 0.0, norms, 1.0)[:, None]
    keys = D @ generic_vectors(D.shape[1]).T
    sign = np.ones(len(b), dtype=int)
    for j in range(len(b)):
        k = int(np.argmax(np.abs(keys[j]) > SIGN_TOL)) if (np.abs(keys[j]) > SIGN_TOL).any() else 0
        if keys[j, k] < 0.0:
            sign[j] = -1
    keys = keys * sign[:, None]
    perm = np.asarray(_order(keys, np.arange(len(b)), 1), dtype=np.intp)
    return b[perm] * sign[perm, None], perm, sign[perm]


def canonical(betas: npt.ArrayLike, basis: Optional[npt.ArrayLike] = None) -> FloatArray:
    """`canonical_order`'s betas alone."""
    return canonical_order(betas, basis)[0]
