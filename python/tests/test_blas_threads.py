"""parallel.one_blas_thread: the BLAS libraries on one thread inside, what
was there restored after, however uses nest and whichever thread ends last;
an atlas task runs inside it."""
import threading

import numpy as np
import pytest

from libkin import parallel

threadpoolctl = pytest.importorskip("threadpoolctl")


def _blas_threads():
    return [d["num_threads"] for d in threadpoolctl.threadpool_info() if d["user_api"] == "blas"]


@pytest.fixture
def two_threads():
    """NumPy's BLAS at 2 threads for the test (whatever the machine has), put back after."""
    if not _blas_threads():
        pytest.skip("NumPy's BLAS is not one threadpoolctl knows")
    with threadpoolctl.threadpool_limits(2, "blas"):
        yield


def test_one_thread_inside_restored_after(two_threads):
    before = _blas_threads()
    with parallel.one_blas_thread():
        assert set(_blas_threads()) == {1}
        with parallel.one_blas_thread():  # nested: still one, and the outer one restores
            assert set(_blas_threads()) == {1}
        assert set(_blas_threads()) == {1}
    assert _blas_threads() == before


def test_restored_after_an_error(two_threads):
    before = _blas_threads()
    with pytest.raises(ZeroDivisionError):
        with parallel.one_blas_thread():
            1 / 0
    assert _blas_threads() == before


def test_concurrent_uses_leave_the_count_as_it_was(two_threads):
    """Two threads overlapping, the first in ending first: the caller's
    count once both are out. (Which threads a count set from a thread
    reaches depends on the OpenBLAS build; the worker processes of a pool run
    their tasks in their main thread.)"""
    before = _blas_threads()
    inside, release = threading.Barrier(3), threading.Event()
    errors = []

    def task():
        try:
            with parallel.one_blas_thread():
                inside.wait(timeout=60)
                release.wait(timeout=60)
        except BaseException as exc:  # noqa: BLE001 - reported below
            errors.append(exc)
    ts = [threading.Thread(target=task, daemon=True) for _ in range(2)]
    for t in ts:
        t.start()
    inside.wait(timeout=60)
    depth = parallel.one_blas_thread.depth
    release.set()
    assert depth == 2
    for t in ts:
        t.join()
    assert not errors and parallel.one_blas_thread.depth == 0
    assert _blas_threads() == before


def test_an_atlas_task_runs_on_one_blas_thread(two_threads, monkeypatch):
    """tasks.follow_branch follows inside the limit (its numpy products
    too: the branch lines' return hook), and leaves the count as it was."""
    import libkin
    from libkin.atlas import tasks
    seen = []
    real = tasks._follow_branch

    def spy(task):
        seen.append(_blas_threads())
        return real(task)
    monkeypatch.setattr(tasks, "_follow_branch", spy)
    a = libkin.Assembly.threebar("RC")
    betas, _ = libkin.solve_quadrics(a.second_order())
    d = a.analyse().internal_mechanisms @ betas[0]
    before = _blas_threads()
    res = tasks.follow_branch({"model": a.to_json(), "coords": a.coords, "direction": d, "max_length": 10.0})
    assert res["event"] == "bifurcation"
    assert seen and set(seen[0]) == {1}
    assert _blas_threads() == before
