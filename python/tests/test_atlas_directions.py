"""A return to the start decided against every branch direction of the
start, at any size (atlas/directions.py), on the hexagonal sail's flat
state (29,828 branch lines x 46 coordinates: too many to send whole with
each task): a sample of its directed branches that come back to the start
gets from directions.follow exactly what following with all 29,828 lines
gives, with the lines shared once (libkin.shared, each branch followed
once) and with the old passes (subsets, where the lines cannot be shared);
the returns along another branch are located as bifurcations at the start
and only the returns along the own branch are loops (the flat state has none
left: issue 36 item 2, bench/bench_return_labels.py); the branch a return
comes back along does not move with the step size; the same on a process
pool and a Dask cluster, and the tasks resume from a store."""
import numpy as np
import pytest

import libkin
from libkin.atlas import directions, explorer, tasks
from libkin.atlas.store import Store
from libkin.parallel import run_tasks
from libkin.shared import Sharing

SCAN = 240      # branches scanned (in a fixed spread over the start's) for returns to the start
RETURNS = 8     # of which this many returns are kept, with NON_RETURNS others
NON_RETURNS = 2
# the branch that the follower's old return test (a step back through the start) called a loop along
# its own branch (with its C3 images the 6 loops of the flat state's atlas before issue 36 item 2):
# it comes back along another branch (0.44 rad from its own; an independent NumPy follow agrees,
# bench/bench_return_labels.py). Found by its direction in joint coordinates (x, y, z of each free
# joint; it moves them out of plane), the line nearest this one, never by a solution index (the
# solver's numbering; docs/atlas.md)
LOOP_DIRECTION = [0.021425, 0, 0, 0.008875, 0, 0, -0.051725, 0, 0, -0.051725, 0, 0, 0.043728, 0, 0,
                  0.118589, 0, 0, -0.036452, 0, 0, -0.029369, 0, 0, 0.277902, 0, 0, -0.081998, 0, 0,
                  -0.448966, 0, 0, 0.550543, 0, 0, -0.252879, 0, 0, 0.005356, 0, 0, 0.372074, 0, 0, -0.430009]
KEYS = ("event", "coords", "length", "steps", "accuracy", "vr_tol", "m", "s", "at_start")


@pytest.fixture(scope="module")
def flat():
    """The flat state's directed branches (the explorer's enumeration), a task
    builder, and a sample of branches: returns to the start and others."""
    a = libkin.Assembly.sail(6, 2)
    ex = explorer._Explorer(a, False, None, None, 20.0, 1, 1, None, 2000, 0, None, True, False)
    an = a.analyse()
    ex.add_node(a.coords, "bifurcation", {"m": an.m_internal, "m_rigid": an.m_rigid, "s": an.s, "v_r_rel": 0.0}, 0)
    br, _ = ex.branches(ex.nodes[0])
    work = [(0, i, sg, b, d) for i, sg, b, d in br]
    lines = np.array([d for _, _, sg, _, d in work if sg == 1])
    assert lines.shape == (29828, 46) and lines.size > tasks.BRANCH_DIRECTIONS_MAX
    # the loop: the line nearest LOOP_DIRECTION (its 6 decimals: cos 1 - 1e-11), far nearer than any other
    loop = np.asarray(LOOP_DIRECTION) / np.linalg.norm(LOOP_DIRECTION)
    cos = np.abs(lines @ loop) / np.linalg.norm(lines, axis=1)
    near = np.argsort(cos)[::-1]
    assert cos[near[0]] > 1 - 1e-9 and cos[near[1]] < 0.999, (cos[near[0]], cos[near[1]])
    own_loop = [k for k, (_, _, sg, _, _) in enumerate(work) if sg == 1][near[0]]  # its sign +1 branch

    def item(nid, d):
        return {"model": ex.text, "coords": ex.nodes[nid].coords.tolist(), "rank_tol": 1e-9,
                "direction": d.tolist(), "max_length": ex.max_length, "max_steps": 2000, "samples": 0,
                "contact": False}
    returns, others = [], []
    for k in np.linspace(0, len(work) - 1, SCAN).astype(int):
        nid, _, _, _, d = work[k]
        res = tasks.follow_branch({**item(nid, d), "branches": [d.tolist()]})  # the first pass: own line only
        # back at the start: a loop with the own line alone, or (Newton's root from the arrival
        # direction on another line: never a loop) the start located or passed within loop_tol
        (returns if res["event"] == tasks.LOOP or res["at_start"] else others).append(k)
        if len(returns) >= RETURNS:
            break
    assert len(returns) >= min(3, RETURNS)  # the flat state's branches often come back to it
    return {"work": work, "lines": lines, "item": item, "sample": [own_loop] + returns + others[:NON_RETURNS],
            "start": a.coords, "loop": own_loop, "loop_line": int(near[0])}


def _serial(items):
    return [tasks.follow_branch(it) for it in items]


def _same(r, s):
    return all(r[k] == s[k] for k in KEYS)


@pytest.fixture
def unshared(monkeypatch):
    monkeypatch.setattr(Sharing, "share", lambda self, array: None)  # workers that cannot get the lines


def test_shared_lines_decide_as_all_directions_in_one_follow(flat):
    work, lines, item = flat["work"], flat["lines"], flat["item"]
    sample = [work[k] for k in flat["sample"]]
    record, sent = {}, []

    def run(items):
        sent.extend(items)
        return _serial(items)
    got = directions.follow(sample, work, item, run, record)
    assert record == {} and len(sent) == len(sample)  # each branch followed once
    assert all(it["own"] == sol and it["branches"].shape == lines.shape for it, (_, sol, *_) in zip(sent, sample))
    for (nid, sol, sg, _, d), res in zip(sample, got):
        whole = tasks.follow_branch({**item(nid, d), "branches": lines})
        assert _same(res, whole), (sol, sg, res["event"], whole["event"])
    assert sum(r["at_start"] for r in got) >= 2


def test_subsets_decide_as_all_directions(flat, unshared):
    work, lines, item = flat["work"], flat["lines"], flat["item"]
    sample = [work[k] for k in flat["sample"]]
    record = {}
    got = directions.follow(sample, work, item, _serial, record)
    margin = directions.branch_margin()
    along_other = along_own = 0
    for (nid, sol, sg, _, d), res in zip(sample, got):
        whole = tasks.follow_branch({**item(nid, d), "branches": lines})
        assert _same(res, whole), (sol, sg, res["event"], whole["event"])
        # what the follower decided at the last return, with every line
        a = tasks.rebuild(item(nid, d))
        ev = a.follow_event(d, max_length=20.0, max_steps=2000, branches=lines)
        assert tasks._EVENTS.get(ev.event) == res["event"]
        if ev.return_branch < 0:  # never came back (-1), or its branch undecided (-2): never a loop
            assert ev.return_branch == -1 or res["event"] != tasks.LOOP
            continue
        own = ev.return_branch == sol and ev.return_gap >= margin
        if res["event"] == tasks.LOOP:
            assert own  # a loop only along its own branch
            along_own += 1
        else:
            # back along another branch: the start located as a bifurcation, or where location
            # gives up among the start's close branches a near miss next to it (docs/follow.md)
            near = np.abs(np.asarray(res["coords"]) - flat["start"]).max()
            assert not own and res["event"] in (tasks.BIFURCATION, tasks.NEAR_MISS), res["event"]
            assert near <= (1e-6 if res["event"] == tasks.BIFURCATION else 1e-2) and (
                res["at_start"] or res["event"] == tasks.NEAR_MISS), (res["event"], near)
            along_other += 1
    assert along_other >= 1 and along_own == 0  # the flat state has no return along its own branch
    # subsets, never the whole set (the returns along another branch are decided with the own line
    # alone: Newton's root from the arrival direction is not on it, so they are not loops to check)
    assert record.get("lines_max", 0) < len(lines)


def test_return_branch_does_not_move_with_the_step(flat):
    """The old loop (LOOP_DIRECTION) followed with the largest step scaled by
    0.9, 1.0 and 1.1: the follower names the same branch it comes back along
    each time, an exact branch of the start 0.44 rad from its own, and never a
    loop. Before issue 36 item 2 (the return direction measured by a step back
    through the 16-fold start, which landed on the own branch) x1.0 was a loop
    along its own branch and x0.9 and x1.1 returns along another."""
    from libkin.assembly import BranchLines
    work, lines, item = flat["work"], flat["lines"], flat["item"]
    nid, _, _, _, d = work[flat["loop"]]
    own, L = flat["loop_line"], BranchLines(lines)
    got = []
    for scale in (0.9, 1.0, 1.1):
        a = tasks.rebuild(item(nid, d))
        o = a.options
        o.step_fraction *= scale
        a.options = o
        ev = a.follow_event(d, max_length=20.0, max_steps=2000, branches=L, own_branch=own)
        got.append((ev.event, ev.return_branch))
    assert all(e != "closed-loop" for e, _ in got), got
    back = {j for _, j in got}
    assert len(back) == 1 and min(back) >= 0, got
    j = back.pop()
    assert float(L.angle(lines[own], j)) > 0.3  # far from its own line: not a neighbour of it


@pytest.mark.parametrize("share", [True, False])
def test_executors_and_resume(flat, tmp_path, monkeypatch, share):
    """The lines shared with a process pool (a file) and a Dask cluster (a
    broadcast), or the subsets shipped as arrays: the same results; with a
    store, a second run (its lines in another temporary file) takes every
    task (the first pass and any decided-again ones) from it."""
    from concurrent.futures import ProcessPoolExecutor
    if not share:
        monkeypatch.setattr(Sharing, "share", lambda self, array: None)
    work, item = flat["work"], flat["item"]
    sample = [work[k] for k in flat["sample"][:4]]
    ref = directions.follow(sample, work, item, _serial)
    path = tmp_path / "run.sqlite"
    with ProcessPoolExecutor(max_workers=2) as ex:
        for resume in (False, True):
            with Store(path, "fingerprint", resume=resume) as store:
                got = directions.follow(sample, work, item,
                                        lambda items: store.run_tasks(tasks.follow_branch, items, ex, None,
                                                                      "branches", None), None, ex)
                assert all(_same(r, s) for r, s in zip(ref, got))
                if resume:
                    assert store.recorded == 0 and store.reused == recorded
                else:
                    recorded = store.recorded
                    # unshared, a return the subset could not decide runs again with every line
                    # (none may need to: returns are decided by Newton on the start's equations)
                    assert recorded == len(sample) if share else recorded >= len(sample)
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                  dashboard_address=":0") as cluster, distributed.Client(cluster) as client:
        got = directions.follow(sample, work, item, lambda items: run_tasks(tasks.follow_branch, items, client),
                                None, client)
    assert all(_same(r, s) for r, s in zip(ref, got))
