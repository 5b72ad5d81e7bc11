"""Long runs resume (issue 22 item 2): `libkin explore` records each solved
node and followed branch in a store as it goes; a run killed with SIGKILL
at any moment and continued with --resume gives the atlas an uninterrupted
run gives, node for node and edge for edge; a store of another run is
refused; SIGINT/SIGTERM write the atlas so far and exit nonzero."""
import json
import os
import pathlib
import random
import signal
import sqlite3
import subprocess
import sys
import time

import pytest

import libkin
from libkin.atlas import explorer, store as atlas_store
from libkin.atlas.model import Atlas
from libkin.cli import main
from subprocess_env import libkin_env as _env  # noqa: E402

MODEL = "sail:4:1"  # depth 1: 4 nodes, 32 directed paths (1 solve, 32 branches recorded), seconds




def _cmd(out, store, *more, depth=1):
    return [sys.executable, "-m", "libkin", "explore", MODEL, "--depth", str(depth), "--out", str(out),
            "--store", str(store), "--quiet", *more]


def _graph(out):
    """The atlas in out: its nodes and edges as written (settings and stats aside)."""
    d = json.loads((pathlib.Path(out) / "atlas.json").read_text())
    return Atlas.from_dict(d), d["nodes"], d["edges"]


def _reference(tmp_path_factory, depth):
    """An uninterrupted run of the command line, without a store given."""
    out = tmp_path_factory.mktemp("ref") / "atl"
    t0 = time.perf_counter()
    r = subprocess.run([sys.executable, "-m", "libkin", "explore", MODEL, "--depth", str(depth), "--out", str(out),
                        "--quiet"], env=_env(), capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return _graph(out), time.perf_counter() - t0


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    return _reference(tmp_path_factory, 1)


def _recorded(store):
    db = sqlite3.connect(str(store))
    try:
        return db.execute("SELECT COUNT(*) FROM results").fetchone()[0]
    except sqlite3.OperationalError:  # not created yet
        return 0
    finally:
        db.close()


def _same(reference, out):
    (ref, ref_nodes, ref_edges), _ = reference
    at, nodes, edges = _graph(out)
    assert at.same_as(ref, tol=0.0)
    assert nodes == ref_nodes and edges == ref_edges  # node for node, edge for edge
    assert at.stats["partial"] is False
    return at


@pytest.mark.parametrize("k", [1, 2, 7])
def test_killed_after_k_results_resumes_to_the_same_atlas(tmp_path, reference, k):
    out, store = tmp_path / "atl", tmp_path / "run.sqlite"
    r = subprocess.run(_cmd(out, store), env=_env(LIBKIN_STORE_KILL_AFTER=str(k)), capture_output=True)
    assert r.returncode == -signal.SIGKILL, r.stderr
    assert not out.exists()  # killed before any atlas was written
    assert _recorded(store) == k  # every result recorded before the kill is there
    r = subprocess.run(_cmd(out, store, "--resume"), env=_env(), capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    at = _same(reference, out)
    assert at.stats["store"]["reused"] == k  # the recorded results were not computed again
    assert at.stats["store"]["recorded"] == _recorded(store) - k


def test_killed_at_a_random_moment_resumes_to_the_same_atlas(tmp_path, tmp_path_factory):
    """Depth 2 (4 nodes, 44 paths): killed a random time after its first
    recorded result, then resumed."""
    reference = _reference(tmp_path_factory, 2)
    out, store = tmp_path / "atl", tmp_path / "run.sqlite"
    delay = random.uniform(0.0, 1.0)
    p = subprocess.Popen(_cmd(out, store, depth=2), env=_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    while not store.exists() or _recorded(store) < 1:
        assert p.poll() is None, p.stderr.read()
        time.sleep(0.01)
    time.sleep(delay)
    p.kill()
    p.wait(timeout=60)
    at_kill = _recorded(store)
    r = subprocess.run(_cmd(out, store, "--resume", depth=2), env=_env(), capture_output=True, text=True)
    assert r.returncode == 0, (delay, r.stderr)
    at = _same(reference, out)
    assert at.stats["store"]["reused"] == at_kill, delay


def test_resume_in_process_reuses_every_result(tmp_path, monkeypatch):
    """explore(store=..., resume=True) after a complete run computes nothing."""
    path = tmp_path / "run.sqlite"
    first = libkin.explore(MODEL, depth=1, store=path)
    assert first.stats["store"]["reused"] == 0 and first.stats["store"]["recorded"] > 1

    def never(*a, **k):
        raise AssertionError("computed again")
    monkeypatch.setattr(explorer, "complete_solve", never)
    monkeypatch.setattr(atlas_store, "run_tasks", never)
    again = libkin.explore(MODEL, depth=1, store=path, resume=True)
    assert again.same_as(first, tol=0.0)
    assert again.stats["store"] == dict(first.stats["store"], reused=first.stats["store"]["recorded"], recorded=0)


@pytest.mark.parametrize("other", [["explore", "threebar:RC", "--depth", "1"],  # another model
                                   ["explore", MODEL, "--depth", "1", "--max-length", "3"]])  # other settings
def test_a_store_of_another_run_is_refused(tmp_path, other):
    store = tmp_path / "run.sqlite"
    r = subprocess.run(_cmd(tmp_path / "a", store), env=_env(LIBKIN_STORE_KILL_AFTER="2"), capture_output=True)
    assert r.returncode == -signal.SIGKILL
    before = store.read_bytes() if not (tmp_path / "run.sqlite-wal").exists() else None
    n = _recorded(store)
    for resume in (["--resume"], []):
        out = tmp_path / "b"
        assert main(other + ["--out", str(out), "--store", str(store), "--quiet"] + resume) == 1
        assert not out.exists()
        assert _recorded(store) == n  # the other run's results are kept
    if before is not None:
        assert store.read_bytes() == before


def test_a_rerun_without_resume_starts_afresh(tmp_path, monkeypatch):
    path = tmp_path / "run.sqlite"
    first = libkin.explore(MODEL, depth=1, store=path)
    again = libkin.explore(MODEL, depth=1, store=path)
    assert again.stats["store"]["reused"] == 0 and again.stats["store"]["recorded"] == first.stats["store"]["recorded"]
    assert again.same_as(first, tol=0.0)


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_a_signal_writes_the_atlas_so_far_and_exits_nonzero(tmp_path, reference, sig):
    out, store = tmp_path / "atl", tmp_path / "run.sqlite"
    p = subprocess.Popen(_cmd(out, store), env=_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    while not store.exists() or _recorded(store) < 2:  # the solve and one branch done
        assert p.poll() is None, p.stderr.read()
        time.sleep(0.02)
    p.send_signal(sig)
    rc = p.wait(timeout=120)
    assert rc == 128 + sig, p.stderr.read()
    at, nodes, edges = _graph(out)
    assert at.stats["partial"] is True and at.stats["stopped_by"] == "interrupted"
    (ref, _, ref_edges), _ = reference
    assert 1 <= len(edges) < len(ref_edges)  # the branches followed so far, not all
    # the partial atlas's edges are among the uninterrupted run's, in its
    # order (the branches followed and their images by symmetry)
    key = [(e["source"], e["solution"], e["sign"], e["event"]) for e in ref_edges]
    got = [(e["source"], e["solution"], e["sign"], e["event"]) for e in edges]
    assert all(g in key for g in got) and [key.index(g) for g in got] == sorted(key.index(g) for g in got)
    r = subprocess.run(_cmd(out, store, "--resume"), env=_env(), capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    _same(reference, out)


def test_default_store_is_next_to_out(tmp_path, reference):
    """Without --store the store is .OUT.explore.sqlite next to --out, kept
    while the run is unfinished and removed once its atlas is complete."""
    out, store = tmp_path / "atl", tmp_path / ".atl.explore.sqlite"
    cmd = [sys.executable, "-m", "libkin", "explore", MODEL, "--depth", "1", "--out", str(out), "--quiet"]
    r = subprocess.run(cmd, env=_env(LIBKIN_STORE_KILL_AFTER="3"), capture_output=True)
    assert r.returncode == -signal.SIGKILL
    assert _recorded(store) == 3
    r = subprocess.run(cmd + ["--resume"], env=_env(), capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert _same(reference, out).stats["store"]["reused"] == 3
    assert sorted(os.listdir(tmp_path)) == [".atl.lock", "atl"]


def test_a_dask_run_survives_the_loss_of_its_client(tmp_path, reference):
    """--executor dask: the client process (which holds the local cluster)
    killed after 5 results; a new client resumes from the store."""
    pytest.importorskip("distributed")
    out, store = tmp_path / "atl", tmp_path / "run.sqlite"
    r = subprocess.run(_cmd(out, store, "--executor", "dask"), env=_env(LIBKIN_STORE_KILL_AFTER="5"),
                       capture_output=True)
    assert r.returncode == -signal.SIGKILL, r.stderr
    assert _recorded(store) == 5
    r = subprocess.run(_cmd(out, store, "--executor", "dask", "--resume"), env=_env(), capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert _same(reference, out).stats["store"]["reused"] == 5
