"""Which configurations of an atlas lie near a given one, without comparing
against every node.

The explorer identifies a followed branch's end with a node when the two
configurations agree to a tolerance in the max-norm (after aligning them by
a rigid motion when the supports allow one). A linear scan makes a depth-1
atlas of n branches cost n x nodes distance evaluations: 59,656 branches out
of the hexagonal sail's flat state and thousands of distinct ends would take
hours. This index keeps one feature vector per entry, f(X) = the
coordinates (or, up to rigid motions, each joint's distance to the
centroid, which an alignment does not change); two configurations within
tol of each other have features within tol (tol x sqrt(dim) for the
distances: a joint within tol per coordinate is within tol sqrt(dim) in
length) in the max-norm, and near() returns exactly the entries whose
features are, sorted by label: the first match of the caller's exact test
is the one a scan in node order would have found.

The entries are found through hash grids on two fixed random projections
of the features (w . f moves by at most |w|_1 tol): a query looks up the
cells around its own projections and checks the few entries there in the
max-norm, in one NumPy operation. The grids' cells are the first query's
radius times 4^level (any integer level); a query uses the finest grid
whose cell is at least half its radius (at most 5 x 5 cells), made when
first needed (a coarsely located point's query is 100 times wider than the
others). Measured
on the hexagonal sail's full atlas (59,656 branch ends, 20,523 nodes and
their images under 6 symmetries): 498,631 queries took 31.8 s of the
client's CPU with the former index (k-d trees, scipy.spatial.cKDTree, in
Bentley and Saxe's logarithmic method, which itself had replaced a window
on one sorted scalar key at half the cost); the whole merge of those ends
took 19.6 s of CPU then and 4.8 s now (docs/atlas.md).
"""
from __future__ import annotations

import math
from typing import Any, Callable, Dict, List, Tuple

import numpy as np
from numpy.typing import NDArray

# projections of the features the grids are made on
_AXES = 2  # (near_features is written for two)
# GroupedIndex: the points known to better than 10^_FINEST form one group
_FINEST = -9
# the cells of grid level L: the first query's radius x _RATIO^L; a query
# of radius r uses the finest level whose cell is at least r / _REACH
_RATIO, _REACH = 4.0, 2.0


class ConfigIndex:
    """Entries (features, label); label is any sortable value (a node id,
    or (node id, symmetry index)). seed: of the projections (any value
    gives the same answers)."""

    def __init__(self, shape: Tuple[int, int], rigid: bool, seed: int = 20261123) -> None:
        njoints, dim = shape
        self.rigid = rigid
        # a max-norm distance tol moves each feature by at most tol * spread
        self.spread = math.sqrt(dim) if rigid else 1.0
        nfeat = njoints if rigid else njoints * dim
        w = np.random.default_rng(seed).normal(size=(_AXES, nfeat))
        self._w = w / np.linalg.norm(w, axis=1)[:, None]
        self._w1 = np.abs(self._w).sum(axis=1)  # |w|_1: how far a max-norm radius moves a projection
        self._f = np.empty((16, nfeat))  # the entries' features, first _n rows
        self._p = np.empty((16, _AXES))  # and their projections
        self._n = 0
        self._labels: List[Any] = []
        self._cell0 = 0.0  # the cell of level 0 (0: no query yet, no grid)
        self._grids: Dict[int, Dict[Tuple[int, ...], List[int]]] = {}  # level -> cell -> entries

    def _features(self, X: NDArray[np.float64]) -> NDArray[np.float64]:
        if self.rigid:
            return np.sqrt(((X - X.mean(axis=0)) ** 2).sum(axis=1))
        return np.asarray(X, dtype=float).ravel()

    def _cell(self, level: int) -> float:
        return float(self._cell0 * _RATIO ** level)

    def add(self, X: NDArray[np.float64], label: Any) -> None:
        f = self._features(X)
        if f.size != self._f.shape[1]:
            raise ValueError(f"a configuration of {f.size} features in an index of {self._f.shape[1]}")
        if self._n == len(self._f):
            self._f = np.concatenate([self._f, np.empty_like(self._f)])
            self._p = np.concatenate([self._p, np.empty_like(self._p)])
        i = self._n
        self._f[i] = f
        self._p[i] = self._w @ f
        self._n += 1
        self._labels.append(label)
        p0, p1 = self._p[i].tolist()
        for level, grid in self._grids.items():
            cell = self._cell(level)
            grid.setdefault((math.floor(p0 / cell), math.floor(p1 / cell)), []).append(i)

    def _grid(self, level: int) -> Dict[Tuple[int, ...], List[int]]:
        grid = self._grids.get(level)
        if grid is None:  # made when first needed, then kept up to date by add()
            grid = self._grids[level] = {}
            keys = np.floor(self._p[: self._n] / self._cell(level)).astype(np.int64)
            for i, k in enumerate(map(tuple, keys.tolist())):
                grid.setdefault(k, []).append(i)
        return grid

    def clear(self) -> None:
        self._n = 0
        self._labels = []
        self._grids = {}

    def near(self, X: NDArray[np.float64], tol: float) -> List[Any]:
        """Labels of every entry whose features lie within tol (x spread) of
        X's in the max-norm, sorted; a superset of the true neighbours."""
        f = self._features(X)
        return self.near_features(f, self._w @ f, tol)

    def near_features(self, f: NDArray[np.float64], p: NDArray[np.float64], tol: float) -> List[Any]:
        """near() of a configuration given by its features f and their
        projections p (self._w @ f: the same in every index of one shape
        and seed, so GroupedIndex makes them once)."""
        # the radius, plus the rounding in the features themselves (far
        # below any tolerance the explorer uses, but never let it drop a match)
        r = tol * self.spread + 1e-12 * self.spread * (float(np.abs(f).max()) + 1.0)
        if not self._n:
            return []
        p0, p1 = p.tolist()
        w0, w1 = self._w1.tolist()
        r0, r1 = r * w0 + 1e-12 * (abs(p0) + 1.0), r * w1 + 1e-12 * (abs(p1) + 1.0)  # with their rounding
        reach = max(r0, r1)
        if self._cell0 == 0.0:
            self._cell0 = reach if reach > 0.0 else 1.0
        level = math.ceil(math.log(reach / (_REACH * self._cell0), _RATIO)) if reach > 0.0 else 0
        while self._cell(level) * _REACH < reach:  # the log's rounding, either way
            level += 1
        while reach > 0.0 and self._cell(level - 1) * _REACH >= reach:
            level -= 1
        grid, cell = self._grid(level), self._cell(level)
        b0, b1 = math.floor((p1 - r1) / cell), math.floor((p1 + r1) / cell)
        cand: List[int] = []
        for a in range(math.floor((p0 - r0) / cell), math.floor((p0 + r0) / cell) + 1):
            for b in range(b0, b1 + 1):
                got = grid.get((a, b))
                if got:
                    cand += got
        if not cand:
            return []
        rows = np.array(cand)
        d = np.abs(self._f[rows] - f).max(axis=1)
        return sorted(self._labels[i] for i in rows[d <= r])

    def __len__(self) -> int:
        return self._n


class GroupedIndex:
    """ConfigIndex entries grouped by how coarsely each point is known.

    Two points are one node within a tolerance that grows with their
    location accuracies (model.pair_window, the explorer's pair_tol). One index queried with
    the coarsest accuracy in the atlas would make a single point located to
    1e-6 widen every query a hundredfold; grouping the entries by decade of
    their accuracy lets each group be queried with its own widest tolerance.
    The points known to better than 1e-9 (those located to the strict 1e-10,
    and the unlocated ones, 0) are one group: a query costs about the same
    in each group, and their windows differ by 3x at most (the merge of the
    hexagonal flat state's atlas 5.7 -> 5.0 s with 4 groups instead of 6; a
    group's wider window only adds candidates, which the caller's exact test
    drops, so the answers are the same).
    """

    def __init__(self, shape: Tuple[int, int], rigid: bool) -> None:
        self.shape, self.rigid = shape, rigid
        self.groups: dict[int, Tuple[ConfigIndex, List[float]]] = {}

    @staticmethod
    def _decade(located: float) -> int:
        return max(_FINEST, -400 if located <= 0.0 else math.floor(math.log10(located)))

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
        if not self.groups:
            return out
        first = next(iter(self.groups.values()))[0]
        f = first._features(X)
        p = first._w @ f  # the same features and projections in every group
        for idx, worst in self.groups.values():
            out += idx.near_features(f, p, window(worst[0]))
        return sorted(out)

    def clear(self) -> None:
        self.groups.clear()

    def __len__(self) -> int:
        return sum(len(idx) for idx, _ in self.groups.values())
