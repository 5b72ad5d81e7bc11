"""Nothing lost, round two (issue 39 items 1 and 2): the folder commit's last
window and the lock of a killed run's workers.

- a kill just after the staging folder is swapped in (while the user's own
  subfolders of --out are moved back): the next run's recovery puts them
  back, it never deletes what it did not write (atlas.report.write,
  `libkin explore`, `libkin study`);
- `--out .` (a folder that is not exchanged): a kill at any rename leaves
  one run's set (the MANIFEST's files, each with its hash), never a new
  atlas.json beside an old report;
- a mount point is committed in place; a read-only --out is refused before
  any work, with one line and exit code 1;
- SIGKILL to `libkin explore --executor process`: no pool worker survives
  its parent and `--resume` is not refused (the lock is the parent's own)."""
import hashlib
import json
import os
import pathlib
import shutil
import signal
import subprocess
import sys
import time
import uuid

import pytest

import libkin
from libkin import atomic
from libkin.atlas import report as atlas_report
from libkin.atlas.model import Atlas
from subprocess_env import libkin_env as _env  # noqa: E402




@pytest.fixture(scope="module")
def atlases(tmp_path_factory):
    """Two atlases (as JSON files a subprocess loads) and the atlases."""
    folder = tmp_path_factory.mktemp("atlases")
    ats = [libkin.explore("threebar:RC", depth=1), libkin.explore("sail:4:1", depth=1)]
    paths = []
    for k, at in enumerate(ats):
        ats[k].to_json(folder / f"a{k}.json")
        paths.append(folder / f"a{k}.json")
    return ats, paths


def one_runs_set(out):
    """The MANIFEST of out (read through links) and every file it names,
    each with its size and hash: one run's set, or an AssertionError."""
    out = pathlib.Path(out)
    files = json.loads((out / atomic.MANIFEST).read_text())["files"]
    for name, meta in files.items():
        data = (out / name).read_bytes()
        assert len(data) == meta["size"] and hashlib.sha256(data).hexdigest() == meta["sha256"], name
    return files


# a subprocess that SIGKILLs itself at a rename (os.rename or os.replace):
# the nth one (KILL_N), or the first whose destination ends with KILL_DST
KILLER = """
import os, signal, sys
n, dst, calls = int(os.environ.get("KILL_N", "0")), os.environ.get("KILL_DST"), [0]
def patch(name):
    real = getattr(os, name)
    def renamed(a, b, *args, **kwargs):
        calls[0] += 1
        if calls[0] == n or (dst and os.fspath(b).endswith(dst)):
            os.kill(os.getpid(), signal.SIGKILL)
        return real(a, b, *args, **kwargs)
    setattr(os, name, renamed)
patch("rename"); patch("replace")
if os.environ.get("NO_EXCHANGE"):  # a file system that cannot swap two folders
    from libkin import atomic
    atomic._exchange = lambda a, b: False
what = sys.argv[1]
if what == "report":
    import json
    from libkin.atlas import report
    from libkin.atlas.model import Atlas
    report.write(Atlas.from_dict(json.load(open(sys.argv[2]))), sys.argv[3])
else:
    from libkin.cli import main
    sys.exit(main(sys.argv[2:]))
"""


def _run_killer(args, cwd=None, **env):
    return subprocess.run([sys.executable, "-c", KILLER, *map(str, args)], env=_env(**env), cwd=cwd,
                          capture_output=True, text=True, timeout=600)


COMMANDS = {
    "report.write": lambda at, out: ["report", at, out],
    "libkin explore": lambda at, out: ["cli", "explore", "threebar:RC", "--depth", "1", "--out", out, "--quiet"],
    "libkin study": lambda at, out: ["cli", "study", "--hub", "4", "--loops", "1", "--out", out, "--quiet"],
}


@pytest.mark.parametrize("command", list(COMMANDS))
def test_a_kill_after_the_swap_keeps_the_users_subfolders(tmp_path, atlases, command):
    out = tmp_path / "out"
    ats, paths = atlases
    atlas_report.write(ats[0], out)  # a previous run's outputs
    (out / "notes").mkdir()
    (out / "notes" / "todo.txt").write_text("the user's own folder\n")
    (out / "notes.txt").write_text("the user's own file\n")
    r = _run_killer(COMMANDS[command](paths[1], out), KILL_DST=os.sep + "notes")
    assert r.returncode == -signal.SIGKILL, r.stderr  # killed moving notes/ back into the new out
    with atomic.folder_lock(out):  # the next run's recovery
        pass
    assert (out / "notes" / "todo.txt").read_text() == "the user's own folder\n"
    assert (out / "notes.txt").read_text() == "the user's own file\n"
    one_runs_set(out)
    assert sorted(p.name for p in tmp_path.iterdir() if "staging" in p.name or ".old-" in p.name) == []
    # and the next run keeps them too
    atlas_report.write(ats[0], out)
    assert (out / "notes" / "todo.txt").read_text() == "the user's own folder\n"


def _outputs(atlas, out):
    atlas_report.write(atlas, out)
    return one_runs_set(out)


@pytest.mark.parametrize("kind", ["cwd", "no exchange"])
def test_a_folder_committed_in_place_shows_one_runs_set_at_every_kill(tmp_path, atlases, kind):
    """`--out .` (and a folder the system cannot exchange): a kill at the
    nth rename, for every n, leaves the previous run's set or the new one."""
    here = tmp_path / "here"
    here.mkdir()
    (here / "notes.txt").write_text("mine\n")
    (here / "sub").mkdir()
    ats, paths = atlases
    old = _outputs(ats[0], tmp_path / "ref0")
    new = _outputs(ats[1], tmp_path / "ref1")
    subprocess.run([sys.executable, "-c", KILLER, "report", str(paths[0]), "."], env=_env(), cwd=here,
                   check=True, timeout=600)
    seen = set()
    env = {} if kind == "cwd" else {"NO_EXCHANGE": "1"}
    out = "." if kind == "cwd" else str(here)
    cwd = here if kind == "cwd" else tmp_path
    for n in range(1, 40):
        r = _run_killer(["report", paths[1], out], cwd=cwd, KILL_N=str(n), **env)
        if r.returncode == 0:
            break
        assert r.returncode == -signal.SIGKILL, r.stderr
        files = one_runs_set(here)
        assert files in (old, new), n
        seen.add("old" if files == old else "new")
        with atomic.folder_lock(here):
            pass
        assert one_runs_set(here) == files
        if files == new:  # back to the previous run's outputs for the next n
            subprocess.run([sys.executable, "-c", KILLER, "report", str(paths[0]), out], env=_env(**env),
                           cwd=cwd, check=True, timeout=600)
        assert (here / "notes.txt").read_text() == "mine\n" and (here / "sub").is_dir()
    assert one_runs_set(here) == new and n > 2
    assert "old" in seen
    assert sorted(os.listdir(tmp_path)) == [".here.lock", "here", "ref0", "ref1"] or kind == "cwd"


def _userns():
    if not shutil.which("unshare") or subprocess.run(["unshare", "-rm", "true"], capture_output=True).returncode:
        pytest.skip("no user namespace (unshare -rm) to mount in")


def _in_namespace(script, cwd):
    return subprocess.run(["unshare", "-rm", "sh", "-ec", script], env=_env(), cwd=cwd, capture_output=True,
                          text=True, timeout=600)


def test_out_on_a_mount_point_is_committed(tmp_path):
    _userns()
    (tmp_path / "mnt").mkdir()
    explore = f"{sys.executable} -m libkin explore threebar:RC --depth 1 --out mnt --quiet"
    r = _in_namespace(f"mount -t tmpfs tmpfs mnt; echo mine > mnt/notes.txt; {explore}; {explore}; "
                      f"cat mnt/notes.txt; cat mnt/atlas.json", tmp_path)
    assert r.returncode == 0, r.stderr
    assert r.stdout.count("wrote") == 2 and "mine\n" in r.stdout and '"libkin-atlas"' in r.stdout


def test_a_read_only_out_is_refused_before_any_work(tmp_path):
    _userns()
    (tmp_path / "ro").mkdir()
    (tmp_path / "ro" / "old.txt").write_text("kept\n")
    r = _in_namespace(f"mount --bind ro ro; mount -o remount,bind,ro ro; "
                      f"{sys.executable} -m libkin explore sail:4:1 --depth 2 --out ro --quiet", tmp_path)
    assert r.returncode == 1, r.stderr
    assert len(r.stderr.strip().splitlines()) == 1 and "read-only" in r.stderr.lower(), r.stderr
    assert sorted(os.listdir(tmp_path)) == [".ro.lock", "ro"]  # no store: nothing was explored
    assert sorted(os.listdir(tmp_path / "ro")) == ["old.txt"]


def _tagged(tag):
    """The live processes whose environment holds tag."""
    found = []
    for p in pathlib.Path("/proc").iterdir():
        if p.name.isdigit():
            try:
                if tag.encode() in (p / "environ").read_bytes():
                    found.append(int(p.name))
            except OSError:
                pass
    return found


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="/proc")
def test_a_killed_process_pool_run_leaves_no_worker_and_resumes(tmp_path):
    out = tmp_path / "atl"
    tag = f"LIBKIN_TEST_TAG={uuid.uuid4().hex}"
    cmd = [sys.executable, "-m", "libkin", "explore", "sail:4:1", "--depth", "1", "--executor", "process",
           "--workers", "2", "--out", str(out), "--quiet"]
    # output to a file: an orphan worker would hold a pipe open (subprocess.run would wait for it)
    with open(tmp_path / "stderr.txt", "wb") as err:
        p = subprocess.Popen(cmd, env=_env(LIBKIN_STORE_KILL_AFTER="3", LIBKIN_TEST_TAG=tag.split("=")[1]),
                             stdout=subprocess.DEVNULL, stderr=err)
        rc = p.wait(timeout=600)
    assert rc == -signal.SIGKILL, (tmp_path / "stderr.txt").read_text()
    end = time.monotonic() + 5
    while _tagged(tag) and time.monotonic() < end:
        time.sleep(0.1)
    left = _tagged(tag)
    for pid in left:  # not left running after the test
        os.kill(pid, signal.SIGKILL)
    assert left == [], "pool workers outlived their killed parent"
    r = subprocess.run(cmd + ["--resume"], env=_env(), capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    assert json.loads((out / "atlas.json").read_text())["stats"]["store"]["reused"] == 3
