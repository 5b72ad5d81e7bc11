"""JSON model format, plots and the command line."""
import json
import subprocess
import sys

import numpy as np
import pytest

import libkin
from libkin import plot


def test_shared_models_load(shared_models):
    counts = {"threebar_RA": (2, 1), "threebar_RB": (2, 1), "threebar_RC": (2, 1),
              "square_sail": (6, 4), "hex_sail": (16, 15)}
    for name, (m, s) in counts.items():
        a = libkin.Assembly.from_json(shared_models / f"{name}.json")
        an = a.analyse()
        assert (an.m, an.s) == (m, s), name


def test_round_trip(tmp_path):
    a = libkin.Assembly.sail(6, 2)
    path = tmp_path / "hex.json"
    doc = a.to_json(path)
    b = libkin.Assembly.from_json(path)
    assert np.array_equal(a.coords, b.coords) and np.array_equal(a.bars, b.bars)
    assert np.array_equal(a.fixed, b.fixed) and np.array_equal(a.rest_lengths, b.rest_lengths)
    assert b.labels == a.labels and doc["joints"][0]["label"] == "C"
    assert libkin.Assembly.from_json(json.dumps(doc)).nfree == 46


@pytest.mark.parametrize("mutate, message", [
    (lambda d: d.update(dimension=4), "dimension: expected 2 or 3"),
    (lambda d: d["joints"][3].update(xyz=[1, 2]), r"joints\[3\].xyz: expected 3 numbers"),
    (lambda d: d["joints"][1].update(xyz=[1, "a", 0]), r"joints\[1\].xyz\[1\]"),
    (lambda d: d["joints"][2].update(free=[1, 0, 1]), r"joints\[2\].free"),
    (lambda d: d["joints"][2].update(index=7), r"joints\[2\].index: expected 2"),
    (lambda d: d["bars"][5].update(joints=[0, 99]), r"bars\[5\].joints: joint 99 out of range"),
    (lambda d: d["bars"][5].update(joints=[0]), r"bars\[5\].joints: expected two"),
    (lambda d: d["bars"][4].update(length=-1.0), r"bars\[4\].length: expected > 0"),
    (lambda d: d["bars"][4].pop("length"), "every bar or for none"),
    (lambda d: d.pop("joints"), "joints: expected a non-empty list"),
])
def test_malformed_models_name_field_and_position(mutate, message):
    doc = libkin.Assembly.sail(6, 2).to_json()
    mutate(doc)
    with pytest.raises(libkin.ModelFormatError, match=message):
        libkin.Assembly.from_json(doc)


def test_json_syntax_error(tmp_path):
    p = tmp_path / "bad.json"
    p.write_text('{"dimension": 2,\n "joints": [}')
    with pytest.raises(libkin.ModelFormatError, match="line 2"):
        libkin.Assembly.from_json(p)


def test_plots_are_written(tmp_path):
    a = libkin.Assembly.sail(6, 2)
    plot.draw(a, path=tmp_path / "hex.png")
    plot.draw(a, plane="xz", path=tmp_path / "hex_xz.png")
    an = a.analyse()
    plot.branch_directions(a, an.internal_mechanisms.T[:3], path=tmp_path / "dirs.png")
    b = libkin.Assembly.threebar("RC")
    xyz = b.coords
    xyz[:2] = [[0.6, 0.8], [1.6, 0.8]]
    b.coords = xyz
    ls, svs, frames = [], [], []
    for info in b.follow(steps=8):
        ls.append(info.l)
        svs.append(b.analyse().singular_values)
        frames.append(b.coords)
    plot.singular_values(ls, np.array(svs), path=tmp_path / "sv.png")
    plot.animate(frames, b.bars, tmp_path / "p.gif")
    for f in ["hex.png", "hex_xz.png", "dirs.png", "sv.png", "p.gif"]:
        assert (tmp_path / f).stat().st_size > 1000, f


def run_cli(*args):
    return subprocess.run([sys.executable, "-m", "libkin", *args], capture_output=True, text=True, timeout=120)


def test_cli(tmp_path, shared_models):
    r = run_cli("--help")
    assert r.returncode == 0 and "analyse" in r.stdout and "follow" in r.stdout
    r = run_cli("analyse", str(shared_models / "hex_sail.json"))
    assert r.returncode == 0 and "m = 16" in r.stdout and "s = 15" in r.stdout
    r = run_cli("follow", str(shared_models / "hex_sail.json"), "--perturb", "0.3", "--steps", "10",
                "--plot", str(tmp_path / "sv.png"), "--quiet")
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "sv.png").stat().st_size > 1000
    r = run_cli("follow", "threebar:RC", "--steps", "3")
    assert r.returncode == 2 and "bifurcation" in r.stderr
    r = run_cli("analyse", str(tmp_path / "missing.json"))
    assert r.returncode == 1 and "libkin:" in r.stderr
    r = run_cli("models", str(tmp_path / "m"))
    assert r.returncode == 0 and (tmp_path / "m" / "hex_sail.json").exists()


def test_cli_locate(tmp_path):
    """From a lifted, relaxed three-bar linkage along its path to the next
    bifurcation, with each method; a bifurcation start is refused."""
    for method in ("fast", "paper", "illinois"):
        r = run_cli("locate", "threebar:RC", "--perturb", "0.5", "--method", method, "--delta", "0.1",
                    "--out", str(tmp_path / f"{method}.json"))
        assert r.returncode == 0, r.stderr
        assert f"by the {method} method" in r.stdout and "m = 2, s = 1" in r.stdout
        assert (tmp_path / f"{method}.json").exists()
    r = run_cli("locate", "threebar:RC")
    assert r.returncode == 2 and "bifurcation" in r.stderr
    r = run_cli("locate", "threebar:RC", "--perturb", "0.5", "--method", "bogus")
    assert r.returncode == 2
