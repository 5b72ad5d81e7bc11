"""Which configurations of an atlas lie near a given one, without comparing
against every node.

The explorer identifies a followed branch's end with a node when the two
configurations agree to a tolerance in the max-norm (after aligning them by
a rigid motion when the supports allow one). A linear scan makes a depth-1
atlas of n branches cost n x nodes distance evaluations: 59,656 branches out
of the hexagonal sail's flat state and thousands of distinct ends would take
hours. This index keeps one feature vector per entry, f(X) = the
coordinates (or, up to rigid motions, each joint's distance to the
centroid, which an alignment does not change), in k-d trees
(scipy.spatial.cKDTree), and returns the entries whose features lie within
tol of f(X) in the max-norm (tol x sqrt(dim) for the distances: a joint
within tol per coordinate is within tol sqrt(dim) in length). Two
configurations within tol of each other are such entries, so they are the
only candidates; the caller still applies its exact test to each. The
candidates come out in the order of their labels, so the first match is
the one a scan in node order would have found.

Entries are added one by one between queries, so the trees are kept as in
Bentley and Saxe's logarithmic method: the newest entries (fewer than
_BLOCK) are scanned directly, the others sit in trees of _BLOCK x 2^k
entries, two trees of one size merged into one of twice the size: a query
searches O(log n) trees, an entry is built into a tree O(log n) times.
Measured (2 cores, load 2-4): merging 59,656 synthetic branch ends of the
hexagonal sail (3,905 ends and their images under its 6 symmetries, each
reached ~2.5 times) takes 28 s, against 52-58 s with the former index (one
sorted scalar key w . f(X) per entry, random weights w, a window of
candidates around the key); 26 s against 62 s for the square sail (4
symmetries, rigid: up to rigid motions); the same nodes and orbits.
"""
from __future__ import annotations

import math
from typing import Any, Callable, List, Tuple

import numpy as np
from numpy.typing import NDArray

# entries scanned directly before they go into a tree
_BLOCK = 256


class ConfigIndex:
    """Entries (features, label); label is any sortable value (a node id,
    or (node id, symmetry index)). `seed` is accepted for callers of the
    former projection index and not used."""

    def __init__(self, shape: Tuple[int, int], rigid: bool, seed: int = 20261123) -> None:
        _, dim = shape
        self.rigid = rigid
        # a max-norm distance tol moves each feature by at most tol * spread
        self.spread = math.sqrt(dim) if rigid else 1.0
        self._recent = np.empty((_BLOCK, 0))  # the newest entries' features, first _nrecent rows
        self._nrecent = 0
        self._recent_labels: List[Any] = []
        self._trees: List[Tuple[Any, NDArray[np.float64], List[Any]]] = []  # (tree, points, labels)

    def _features(self, X: NDArray[np.float64]) -> NDArray[np.float64]:
        if self.rigid:
            return np.sqrt(((X - X.mean(axis=0)) ** 2).sum(axis=1))
        return np.asarray(X, dtype=float).ravel()

    def add(self, X: NDArray[np.float64], label: Any) -> None:
        f = self._features(X)
        if self._recent.shape[1] != f.size:
            self._recent = np.empty((_BLOCK, f.size))
        self._recent[self._nrecent] = f
        self._nrecent += 1
        self._recent_labels.append(label)
        if self._nrecent < _BLOCK:
            return
        from scipy.spatial import cKDTree
        pts, labels = self._recent.copy(), self._recent_labels
        self._nrecent, self._recent_labels = 0, []
        while self._trees and len(self._trees[-1][2]) == len(labels):
            _, p, lab = self._trees.pop()
            pts, labels = np.vstack([p, pts]), lab + labels
        self._trees.append((cKDTree(pts), pts, labels))

    def clear(self) -> None:
        self._nrecent = 0
        self._recent_labels = []
        self._trees = []

    def near(self, X: NDArray[np.float64], tol: float) -> List[Any]:
        """Labels of every entry that can lie within tol of X (max-norm),
        sorted; a superset of the true neighbours."""
        f = self._features(X)
        # the radius, plus the rounding in the features themselves (far
        # below any tolerance the explorer uses, but never let it drop a match)
        r = tol * self.spread + 1e-12 * self.spread * (float(np.abs(f).max()) + 1.0)
        out: List[Any] = []
        if self._nrecent:
            d = np.abs(self._recent[: self._nrecent] - f).max(axis=1)
            out += [self._recent_labels[i] for i in np.flatnonzero(d <= r)]
        for tree, _, labels in self._trees:
            out += [labels[i] for i in tree.query_ball_point(f, r, p=np.inf)]
        return sorted(out)

    def __len__(self) -> int:
        return self._nrecent + sum(len(lab) for _, _, lab in self._trees)


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
