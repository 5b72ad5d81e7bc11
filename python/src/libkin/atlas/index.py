"""Which configurations of an atlas lie near a given one, without comparing
against every node.

The explorer identifies a followed branch's end with a node when the two
configurations agree to a tolerance in the max-norm (after aligning them by
a rigid motion when the supports allow one). A linear scan makes a depth-1
atlas of n branches cost n x nodes distance evaluations: 59,656 branches out
of the hexagonal sail's flat state and thousands of distinct ends would take
hours. This index keeps one scalar key per entry, key(X) = w . f(X), with
f(X) the coordinates (or, up to rigid motions, each joint's distance to the
centroid, which an alignment does not change) and w fixed random weights,
sorted. Two configurations within tol of each other have keys within
tol x |w|_1 (x sqrt(dim) for the distances), so the entries in that window
of the sorted keys are the only candidates; the caller still applies its
exact test to each. The candidates come out in the order of their labels, so
the first match is the one a scan in node order would have found.
"""
from __future__ import annotations

import bisect
import math
from typing import Any, Callable, List, Tuple

import numpy as np
from numpy.typing import NDArray


class ConfigIndex:
    """Entries (key, label) sorted by key; label is any sortable value
    (a node id, or (node id, symmetry index))."""

    def __init__(self, shape: Tuple[int, int], rigid: bool, seed: int = 20261123) -> None:
        njoints, dim = shape
        self.rigid = rigid
        n = njoints if rigid else njoints * dim
        self.w = np.random.default_rng(seed).uniform(-1.0, 1.0, n)
        # a max-norm distance tol moves the key by at most tol * spread
        self.spread = float(np.abs(self.w).sum()) * (math.sqrt(dim) if rigid else 1.0)
        self.keys: List[float] = []
        self.labels: List[Any] = []

    def _features(self, X: NDArray[np.float64]) -> NDArray[np.float64]:
        if self.rigid:
            return np.sqrt(((X - X.mean(axis=0)) ** 2).sum(axis=1))
        return X.ravel()

    def key(self, X: NDArray[np.float64]) -> float:
        return float(self._features(X) @ self.w)

    def add(self, X: NDArray[np.float64], label: Any) -> None:
        k = self.key(X)
        i = bisect.bisect_right(self.keys, k)
        self.keys.insert(i, k)
        self.labels.insert(i, label)

    def clear(self) -> None:
        self.keys.clear()
        self.labels.clear()

    def near(self, X: NDArray[np.float64], tol: float) -> List[Any]:
        """Labels of every entry that can lie within tol of X (max-norm),
        sorted; a superset of the true neighbours."""
        f = self._features(X)
        k = float(f @ self.w)
        # the window, plus the rounding in the keys themselves (far below
        # any tolerance the explorer uses, but never let it drop a match)
        r = tol * self.spread + 1e-12 * self.spread * (float(np.abs(f).max()) + 1.0)
        lo = bisect.bisect_left(self.keys, k - r)
        hi = bisect.bisect_right(self.keys, k + r)
        return sorted(self.labels[lo:hi])

    def __len__(self) -> int:
        return len(self.keys)


class GroupedIndex:
    """ConfigIndex entries grouped by how coarsely each point is known.

    Two points are one node within a tolerance that grows with the coarser
    of their location accuracies (atlas.py, pair_tol). One index queried with
    the coarsest accuracy in the atlas would make a single point located to
    1e-6 widen every query a hundredfold; grouping the entries by decade of
    their accuracy lets each group be queried with its own widest tolerance.
    """

    def __init__(self, shape: Tuple[int, int], rigid: bool) -> None:
        self.shape, self.rigid = shape, rigid
        self.groups: dict[int, Tuple[ConfigIndex, List[float]]] = {}

    @staticmethod
    def _decade(located: float) -> int:
        return -400 if located <= 0.0 else math.floor(math.log10(located))

    def add(self, X: NDArray[np.float64], label: Any, located: float) -> None:
        d = self._decade(located)
        if d not in self.groups:
            self.groups[d] = (ConfigIndex(self.shape, self.rigid), [0.0])
        idx, worst = self.groups[d]
        idx.add(X, label)
        worst[0] = max(worst[0], located)

    def near(self, X: NDArray[np.float64], window: Callable[[float], float]) -> List[Any]:
        """Labels of every entry that can lie within window(g) of X, g the
        coarsest accuracy in the entry's group; sorted."""
        out: List[Any] = []
        for idx, worst in self.groups.values():
            out += idx.near(X, window(worst[0]))
        return sorted(out)

    def clear(self) -> None:
        self.groups.clear()

    def __len__(self) -> int:
        return sum(len(idx) for idx, _ in self.groups.values())
