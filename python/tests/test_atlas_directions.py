"""A return to the start decided against every branch direction of the
start, at any size (atlas/directions.py), on the hexagonal sail's flat
state (29,828 branch lines x 46 coordinates: too many to send whole with
each task): a sample of its directed branches that come back to the start
gets from directions.follow exactly what following with all 29,828 lines
gives, with the lines shared once (libkin.shared, each branch followed
once) and with the old passes (subsets, where the lines cannot be shared);
the returns along another branch are located as bifurcations at the start
and only the returns along the own branch are loops; the same on a process
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
# a branch that returns along its own branch (with its C3 images the only loops of the flat state's
# atlas, bench/atlas_flat_symmetry_summary_directions.json): found by its direction in joint
# coordinates (x, y, z of each free joint; it moves them out of plane), the line nearest this one,
# never by a solution index (the solver's numbering; docs/atlas.md)
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
        (returns if res["event"] == tasks.LOOP else others).append(k)
        if len(returns) >= RETURNS:
            break
    assert len(returns) >= min(3, RETURNS)  # the flat state's branches often come back to it
    return {"work": work, "lines": lines, "item": item, "sample": [own_loop] + returns + others[:NON_RETURNS],
            "start": a.coords}


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
    assert sum(r["event"] == tasks.LOOP for r in got) >= 1 and sum(r["at_start"] for r in got) >= 2


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
        if ev.return_branch < 0:
            continue  # never came back
        own = ev.return_branch == sol and ev.return_gap >= margin
        if res["event"] == tasks.LOOP:
            assert own  # a loop only along its own branch
            along_own += 1
        else:
            # back along another branch (or too close to call): the start located as a bifurcation
            assert not own and res["event"] == tasks.BIFURCATION and res["at_start"]
            assert np.abs(np.asarray(res["coords"]) - flat["start"]).max() <= 1e-6
            along_other += 1
    assert along_other >= 1 and along_own >= 1
    assert record.get("tasks", 0) >= 1 and record["lines_max"] < len(lines)  # subsets, never the whole set


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
                    assert recorded == len(sample) if share else recorded > len(sample)  # returns ran twice
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        got = directions.follow(sample, work, item, lambda items: run_tasks(tasks.follow_branch, items, client),
                                None, client)
    assert all(_same(r, s) for r, s in zip(ref, got))
