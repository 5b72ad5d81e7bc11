"""Nothing saved is lost (issue 22 items 1 and 6): every writer of libkin is
run into a file (or folder) holding a previous good result while a fault is
injected, and the previous result must be there byte for byte afterwards,
with no temporary file left:

- a full disk: os.write raising ENOSPC at the 1st, 2nd, ... call, and a file
  size limit (RLIMIT_FSIZE: the system refuses the write that crosses it, as
  a full disk does, inside matplotlib, PIL and networkx too);
- a failing fsync or rename (the nth call);
- a kill: the writing process SIGKILLed at its nth rename, and an exception
  thrown from the middle of a folder's writes;
- two runs into one --out folder: the second fails at once.

FAULTS counts the faults tried per kind (printed at the end with -s)."""
import collections
import contextlib
import errno
import json
import os
import pathlib
import resource
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import libkin
from libkin import atomic
from libkin.assembly import Assembly
from libkin.atlas import report as atlas_report
from libkin.cli import main
from libkin.io.fold import write_fold
from subprocess_env import libkin_env as _env  # noqa: E402

FAULTS: collections.Counter = collections.Counter()


@pytest.fixture(scope="module", autouse=True)
def fault_table():
    yield
    print("\nfaults injected into writes (kind: count):")
    for kind, n in sorted(FAULTS.items()):
        print(f"  {kind}: {n}")


def snapshot(folder):
    """{relative name: bytes} of everything under folder (hidden files too)."""
    folder = pathlib.Path(folder)
    return {str(p.relative_to(folder)): (p.read_bytes() if p.is_file() else None)
            for p in sorted(folder.rglob("*"))}


@contextlib.contextmanager
def fail_nth(monkeypatch, name, n, err=errno.ENOSPC):
    """os.<name> raises OSError(err) at its nth call inside the block."""
    real = getattr(os, name)
    calls = [0]

    def faulty(*args, **kwargs):
        calls[0] += 1
        if calls[0] == n:
            raise OSError(err, os.strerror(err))
        return real(*args, **kwargs)
    with monkeypatch.context() as m:
        m.setattr(os, name, faulty)
        yield calls


@contextlib.contextmanager
def file_size_limit(nbytes):
    """Writes that would make a file larger than nbytes fail with EFBIG (as
    on a full disk); Python ignores SIGXFSZ, so they raise OSError."""
    soft, hard = resource.getrlimit(resource.RLIMIT_FSIZE)
    resource.setrlimit(resource.RLIMIT_FSIZE, (nbytes, hard))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_FSIZE, (soft, hard))


@pytest.fixture(scope="module")
def atlases():
    return libkin.explore("threebar:RC", depth=1), libkin.explore("sail:4:1", depth=1)


def _save_fig(path, k):
    from libkin.plot import draw3d, pyplot
    plt = pyplot()
    fig = plt.figure(figsize=(2, 2))
    fig.gca().plot(np.arange(10) ** (k + 1))
    try:
        draw3d.save_small(fig, path, 50)
    finally:
        plt.close(fig)


def writers(atlases):
    """name -> write(path, k): k = 0 the good result, 1 a different new one."""
    from libkin.atlas import plot as atlas_plot
    models = [Assembly.threebar("RC"), Assembly.sail(4, 1)]
    return {
        "Assembly.to_json": lambda p, k: models[k].to_json(p),
        "write_fold": lambda p, k: write_fold(p, models[k]),
        "Atlas.to_json": lambda p, k: atlases[k].to_json(p),
        "Atlas.to_graphml": lambda p, k: atlases[k].to_graphml(p),
        "atlas draw_map": lambda p, k: atlas_plot.draw_map(atlases[k], p),
        "atlas draw_nodes": lambda p, k: atlas_plot.draw_nodes(atlases[k], p),
        "draw3d.save_small (study figures)": _save_fig,
        "write_text (report.md, summary.json)": lambda p, k: atomic.write_text(p, f"{k}\n" * (70000 * (k + 1))),
    }


WRITER_NAMES = ["Assembly.to_json", "write_fold", "Atlas.to_json", "Atlas.to_graphml", "atlas draw_map",
                "atlas draw_nodes", "draw3d.save_small (study figures)", "write_text (report.md, summary.json)"]
SUFFIX = {"write_fold": ".fold", "Atlas.to_graphml": ".graphml", "atlas draw_map": ".png",
          "atlas draw_nodes": ".png", "draw3d.save_small (study figures)": ".png"}


@pytest.mark.parametrize("name", WRITER_NAMES)
def test_a_fault_keeps_the_file_saved_before(tmp_path, monkeypatch, atlases, name):
    write = writers(atlases)[name]
    path = tmp_path / ("result" + SUFFIX.get(name, ".json"))
    write(path, 0)
    good = snapshot(tmp_path)
    # the size of the new result, to put size limits inside it
    scratch = tmp_path.parent / f"{tmp_path.name}-scratch"
    scratch.mkdir()
    write(scratch / path.name, 1)
    new_size = (scratch / path.name).stat().st_size
    assert (scratch / path.name).read_bytes() != path.read_bytes()

    def check(kind):
        FAULTS[kind] += 1
        assert snapshot(tmp_path) == good, (name, kind)

    for n in (1, 2, 3):  # a full disk at the 1st, 2nd, 3rd os.write (libkin's own writes)
        with fail_nth(monkeypatch, "write", n) as calls:
            try:
                write(path, 1)
            except OSError:
                pass
        if calls[0] >= n:
            check(f"ENOSPC at os.write #{n}")
        elif path.read_bytes() != good[path.name]:  # matplotlib, PIL, networkx write through
            path.write_bytes(good[path.name])       # file objects: the size limits below
    for limit in (0, 1, new_size // 3, 2 * new_size // 3, new_size - 1):  # the disk fills at that byte
        with pytest.raises(OSError), file_size_limit(limit):
            write(path, 1)
        check("disk full at byte k of the new file (RLIMIT_FSIZE)")
    for call in ("fsync", "replace"):  # of the new file (the folder's fsync comes after the rename)
        with fail_nth(monkeypatch, call, 1), pytest.raises(OSError):
            write(path, 1)
        check(f"{call} of the new file fails")
    write(path, 1)  # with no fault the new result replaces the old one whole
    assert path.read_bytes() == (scratch / path.name).read_bytes()
    assert sorted(os.listdir(tmp_path)) == [path.name]


def test_the_atlas_folder_is_committed_whole(tmp_path, monkeypatch, atlases):
    out = tmp_path / "atl"
    atlas_report.write(atlases[0], out)
    (out / "notes.txt").write_text("the user's own file\n")
    good = snapshot(tmp_path)
    counts = {}
    scratch = tmp_path.parent / f"{tmp_path.name}-scratch"
    for call in ("replace", "fsync", "write"):
        with fail_nth(monkeypatch, call, 10 ** 6) as calls:  # count the calls of one good write
            atlas_report.write(atlases[1], scratch)
        counts[call] = calls[0]
    assert counts["replace"] >= 5 and counts["fsync"] >= 5
    for call, n_calls in counts.items():
        for n in range(1, n_calls + 1):
            try:
                with fail_nth(monkeypatch, call, n):
                    atlas_report.write(atlases[1], out)
            except OSError:
                FAULTS[f"atlas folder: os.{call} #n fails (each n)"] += 1
                assert snapshot(tmp_path) == good, (call, n)
            else:  # a folder's fsync (after a rename) may fail unreported: then the new set is whole
                assert call == "fsync", n
                new = snapshot(out)
                assert all(new[k] == v for k, v in snapshot(scratch).items() if k != atomic.MANIFEST), n
                atlas_report.write(atlases[0], out)
                assert snapshot(tmp_path) == good
    for limit in (0, 1000, 10000, 20000):
        with pytest.raises(OSError), file_size_limit(limit):
            atlas_report.write(atlases[1], out)
        FAULTS["atlas folder: disk full (RLIMIT_FSIZE)"] += 1
        assert snapshot(tmp_path) == good

    from libkin.atlas import plot as atlas_plot

    def broken(*args, **kwargs):
        raise RuntimeError("stopped between two files")
    with monkeypatch.context() as m:
        m.setattr(atlas_plot, "draw_nodes", broken)
        with pytest.raises(RuntimeError):
            atlas_report.write(atlases[1], out)
    FAULTS["atlas folder: stopped between two files"] += 1
    assert snapshot(tmp_path) == good

    atlas_report.write(atlases[1], out)  # the new atlas, whole, and the user's file kept
    new = snapshot(out)
    assert new["notes.txt"] == b"the user's own file\n"
    assert json.loads(new["atlas.json"]) == json.loads(atlases[1].to_json())
    assert new["report.md"] != good["atl/report.md"]
    assert sorted(os.listdir(tmp_path)) == ["atl"]


def test_commit_without_an_atomic_exchange(tmp_path, monkeypatch, atlases):
    """Where the system cannot swap two folders out is committed in place
    (a run folder in it, each output a link into it through one link that
    is switched): a failure at the nth os.replace, for each n, leaves the
    previous run's set, and the next holder of the lock tidies what it left."""
    out = tmp_path / "atl"
    atlas_report.write(atlases[0], out)  # exchanged: plain files
    (out / "notes").mkdir()
    good = snapshot(out)
    monkeypatch.setattr(atomic, "_exchange", lambda a, b: False)
    assert atomic.commit_mode(out) == "in place"
    for n in range(1, 100):
        try:
            with fail_nth(monkeypatch, "replace", n):
                atlas_report.write(atlases[1], out)
        except OSError:
            FAULTS["atlas folder in place: os.replace #n fails (each n)"] += 1
            assert {k: (out / k).read_bytes() if (out / k).is_file() else None for k in good} == good, n
            with atomic.folder_lock(out):
                pass
            assert {k: (out / k).read_bytes() if (out / k).is_file() else None for k in good} == good, n
            assert len(os.listdir(out / atomic.RUNS)) <= 1
            continue
        break
    assert n > 5
    assert json.loads((out / "atlas.json").read_text()) == json.loads(atlases[1].to_json())
    assert os.readlink(out / "atlas.json") == atomic.CURRENT + "/atlas.json" and (out / "notes").is_dir()
    assert len(os.listdir(out / atomic.RUNS)) == 1
    assert sorted(os.listdir(tmp_path)) == [".atl.lock", "atl"]




KILL_AT = """
import os, signal, sys
import libkin
from libkin.atlas import report
n, calls, real = int(sys.argv[2]), [0], os.replace
def replace(*a, **k):
    calls[0] += 1
    if calls[0] == n:
        os.kill(os.getpid(), signal.SIGKILL)
    return real(*a, **k)
os.replace = replace
report.write(libkin.explore("sail:4:1", depth=1), sys.argv[1])
"""


@pytest.mark.parametrize("n", [1, 2, 3, 5])
def test_a_kill_while_writing_keeps_the_folder(tmp_path, atlases, n):
    out = tmp_path / "atl"
    atlas_report.write(atlases[0], out)
    good = snapshot(out)
    r = subprocess.run([sys.executable, "-c", KILL_AT, str(out), str(n)], env=_env(), capture_output=True)
    assert r.returncode == -signal.SIGKILL, r.stderr
    FAULTS["SIGKILL at the nth rename (subprocess)"] += 1
    assert snapshot(out) == good
    with atomic.folder_lock(out):  # the next run clears what the killed one left
        pass
    assert sorted(os.listdir(tmp_path)) == [".atl.lock", "atl"]


@pytest.mark.parametrize("command", [["explore", "threebar:RC", "--depth", "1"], ["study", "--hub", "4", "--loops", "1"]])
def test_a_second_run_into_a_folder_in_use_fails_at_once(tmp_path, capsys, command):
    out = tmp_path / "out"
    out.mkdir()
    (out / "report.md").write_text("the running study's\n")
    good = snapshot(out)
    with atomic.folder_lock(out):
        t0 = time.perf_counter()
        assert main(command + ["--out", str(out), "--quiet"]) == 1
        assert time.perf_counter() - t0 < 5
    FAULTS["a second run into an --out in use"] += 1
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1
    assert snapshot(out) == good
    assert sorted(os.listdir(tmp_path)) == [".out.lock", "out"]


def test_two_concurrent_explores(tmp_path):
    out = tmp_path / "atl"
    cmd = [sys.executable, "-m", "libkin", "explore", "sail:4:1", "--depth", "1", "--out", str(out), "--quiet"]
    procs = [subprocess.Popen(cmd, env=_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE) for _ in range(2)]
    results = [(p.wait(timeout=300), p.stderr.read()) for p in procs]
    FAULTS["two concurrent libkin explore --out"] += 1
    codes = sorted(rc for rc, _ in results)
    assert codes in ([0, 0], [0, 1]), results  # [0, 0]: the first had finished before the second started
    for rc, err in results:
        if rc == 1:
            assert len(err.decode().strip().splitlines()) == 1
    names = sorted(os.listdir(out))
    assert names == [atomic.MANIFEST, "atlas.graphml", "atlas.json", "atlas_map.png", "atlas_nodes.png", "report.md"]
    assert json.loads((out / "atlas.json").read_text())["format"] == "libkin-atlas"
    assert sorted(os.listdir(tmp_path)) == [".atl.lock", "atl"]


def test_a_run_replaces_the_previous_outputs_as_a_set(tmp_path):
    """A run that writes fewer files (a study stopped early) leaves none of
    the previous run's beside its own; the user's files stay; the MANIFEST
    names, sizes and hashes what the run wrote."""
    import hashlib
    out = tmp_path / "out"
    with atomic.staged_folder(out) as stage:
        atomic.write_text(stage / "summary.json", "{}\n")
        atomic.write_text(stage / "report.md", "old report\n")
    (out / "notes.txt").write_text("mine\n")
    with atomic.staged_folder(out) as stage:
        atomic.write_text(stage / "summary.json", '{"failed": "early"}\n')
    assert sorted(os.listdir(out)) == [atomic.MANIFEST, "notes.txt", "summary.json"]
    files = json.loads((out / atomic.MANIFEST).read_text())["files"]
    data = (out / "summary.json").read_bytes()
    assert files == {"summary.json": {"size": len(data), "sha256": hashlib.sha256(data).hexdigest()}}


def test_the_study_folder_is_committed_whole(tmp_path, monkeypatch):
    from libkin.studies import squarestudy
    out = tmp_path / "study"
    with fail_nth(monkeypatch, "replace", 10 ** 6) as calls:  # counts the renames of a good run
        assert main(["study", "--hub", "4", "--loops", "1", "--out", str(out), "--quiet"]) == 0
    assert calls[0] >= 3
    (out / "notes.txt").write_text("mine\n")
    good = snapshot(tmp_path)
    for n in (1, calls[0]):  # the first file, the MANIFEST (the last)
        with fail_nth(monkeypatch, "replace", n), pytest.raises(OSError):
            squarestudy.square_study(progress=False, out=out)
        FAULTS["study folder: os.replace #n fails"] += 1
        assert snapshot(tmp_path) == good, n
    with file_size_limit(5000):  # the command: one line, exit 1, the folder kept
        assert main(["study", "--hub", "4", "--loops", "1", "--out", str(out), "--quiet"]) == 1
    FAULTS["study folder: disk full (RLIMIT_FSIZE)"] += 1
    assert snapshot(tmp_path) == good


def test_out_is_the_working_folder_or_a_link(tmp_path, monkeypatch, atlases):
    """`--out .` keeps the folder the shell stands in (files renamed in one
    by one, the MANIFEST last); a link to a folder keeps pointing at it."""
    here = tmp_path / "here"
    here.mkdir()
    (here / "notes.txt").write_text("mine\n")
    monkeypatch.chdir(here)
    inode = os.stat(".").st_ino
    atlas_report.write(atlases[0], ".")
    atlas_report.write(atlases[1], ".")
    assert os.stat(".").st_ino == inode and os.path.samefile(".", here)
    assert json.loads((here / "atlas.json").read_text()) == json.loads(atlases[1].to_json())
    assert (here / "notes.txt").read_text() == "mine\n"
    assert sorted(os.listdir(tmp_path)) == ["here"]
    link = tmp_path / "link"
    link.symlink_to(here)
    atlas_report.write(atlases[0], link)
    assert link.is_symlink()
    assert json.loads((here / "atlas.json").read_text()) == json.loads(atlases[0].to_json())
