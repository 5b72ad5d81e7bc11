"""The complete solver with symmetry from Python: solve_quadrics(group=...)
against the plain solver on sail flat states, mechanism_group, and the
errors."""
import numpy as np
import pytest

import libkin
from libkin import solve_quadrics
from libkin.symmetry.automorphisms import mechanism_group
from libkin.errors import InvalidArgumentError


def same_roots(a, b):
    """every row of a is +-a row of b"""
    return all(min(np.abs(b - r).max(axis=1).min(), np.abs(b + r).max(axis=1).min()) < 1e-8 for r in a)


@pytest.mark.parametrize("sides,loops", [(6, 1), (4, 1)])
def test_sail_flat_state_same_roots(sides, loops):
    a = libkin.Assembly.sail(sides, loops)
    Q = a.second_order()
    R = mechanism_group(a)
    m = Q.shape[1]
    assert R.shape[1:] == (m, m)
    assert np.allclose(R[0], np.eye(m))
    for Rg in R:  # orthogonal, and the system equivariant: R^T Q_j R in the span of the Q_j
        assert np.abs(Rg.T @ Rg - np.eye(m)).max() < 1e-10
        M = Q.reshape(len(Q), -1).T
        for Qj in Q:
            coef = np.linalg.lstsq(M, (Rg.T @ Qj @ Rg).ravel(), rcond=None)[0]
            assert np.abs(M @ coef - (Rg.T @ Qj @ Rg).ravel()).max() < 1e-9
    b0, acc0 = solve_quadrics(Q, "homotopy")
    b1, acc1 = solve_quadrics(Q, "homotopy", group=R)
    s = len(Q)
    assert acc1["paths"] == 2 ** s and acc1["found"] == 2 ** s
    assert acc1["real"] + acc1["nonreal"] + acc1["singular"] + acc1["failed"] == 2 ** s
    for k in ("real", "real_distinct", "nonreal", "singular", "failed", "duplicates", "unpaired"):
        assert acc1[k] == acc0[k], k
    assert len(b1) == len(b0) and same_roots(b1, b0) and same_roots(b0, b1)
    if sides == 6:  # C3 (the mirror z -> -z acts as -I): orbits of 3 or 1
        assert acc1["group"] == 3 and acc1["orbits"] < 2 ** s
        # it permutes 3 triples of mechanisms and of self-stresses alike: the
        # equivariant start system, one path per orbit of start roots
        assert acc1["monodromy_paths"] == 0 and acc1["orbits"] == (2 ** 9 - 8) // 3 + 8


def test_group_errors():
    a = libkin.Assembly.sail(6, 1)
    Q = a.second_order()
    R = mechanism_group(a)
    with pytest.raises(InvalidArgumentError):
        solve_quadrics(Q, "homotopy", group=R[:, :2, :2])  # wrong shape
    with pytest.raises(InvalidArgumentError):
        solve_quadrics(Q, "scan", group=R)
    bad = R.copy()
    bad[1, 0, 0] *= 1.01  # not orthogonal
    with pytest.raises(InvalidArgumentError):
        solve_quadrics(Q, "homotopy", group=bad)
    perm = np.eye(Q.shape[1])[[1, 0] + list(range(2, Q.shape[1]))]  # orthogonal, not a symmetry
    with pytest.raises(InvalidArgumentError):
        solve_quadrics(Q, "homotopy", group=perm[None])


def test_sharded_with_group():
    """The equivariant route in shards on a process pool (one path per orbit
    of start roots, the merge on the equivariant form, beta = U x): the
    one-call answer; a group without a qualifying subgroup: every path."""
    from concurrent.futures import ProcessPoolExecutor
    from libkin.homotopy import shards as homotopy_shards
    a = libkin.Assembly.sail(6, 1)
    Q = a.second_order()
    R = mechanism_group(a, method="c")
    form = homotopy_shards.equivariant_form(Q, R)
    assert form is not None
    Qt, U, perm, order, norbits = form
    assert order == 3 and norbits == 176 and perm[0] == 0
    assert np.abs(U.T @ U - np.eye(len(U))).max() < 1e-12
    b0, acc0 = solve_quadrics(Q, "homotopy", group=R)
    with ProcessPoolExecutor(max_workers=2) as ex:
        b1, acc1 = homotopy_shards.solve_sharded(Q, ex, shards=3, group=R)
        b2, acc2 = homotopy_shards.solve_sharded(Q, ex, shards=2, group=np.eye(Q.shape[1])[None])
    for k in ("paths", "real", "real_distinct", "nonreal", "singular", "failed", "duplicates", "unpaired"):
        assert acc1[k] == acc0[k], k
    assert acc1["orbits"] == 176 and acc1["order"] == 3
    assert len(b1) == len(b0) and same_roots(b1, b0) and same_roots(b0, b1)
    assert "orbits" not in acc2 and acc2["real"] == acc0["real"] and same_roots(b2, b0)
    assert homotopy_shards.equivariant_form(Q, np.eye(Q.shape[1])[None]) is None


def test_sharded_proofs_are_about_q():
    """issue 38: the sharded equivariant route proves the caller's Q (not the
    rotated form Qt) at beta = U x: the same proven counts as the one call,
    every root; with a U that does not belong to the form no root of Q is
    proven (refused), none wrongly; bad Q, U refused with an error"""
    from libkin.homotopy import shards as homotopy_shards
    from libkin._native._lib import ffi
    a = libkin.Assembly.sail(6, 1)
    Q = a.second_order()
    R = mechanism_group(a, method="c")
    _, acc0 = solve_quadrics(Q, "homotopy", group=R)
    _, acc1 = homotopy_shards.solve_sharded(Q, None, shards=2, group=R)
    keys = ("proven_real", "proven_nonreal", "unproven", "proven_all")
    assert [acc1[k] for k in keys] == [acc0[k] for k in keys]
    assert acc1["proven_all"] == 1 and acc1["proven_real"] + acc1["proven_nonreal"] == 2 ** Q.shape[0]
    # the same records merged with a wrong U (the form's with two columns swapped)
    Qt, U, perm, order, norbits = homotopy_shards.equivariant_form(Q, R, 1)
    m, s = Q.shape[1], Q.shape[0]
    items = {"Qt": Qt.tolist(), "perm": perm.tolist(), "order": order, "seed": 1, "threads": 1, "first": 0,
             "count": norbits}
    part = homotopy_shards.orbit_task(items)
    n = 1 << s
    rec = ffi.sizeof("kin_homotopy_endpoint")
    off = ffi.offsetof("kin_homotopy_endpoint", "path")
    raw = np.frombuffer(part["ends"], dtype=np.uint8).reshape(-1, rec)
    paths = raw[:, off:off + 4].copy().view(np.intc).ravel()
    table = np.zeros((n, rec), dtype=np.uint8)
    table[paths] = raw
    z = np.zeros((n, 2 * m))
    z[paths] = np.frombuffer(part["z"], dtype=np.float64).reshape(-1, 2 * m)
    ends = ffi.new("kin_homotopy_endpoint[]", n)
    ffi.buffer(ends)[:] = table.tobytes()
    z = z.ravel()
    good = homotopy_shards._merge(Qt, m, s, 1, 1, ends, z, proven_on=(Q, np.ascontiguousarray(U.T)))[1]
    assert [good[k] for k in keys] == [acc0[k] for k in keys]
    wrong = U.copy()
    wrong[:, [1, 2]] = wrong[:, [2, 1]]
    bad = homotopy_shards._merge(Qt, m, s, 1, 1, ends, z, proven_on=(Q, np.ascontiguousarray(wrong.T)))[1]
    assert bad["proven_all"] == 0 and bad["proven_real"] + bad["proven_nonreal"] < good["proven_real"]
    assert bad["real"] == good["real"]  # the solve itself is Qt's, unchanged
    nan = Q.copy()
    nan[0, 0, 0] = np.nan
    with pytest.raises(InvalidArgumentError):
        homotopy_shards._merge(Qt, m, s, 1, 1, ends, z, proven_on=(nan, np.ascontiguousarray(U.T)))


def test_branches_with_group():
    """Assembly.branches(group=...): the same solutions and paths as without it."""
    a = libkin.Assembly.sail(6, 1)
    R = mechanism_group(a, method="c")
    b0 = a.branches(length=0.2)
    b1 = a.branches(length=0.2, group=R)
    assert b1.accounting["orbits"] == 176 and b1.accounting["monodromy_paths"] == 0
    assert len(b1.betas) == len(b0.betas) and same_roots(np.asarray(b1.betas), np.asarray(b0.betas))
    assert b1.distinct == b0.distinct
