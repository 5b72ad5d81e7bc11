"""atlas_index.ConfigIndex: the sorted-key window never loses a neighbour
that a scan over every entry would find, and returns labels in order."""
import numpy as np
import pytest

from libkin.atlas_index import ConfigIndex


def _aligned_distance(X, Y):
    cx, cy = X.mean(axis=0), Y.mean(axis=0)
    U, _, Vt = np.linalg.svd((X - cx).T @ (Y - cy))
    D = np.eye(X.shape[1])
    D[-1, -1] = np.sign(np.linalg.det(Vt.T @ U.T)) or 1.0
    return float(np.abs((X - cx) @ (Vt.T @ D @ U.T).T + cy - Y).max())


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
    dist = _aligned_distance if rigid else (lambda X, Y: float(np.abs(X - Y).max()))
    found = 0
    for Y in entries[::5]:
        truth = [i for i, X in enumerate(entries) if dist(X, Y) <= tol]
        cands = idx.near(Y, tol)
        assert cands == sorted(cands)
        assert set(truth) <= set(cands)
        assert len(cands) < len(entries) // 4   # a window, not the whole list
        found += len(truth)
    assert found > len(entries[::5])  # the clusters do have neighbours beyond the query itself
