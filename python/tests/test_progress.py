"""Progress reports, cancellation and Ctrl-C of the long calls (libkin._native._progress)."""
import os
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

import libkin
from libkin.assembly import solve_quadrics


def random_quadrics(s, seed):
    """s Gaussian symmetric (s+1) x (s+1) matrices: every root simple."""
    g = np.random.default_rng(seed).standard_normal((s, s + 1, s + 1))
    return g + g.transpose(0, 2, 1)


class Recorder:
    def __init__(self, cancel_at=0, raise_at=0, exc=None):
        self.calls = []
        self.cancel_at, self.raise_at, self.exc = cancel_at, raise_at, exc

    def __call__(self, done, total):
        self.calls.append((done, total))
        if len(self.calls) == self.raise_at:
            raise self.exc
        return len(self.calls) == self.cancel_at

    def check_monotonic(self):
        done = [c[0] for c in self.calls]
        total = [c[1] for c in self.calls]
        assert all(0 <= d <= t for d, t in self.calls)
        assert done == sorted(done) and total == sorted(total)


def on_p1():
    """The three-bar linkage on its path P1, at a regular point."""
    a = libkin.Assembly.threebar("RC")
    xyz = a.coords
    xyz[:2] = [[0.6, 0.8], [1.6, 0.8]]
    a.coords = xyz
    return a


def test_homotopy_progress_monotonic_and_same_answer():
    Q = random_quadrics(8, 1)
    ref, acc_ref = solve_quadrics(Q, "homotopy", threads=1)
    rec = Recorder()
    got, acc = solve_quadrics(Q, "homotopy", threads=2, progress=rec)
    np.testing.assert_array_equal(got, ref)
    assert acc == acc_ref
    assert len(rec.calls) >= 2 and rec.calls[0][0] == 0
    rec.check_monotonic()
    assert rec.calls[-1][0] == rec.calls[-1][1] == 2 ** 8 + acc["retracked"]


def test_homotopy_tqdm_bar(capsys):
    pytest.importorskip("tqdm")
    solve_quadrics(random_quadrics(6, 2), "homotopy", progress=True)
    assert "path" in capsys.readouterr().err


def test_homotopy_cancel_from_callback_is_quick():
    Q = random_quadrics(12, 3)  # 4096 paths: seconds uncancelled
    rec = Recorder(cancel_at=2)
    t0 = time.perf_counter()
    with pytest.raises(libkin.errors.CancelledError):
        solve_quadrics(Q, "homotopy", threads=2, progress=rec)
    assert time.perf_counter() - t0 < 1.0
    assert len(rec.calls) == 2


@pytest.mark.parametrize("exc", [KeyboardInterrupt(), ValueError("from the callback")])
def test_homotopy_exception_in_callback_cancels_and_propagates(exc):
    rec = Recorder(raise_at=2, exc=exc)
    t0 = time.perf_counter()
    with pytest.raises(type(exc)):
        solve_quadrics(random_quadrics(12, 4), "homotopy", threads=2, progress=rec)
    assert time.perf_counter() - t0 < 1.0
    assert len(rec.calls) == 2


def test_homotopy_path_limit():
    Q = random_quadrics(8, 5)
    with pytest.raises(libkin.errors.LimitError):
        solve_quadrics(Q, "homotopy", max_paths=255)
    betas, acc = solve_quadrics(Q, "homotopy", max_paths=256)
    assert acc["paths"] == 256


def test_bad_progress_argument():
    with pytest.raises(TypeError):
        solve_quadrics(random_quadrics(2, 6), "homotopy", progress="yes")


def test_locate_progress_and_cancel():
    rec = Recorder()
    a = on_p1()
    info = a.locate(delta=0.1, progress=rec)
    assert info.located
    rec.check_monotonic()
    assert rec.calls[0][0] == 0 and rec.calls[-1][0] == rec.calls[-1][1]
    assert len(rec.calls) > info.steps
    # cancelled after two steps: on the path, and locating again works
    a = on_p1()
    with pytest.raises(libkin.errors.CancelledError):
        a.locate(delta=0.1, progress=Recorder(cancel_at=3))
    assert a.analyse().m_internal == 1 and a.max_strain <= 1e-12
    info = a.locate(delta=0.1)
    assert info.located and info.m_internal == 2
    # Ctrl-C (a KeyboardInterrupt in the callback) the same way
    a = on_p1()
    with pytest.raises(KeyboardInterrupt):
        a.locate(delta=0.1, progress=Recorder(raise_at=2, exc=KeyboardInterrupt()))
    assert a.locate(delta=0.1).located


def test_branches_progress_and_cancel():
    a = libkin.Assembly.threebar("RC")
    rec = Recorder()
    br = a.branches(length=0.5, progress=rec)
    assert br.distinct == 4
    follow = [c for c in rec.calls if c[1] == 4]  # the following's reports (total: 4 directed paths)
    assert follow and follow[0][0] == 0 and follow[-1][0] == 4
    before = a.coords
    with pytest.raises(libkin.errors.CancelledError):
        a.follow_branches(br.betas, length=0.5, progress=Recorder(cancel_at=3))
    np.testing.assert_array_equal(a.coords, before)
    assert a.follow_branches(br.betas, length=0.5).distinct == 4  # the handle's callback was removed


CHILD = textwrap.dedent("""
    import signal, sys, time
    import libkin
    # Python's own Ctrl-C handler, even if this test runs where SIGINT is
    # ignored (a background job inherits that and Python then keeps it)
    signal.signal(signal.SIGINT, signal.default_int_handler)
    from libkin.assembly import solve_quadrics
    a = libkin.Assembly.sail(6, 2)          # the hexagonal sail's flat state: s = 15
    Q = a.second_order()
    print("ready", Q.shape[0], flush=True)
    t0 = time.perf_counter()
    try:
        solve_quadrics(Q, "homotopy", threads=2)
    except KeyboardInterrupt:
        print(f"interrupted after {time.perf_counter() - t0:.2f} s", flush=True)
        sys.exit(42)
    print("finished", flush=True)
""")


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
def test_sigint_stops_the_complete_solver():
    env = dict(os.environ)
    proc = subprocess.Popen([sys.executable, "-c", CHILD], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, env=env)
    try:
        line = proc.stdout.readline()
        assert line.split() == ["ready", "15"], line + proc.stderr.read()
        time.sleep(1.0)  # 2^15 paths: about 20 s uncancelled
        assert proc.poll() is None
        t0 = time.perf_counter()
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=10)
        dt = time.perf_counter() - t0
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 42, out + err
    assert "interrupted" in out
    assert dt < 1.0, f"exited {dt:.2f} s after SIGINT"
