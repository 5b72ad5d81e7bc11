"""atlas.index.ConfigIndex: the grid never loses a neighbour that a scan
over every entry would find, whatever the radius of a query, and returns
labels in order."""
import numpy as np
import pytest

from libkin.symmetry.procrustes import aligned_distance
from libkin.atlas.index import ConfigIndex


def _random_rotation(rng, dim):
    q, r = np.linalg.qr(rng.normal(size=(dim, dim)))
    q = q * np.sign(np.diag(r))
    if np.linalg.det(q) < 0:
        q[:, 0] = -q[:, 0]
    return q


@pytest.mark.parametrize("rigid", [False, True])
@pytest.mark.parametrize("dim", [2, 3])
def test_window_finds_every_neighbour(rigid, dim):
    rng = np.random.default_rng(7 + dim + 10 * rigid)
    njoints, tol = 9, 1e-3
    base = [rng.normal(size=(njoints, dim)) for _ in range(40)]
    entries = []
    for b in base:  # clusters: copies within and just beyond tol, moved rigidly when allowed
        for k in range(6):
            X = b + rng.uniform(-1, 1, size=b.shape) * tol * (0.3 if k < 3 else 3.0)
            if rigid:
                X = X @ _random_rotation(rng, dim).T + rng.normal(size=dim)
            entries.append(X)
    idx = ConfigIndex((njoints, dim), rigid)
    for i, X in enumerate(entries):
        idx.add(X, i)
    dist = aligned_distance if rigid else (lambda X, Y: float(np.abs(X - Y).max()))
    found = 0
    for Y in entries[::5]:
        truth = [i for i, X in enumerate(entries) if dist(X, Y) <= tol]
        cands = idx.near(Y, tol)
        assert cands == sorted(cands)
        assert set(truth) <= set(cands)
        assert len(cands) < len(entries) // 4   # a window, not the whole list
        found += len(truth)
    assert found > len(entries[::5])  # the clusters do have neighbours beyond the query itself


def test_grouped_window_per_accuracy():
    """Each group is searched with its own tolerance: a coarse entry is
    found from far, and does not widen the search among the fine ones."""
    from libkin.atlas.index import GroupedIndex
    rng = np.random.default_rng(3)
    shape = (8, 3)
    idx = GroupedIndex(shape, rigid=False)
    entries = [(rng.normal(size=shape), 1e-10 if k % 50 else 1e-4) for k in range(500)]
    for i, (X, loc) in enumerate(entries):
        idx.add(X, i, loc)

    def window(worst):  # as atlas.pair_tol: grows with the coarser accuracy
        return max(1e-6, 10.0 * np.sqrt(worst))

    for q in range(0, 500, 7):
        Y = entries[q][0] + rng.uniform(-1, 1, size=shape) * 0.05
        truth = [i for i, (X, loc) in enumerate(entries) if np.abs(X - Y).max() <= window(loc)]
        cands = idx.near(Y, window)
        assert cands == sorted(cands) and set(truth) <= set(cands)
        # the fine entries' window (1e-4) admits only a few of them
        assert sum(1 for c in cands if entries[c][1] < 1e-9) < 50
    assert len(idx) == 500


@pytest.mark.parametrize("rigid", [False, True])
def test_any_radius_gives_exactly_the_scan(rigid):
    """Queries of radii from 1e-9 to 10 (the grids' levels made as they are
    needed, in any order, entries added between queries) return exactly the
    entries a scan of the features finds, in label order."""
    rng = np.random.default_rng(11 + rigid)
    shape = (7, 3)
    idx = ConfigIndex(shape, rigid)
    pts = []
    for k in range(600):
        base = pts[rng.integers(len(pts))] if pts and k % 3 else rng.normal(size=shape)
        X = base + rng.normal(size=shape) * 10.0 ** rng.uniform(-9, 0)
        pts.append(X)
        idx.add(X, k)
        if k % 4 == 0:
            Y = pts[rng.integers(len(pts))] + rng.normal(size=shape) * 10.0 ** rng.uniform(-10, -1)
            tol = 10.0 ** rng.uniform(-9, 1)
            fy = idx._features(Y)
            r = tol * idx.spread + 1e-12 * idx.spread * (float(np.abs(fy).max()) + 1.0)
            truth = [i for i, X in enumerate(pts) if np.abs(idx._features(X) - fy).max() <= r]
            assert idx.near(Y, tol) == truth
