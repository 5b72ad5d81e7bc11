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
LOOP_TOL = 0.05


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
                                  dashboard_address=":0") as cluster, distributed.Client(cluster) as client:
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


@pytest.fixture(scope="module")
def sail4():
    """The flat state of sail:4:1 and its directed branches (with loop_tol LOOP_TOL, 9 of the 32
    come back to it by the follower's loop test)."""
    from libkin.atlas import explorer
    a = libkin.Assembly.sail(4, 1)
    ex = explorer._Explorer(a, False, None, None, 20.0, 1, 1, None, 2000, 0, None, True, False)
    an = a.analyse()
    ex.add_node(a.coords, "bifurcation", {"m": an.m_internal, "m_rigid": an.m_rigid, "s": an.s, "v_r_rel": 0.0}, 0)
    br, _ = ex.branches(ex.nodes[0])
    return a, br, np.array([d for _, sg, _, d in br if sg == 1])


def test_follow_event_with_branch_lines_decides_as_c(sail4):
    a, br, L = sail4
    lines, back = BranchLines(L), 0
    for i, sg, _, d in br:
        x, y = a.clone(), a.clone()
        ex = x.follow_event(d, max_length=20.0, loop_tol=LOOP_TOL, branches=L)
        ey = y.follow_event(d, max_length=20.0, loop_tol=LOOP_TOL, branches=lines, own_branch=i)
        assert (ex.event, ex.steps, ex.at_start, ex.return_branch) == (ey.event, ey.steps, ey.at_start, ey.return_branch)
        assert np.array_equal(x.coords, y.coords)
        assert np.isclose(ex.return_gap, ey.return_gap, rtol=0.0, atol=1e3 * EPS, equal_nan=True)
        back += ex.return_branch != -1  # decided (>= 0) or undecided (-2)
    assert back >= 1  # returns to the start were met


class _Raises(BranchLines):
    def nearest(self, t):
        raise RuntimeError("lines gone")


class _Stops(BranchLines):
    def nearest(self, t):
        return -3, 0.0, 1.0


class _Nonsense(BranchLines):
    def nearest(self, t):
        return 0, float("nan"), 1.0


def test_follow_event_with_branch_lines_checks_its_input(sail4):
    a, br, L = sail4
    i, _, _, d = br[0]
    lines = BranchLines(L)
    for bad in ({"own_branch": len(L)}, {"own_branch": -1}, {"own_branch": 1.0}, {"own_branch": None},
                {"own_branch": i + 1}):  # i + 1: d is not along that line
        with pytest.raises(InvalidArgumentError):
            a.clone().follow_event(d, branches=lines, **bad)
    with pytest.raises(InvalidArgumentError):
        a.clone().follow_event(d, branches=L, own_branch=i)  # own_branch only with BranchLines
    with pytest.raises(InvalidArgumentError):
        a.clone().follow_event(d, branches=BranchLines(np.ones((2, a.nfree + 1))), own_branch=0)
    # a return decided by a hook that fails: its exception, a stop, nonsense refused
    k = next(k for k, (i, _, _, d) in enumerate(br)
             if a.clone().follow_event(d, max_length=20.0, loop_tol=LOOP_TOL, branches=L).return_branch != -1)
    i, _, _, d = br[k]
    with pytest.raises(RuntimeError, match="lines gone"):
        a.clone().follow_event(d, max_length=20.0, loop_tol=LOOP_TOL, branches=_Raises(L), own_branch=i)
    with pytest.raises(libkin.errors.CancelledError):
        a.clone().follow_event(d, max_length=20.0, loop_tol=LOOP_TOL, branches=_Stops(L), own_branch=i)
    ev = a.clone().follow_event(d, max_length=20.0, loop_tol=LOOP_TOL, branches=_Nonsense(L), own_branch=i)
    assert ev.event == "failed" and ev.status == "KIN_EINVAL"
