"""Limits said where they bite (issue 36 item 6): `libkin explore` says on
stderr which limit stopped the run and how to lift it; `libkin study` refuses
before any work, naming every missing extra at once; libkin.load_model takes
the built-in names the command line takes."""
import subprocess
import sys

import libkin
from libkin.cli import main
from subprocess_env import libkin_env  # noqa: E402

MODEL = "sail:4:1"


def test_explore_says_max_nodes_stopped_it(tmp_path, capsys):
    out = tmp_path / "atl"
    assert main(["explore", MODEL, "--depth", "2", "--max-nodes", "2", "--out", str(out), "--quiet"]) == 0
    err = capsys.readouterr().err
    said = [line for line in err.splitlines() if "--max-nodes" in line]
    assert len(said) == 1, err  # one line, even with --quiet
    assert "depth 1" in said[0] and "2" in said[0] and "raise" in said[0]


def test_explore_says_max_length_bit(tmp_path, capsys):
    out = tmp_path / "atl"
    assert main(["explore", MODEL, "--depth", "1", "--max-length", "0.01", "--out", str(out), "--quiet"]) == 0
    err = capsys.readouterr().err
    assert sum("--max-length" in line for line in err.splitlines()) == 1, err


def test_explore_says_time_limit_stopped_it(tmp_path, capsys):
    out = tmp_path / "atl"
    assert main(["explore", MODEL, "--depth", "2", "--time-limit", "0.001", "--out", str(out), "--quiet"]) == 0
    err = capsys.readouterr().err
    said = [line for line in err.splitlines() if "--time-limit" in line]
    assert len(said) == 1 and "--resume" in said[0], err


def test_explore_says_nothing_when_no_limit_bites(tmp_path, capsys):
    out = tmp_path / "atl"
    assert main(["explore", "threebar:RC", "--depth", "1", "--out", str(out), "--quiet"]) == 0
    err = capsys.readouterr().err
    assert "--max-nodes" not in err and "--time-limit" not in err


# run libkin's command line with the named modules unimportable, as if not installed
_BLOCKED = """
import sys
class _Block:
    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] in {blocked!r}:
            raise ImportError("blocked: " + name)
        return None
sys.meta_path.insert(0, _Block())
from libkin.cli import main
sys.exit(main(sys.argv[1:]))
"""


def _run_blocked(blocked, *argv, cwd):
    return subprocess.run([sys.executable, "-c", _BLOCKED.format(blocked=set(blocked)), *argv], env=libkin_env(), cwd=cwd,
                          capture_output=True, text=True, timeout=120)


def test_study_refuses_before_any_work_naming_every_missing_extra(tmp_path):
    out = tmp_path / "study"
    r = _run_blocked({"matplotlib", "distributed"}, "study", "--quick", "--map-depth", "1", "--executor", "dask",
                     "--out", str(out), cwd=tmp_path)
    assert r.returncode != 0
    err = r.stderr.strip().splitlines()
    assert len(err) == 1, r.stderr  # one message
    assert "matplotlib" in err[0] and "distributed" in err[0] and "plot" in err[0] and "dask" in err[0]
    assert "[map]" not in r.stdout + r.stderr  # no work started
    assert not out.exists() and list(tmp_path.iterdir()) == []  # nothing written, not even the lock


def test_explore_names_every_missing_extra_at_once(tmp_path):
    out = tmp_path / "atl"
    r = _run_blocked({"networkx", "plotly"}, "explore", "threebar:RC", "--html", "--out", str(out), "--quiet",
                     cwd=tmp_path)
    assert r.returncode != 0
    err = r.stderr.strip().splitlines()
    assert len(err) == 1 and "networkx" in err[0] and "plotly" in err[0], r.stderr
    assert list(tmp_path.iterdir()) == []


def test_load_model_takes_builtin_names():
    a = libkin.load_model(MODEL)
    b = libkin.Assembly.sail(4, 1)
    assert a.coords.shape == b.coords.shape and abs(a.coords - b.coords).max() == 0
    assert libkin.load_model("threebar:RC", engine="c").coords.shape == libkin.Assembly.threebar("RC").coords.shape


def test_default_node_limit_lets_the_depth_bound_the_run():
    """`libkin explore sail:6:2 --depth 2` stopped at depth 1 on --max-nodes'
    default of 200 (its first level has 20,523 nodes; docs/atlas.md): the
    default now exceeds every documented run (the hexagonal sail's whole
    graph to depth 6: about 27,000 nodes), in the command and in explore()."""
    import argparse
    import inspect
    from libkin.atlas import cli as atlas_cli
    p = argparse.ArgumentParser()
    atlas_cli.add_arguments(p)
    args = p.parse_args(["sail:6:2", "--depth", "2", "--out", "x"])
    assert args.max_nodes >= 100_000
    assert inspect.signature(libkin.explore).parameters["max_nodes"].default == args.max_nodes


def test_writing_the_atlas_reports_each_file(tmp_path, capsys):
    """Long phases are not silent: report.write names each file as it starts
    and says when it is done (a callable gets files done / in all); the
    command prints them unless --quiet."""
    from libkin.atlas import report
    at = libkin.explore("threebar:RC", depth=1)
    seen = []
    report.write(at, tmp_path / "a", html="atlas.html",
                 progress=lambda done, total, what: seen.append((done, total, what)))
    files = ["atlas.json", "atlas.graphml", "atlas_map.png", "atlas_nodes.png", "atlas.html", "report.md"]
    assert [d for d, _, _ in seen] == list(range(len(files) + 1)) and {t for _, t, _ in seen} == {len(files)}
    assert [w.split(":")[0] for _, _, w in seen[:-1]] == files
    assert main(["explore", "threebar:RC", "--out", str(tmp_path / "b"), "--html"]) == 0
    err = capsys.readouterr().err
    for f in files:  # a line as it starts and one as it ends
        assert sum(line.startswith("[write] " + f) for line in err.splitlines()) == 2, err
