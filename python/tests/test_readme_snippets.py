"""Every ```sh and ```python block of README.md and python/README.md runs,
verbatim, in a fresh copy of the repository.

A comment line right before a block says how it is run:
- no marker: run by the normal suite (tools/run_tests.sh);
- ``<!-- snippet: slow -->``: run only with LIBKIN_TEST_SLOW=1 (pip installs
  and CMake builds from scratch: minutes). Blocks after an unrun install use a
  stand-in for what it installs: ``.venv/bin/libkin`` and ``python`` run the
  copy's python/src with the build tree's library;
- ``<!-- snippet: skip WHY -->``: not run here; WHY names what runs it (the
  README's first block, which runs the whole job and every test).

The copy holds the files git tracks (as they are in the working tree), so a
snippet that needs an untracked file fails here as it would after a clone.
Blocks of one README run in order in the same copy, as a reader would.
"""
import os
import pathlib
import re
import shutil
import stat
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
READMES = ["README.md", "python/README.md"]
SLOW = os.environ.get("LIBKIN_TEST_SLOW") == "1"
BLOCK = re.compile(r"(?:<!--\s*snippet:\s*(\w+)[^>]*-->\s*\n)?```(sh|python)\n(.*?)```", re.S)


def blocks(readme):
    """(marker, language, code) of each sh/python block, in order."""
    text = (ROOT / readme).read_text()
    return [(m.group(1) or "run", m.group(2), m.group(3)) for m in BLOCK.finditer(text)]


def test_every_block_is_marked_run_slow_or_skip():
    found = 0
    for readme in READMES:
        for marker, _, code in blocks(readme):
            assert marker in ("run", "slow", "skip"), (readme, marker, code)
            found += 1
    assert found >= 6


# what .gitignore leaves out (and git's own folder, and tool caches): the
# copy without git; the first at the top folder only
UNTRACKED_TOP = ("build*",)
UNTRACKED = ("build", "__pycache__", "*.egg-info", ".venv", "out", "study_out", ".hypothesis", ".git",
             ".pytest_cache", ".mypy_cache")


def tracked_files():
    """The repository's files as git tracks them; without git (not installed,
    or an unpacked archive) every file .gitignore does not leave out."""
    if shutil.which("git") and (ROOT / ".git").exists():
        files = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True).stdout
        return [n for n in files.decode().split("\0") if n and (ROOT / n).is_file()]
    out = []
    for d, dirs, names in os.walk(ROOT):
        rel = pathlib.PurePath(d).relative_to(ROOT)
        skip = UNTRACKED + (UNTRACKED_TOP if str(rel) == "." else ())
        dirs[:] = [x for x in dirs if not any(pathlib.PurePath(x).match(p) for p in skip)]
        out += [str(rel / n) if str(rel) != "." else n for n in names if n != ".git"]
    return out


def fresh_copy(dest):
    for name in tracked_files():
        (dest / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(ROOT / name, dest / name)


def test_copy_needs_no_git(monkeypatch):
    """Without git the copy holds the same files (the working tree less what
    .gitignore leaves out)."""
    with_git = set(tracked_files()) if shutil.which("git") else None
    monkeypatch.setattr(shutil, "which", lambda cmd, *a, **k: None)
    monkeypatch.setenv("PATH", "/nonexistent")
    without = set(tracked_files())
    assert "README.md" in without and "CMakeLists.txt" in without
    assert not any(n.startswith(("build/", ".git/")) or "__pycache__" in n for n in without)
    if with_git is not None:
        assert with_git <= without


def stand_in_install(clone, env, bin_dir):
    """What `pip install ./python` provides, without building: the copy's
    package on PYTHONPATH, the build tree's library, and a `libkin` command
    (on PATH and as .venv/bin/libkin)."""
    env["LIBKIN_LIBRARY"] = os.environ.get("LIBKIN_LIBRARY") or str(ROOT / "build" / "libkin.so")
    env["PYTHONPATH"] = str(clone / "python" / "src")
    for d in (bin_dir, clone / ".venv" / "bin"):
        d.mkdir(parents=True)
        script = d / "libkin"
        script.write_text(f'#!/bin/sh\nexec "{sys.executable}" -m libkin "$@"\n')
        script.chmod(script.stat().st_mode | stat.S_IXUSR)
    env["PATH"] = os.pathsep.join([str(bin_dir), str(pathlib.Path(sys.executable).parent), env["PATH"]])


@pytest.mark.parametrize("readme", READMES)
def test_readme_blocks_run_in_a_fresh_copy(readme, tmp_path):
    clone = tmp_path / "libkin"
    fresh_copy(clone)
    env = {k: v for k, v in os.environ.items() if k not in ("LIBKIN_LIBRARY", "PYTHONPATH")}
    env["HOME"] = str(tmp_path / "home")
    env["MPLBACKEND"] = "Agg"
    if SLOW:
        # a reader's own virtual environment for python/README.md's `pip install`
        subprocess.run([sys.executable, "-m", "venv", str(tmp_path / "env")], check=True)
        env["PATH"] = f"{tmp_path / 'env' / 'bin'}{os.pathsep}{env['PATH']}"
    else:
        stand_in_install(clone, env, tmp_path / "bin")
    ran = 0
    for k, (marker, lang, code) in enumerate(blocks(readme)):
        if marker == "skip" or (marker == "slow" and not SLOW):
            continue
        if lang == "sh":
            cmd = ["bash", "-euo", "pipefail", "-c", code]
        else:
            script = tmp_path / f"block{k}.py"
            script.write_text(code)
            cmd = ["python", str(script)]
        r = subprocess.run(cmd, cwd=clone, env=env, capture_output=True, text=True, timeout=1800)
        assert r.returncode == 0, f"{readme} block {k} ({lang}) failed:\n{code}\n{r.stdout[-3000:]}\n{r.stderr[-3000:]}"
        ran += 1
    assert ran >= 1


def test_example_models_are_what_the_readmes_say():
    import libkin

    counts = {"threebar_RA": (2, 1), "threebar_RB": (2, 1), "threebar_RC": (2, 1), "square_sail": (6, 4),
              "hex_sail": (16, 15), "fold_vertex": (2, 1)}
    models = ROOT / "examples" / "models"
    assert {p.stem for p in models.glob("*.json")} == set(counts)
    for name, (m, s) in counts.items():
        with libkin.Assembly.from_json(models / f"{name}.json") as a:
            an = a.analyse()
            assert (an.m, an.s) == (m, s), name
    with libkin.Assembly.from_json(models / "fold_vertex.json") as fv:
        assert fv.dim == 3
        br = fv.branches(length=0.5)
        assert br.accounting["real_distinct"] == 2 and br.distinct == 4
        assert all(p.exists and p.tangent_ok for p in br.paths)
