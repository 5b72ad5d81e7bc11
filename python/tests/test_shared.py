"""Large read-only arrays given to the workers once (libkin.shared) and the
branch lines the follower asks at each return (BranchLines): a Ref is named
by its content on every executor, resolves to the same array in the worker,
once per process; its files go at close; an executor it cannot reach gets
None. BranchLines gives the follower C's own decision (nearest line, angle,
gap) and refuses bad input; the follower refuses a bad own_branch and
raises what the hook raised."""
import concurrent.futures
import os
import pickle

import numpy as np
import pytest

import libkin
from libkin import shared
from libkin.assembly import BranchLines
from libkin.atlas.store import _hash
from libkin.errors import InvalidArgumentError
from libkin.parallel import ProcessPool, run_tasks

EPS = np.finfo(float).eps


def _sum_of(ref):
    a = shared.resolve(ref)
    return [float(a.sum()), a.flags.writeable, id(a) == id(shared.resolve(ref)), os.getpid()]


def _sum_in(item):
    return _sum_of(item["b"])


def _array(n=50, m=7, seed=3):
    return np.random.default_rng(seed).normal(size=(n, m))


def test_ref_by_content_on_every_executor(tmp_path):
    x = _array()
    keys, sums = set(), []
    with shared.Sharing(None) as here, shared.Sharing(concurrent.futures.ThreadPoolExecutor(1)) as threads, \
            ProcessPool(2) as pool, shared.Sharing(pool, str(tmp_path)) as files:
        refs = [s.share(x) for s in (here, threads, files)]
        assert files.share(x.copy()) is refs[2]  # the same content: one file
        folder = os.path.dirname(refs[2].where)
        assert os.listdir(folder) == [refs[2].digest + ".npy"]
        for r in refs:
            keys.add(_hash({"task": 1, "branches": r}))  # the store's key: by content, never by path
            sums.append(_sum_of(r))
            sums += run_tasks(_sum_of, [r, r, r], pool)
        x[0, 0] = 7.0  # the caller's array may change: the shared copy does not
        assert shared.resolve(refs[0])[0, 0] != 7.0
    assert len(keys) == 1
    assert not os.path.exists(folder)  # removed at close
    total = float(_array().sum())
    assert all(abs(s[0] - total) <= 64 * EPS * np.abs(_array()).sum() and not s[1] and s[2] for s in sums)
    assert pickle.loads(pickle.dumps(refs[2])).digest == refs[2].digest


def test_an_executor_it_cannot_reach_gets_none():
    class Elsewhere(concurrent.futures.Executor):
        pass
    with shared.Sharing(Elsewhere()) as s:
        assert s.share(_array()) is None


def test_dask_broadcast():
    distributed = pytest.importorskip("distributed")
    x = _array()
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        with shared.Sharing(client) as s:
            r = s.share(x)
            assert _hash({"b": r}) == _hash({"b": shared.Sharing(None).share(x)})
            got = run_tasks(_sum_in, [{"b": r}] * 3, client)  # the future resolved by Dask in the worker
    assert all(abs(g[0] - float(x.sum())) <= 64 * EPS * np.abs(x).sum() for g in got)


def _c_rule(lines, t):
    """C's nearest_branch: every line's angle by its formula, the first smallest."""
    best, b1, b2 = -1, np.inf, np.inf
    for j, v in enumerate(lines):
        uu, vv, uv = t @ t, v @ v, t @ v
        r = t - (uv / vv) * v
        g = np.arctan2(np.sqrt((r @ r) / uu), abs(uv) / np.sqrt(uu * vv))
        if g < b1:
            best, b2, b1 = j, b1, g
        elif g < b2:
            b2 = g
    return best, b1, b2 - b1


def test_branch_lines_nearest_as_c():
    rng = np.random.default_rng(5)
    L = rng.normal(size=(300, 9)) * rng.uniform(0.1, 10.0, size=(300, 1))
    L[7] = 3.0 * L[2] + 1e-9 * rng.normal(size=9)  # nearly the same line, another scale
    lines = BranchLines(L)
    for t in [rng.normal(size=9) for _ in range(40)] + [-2.0 * L[2], L[7] + 1e-7, L[11]]:
        j, a, g = lines.nearest(t)
        cj, ca, cg = _c_rule(L, t)
        assert j == cj and abs(a - ca) <= 1e3 * EPS and abs(g - cg) <= 1e3 * EPS
    assert lines.nearest(L[0])[2] == np.inf or BranchLines(L[:1]).nearest(L[0])[2] == np.inf
    assert BranchLines(L[:1]).nearest(L[0]) == (0, 0.0, np.inf)
    for bad in (np.zeros(4), np.zeros((0, 3)), [[1.0, np.nan]], [[1.0, np.inf]]):
        with pytest.raises(InvalidArgumentError):
            BranchLines(bad)


def test_follow_event_with_branch_lines_checks_its_input():
    a = libkin.Assembly.threebar("RC")
    an = a.analyse()
    U = an.internal_mechanisms
    d = U[:, 0]
    lines = BranchLines(np.array([d, U[:, 1]]))
    for bad in ({"own_branch": 2}, {"own_branch": -1}, {"own_branch": 1.0}, {"own_branch": None},
                {"own_branch": 1}):  # 1: d is not along line 1
        with pytest.raises(InvalidArgumentError):
            a.clone().follow_event(d, branches=lines, **bad)
    with pytest.raises(InvalidArgumentError):
        a.clone().follow_event(d, branches=np.array([d]), own_branch=0)  # own_branch only with BranchLines
    with pytest.raises(InvalidArgumentError):
        a.clone().follow_event(d, branches=BranchLines(np.ones((2, a.nfree + 1))), own_branch=0)
    ev = a.clone().follow_event(d, branches=lines, own_branch=0)
    assert ev.event in ("bifurcation", "closed-loop", "near-miss", "length-limit", "step-limit")
