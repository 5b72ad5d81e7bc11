"""A node with many branch lines (more than tasks.BRANCH_DIRECTIONS_MAX,
forced low here) gives its tasks every line once through libkin.shared:
the same atlas as the old passes (subsets of the lines, returns followed
again), in this process and on a process pool, with no return followed
twice; and a store's results resume across the change of the shared file's
temporary path (the tasks are keyed by the lines' content)."""
import pytest

import libkin
from libkin.atlas import tasks
from libkin.parallel import ProcessPool
from libkin.shared import Sharing

MODEL = "sail:4:2"  # 24 of its 512 branches come back to the start (returns the follower decides)
SETTINGS = {"depth": 1, "symmetry": False}


@pytest.fixture
def many(monkeypatch):
    monkeypatch.setattr(tasks, "BRANCH_DIRECTIONS_MAX", 1)  # every node's lines are "many"


def test_the_same_atlas_as_the_old_passes(many, monkeypatch):
    here = libkin.explore(MODEL, **SETTINGS)
    assert here.stats["returns_decided_again"] == {}  # every return decided in its one follow
    with ProcessPool(2) as pool:
        on_pool = libkin.explore(MODEL, executor=pool, **SETTINGS)
    monkeypatch.setattr(Sharing, "share", lambda self, array: None)  # workers that cannot get the lines
    old = libkin.explore(MODEL, **SETTINGS)
    # the old passes (returns_decided_again) run only for loops with the own line alone: since
    # issue 36 item 2 a return along another branch is not one (the follower's Newton root from
    # its arrival is on another line), so here they may have nothing to decide again
    assert here.same_as(old, tol=0.0) and on_pool.same_as(old, tol=0.0)
    assert [e.event for e in here.edges] == [e.event for e in old.edges]


def test_resume_across_the_temporary_path(many, tmp_path):
    path = tmp_path / "run.sqlite"
    seen = []
    share = Sharing.share

    def spy(self, array):
        ref = share(self, array)
        seen.append(ref.where)
        return ref
    with pytest.MonkeyPatch.context() as mp, ProcessPool(2) as pool:
        mp.setattr(Sharing, "share", spy)
        first = libkin.explore(MODEL, executor=pool, store=path, **SETTINGS)
        again = libkin.explore(MODEL, executor=pool, store=path, resume=True, **SETTINGS)
    assert len(seen) == 2 and seen[0] != seen[1]  # the lines went in another file
    assert first.stats["store"]["recorded"] >= len(first.edges)
    assert again.stats["store"]["recorded"] == 0 and again.stats["store"]["reused"] == first.stats["store"]["recorded"]
    assert again.same_as(first, tol=0.0)


def test_dask_broadcast_with_a_store(many, tmp_path):
    """On Dask the lines go once to every worker (a broadcast), the tasks stream through the store."""
    distributed = pytest.importorskip("distributed")
    here = libkin.explore(MODEL, **SETTINGS)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=":0") as cluster, distributed.Client(cluster) as client:
        on_dask = libkin.explore(MODEL, executor=client, store=tmp_path / "run.sqlite", **SETTINGS)
    assert on_dask.stats["returns_decided_again"] == {} and on_dask.same_as(here, tol=0.0)
