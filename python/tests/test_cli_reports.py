"""Commands say what happened: `libkin follow` reports each bifurcation it
passes; `libkin draw` tells a roller from a pin."""
import json
import math
import re
import subprocess
import sys

import numpy as np

import libkin
from libkin import cli


def parallelogram(path):
    """A rectangle-shaped parallelogram four-bar (supports 2 apart, cranks of
    length 1): per turn it passes the two flat states, where it can switch to
    the anti-parallelogram branch."""
    model = {"name": "parallelogram", "dimension": 2,
             "joints": [{"index": 0, "xyz": [0.0, 1.0], "free": [True, True]},
                        {"index": 1, "xyz": [2.0, 1.0], "free": [True, True]},
                        {"index": 2, "xyz": [0.0, 0.0], "free": [False, False]},
                        {"index": 3, "xyz": [2.0, 0.0], "free": [False, False]}],
             "bars": [{"index": 0, "joints": [0, 2], "length": 1.0},
                      {"index": 1, "joints": [0, 1], "length": 2.0},
                      {"index": 2, "joints": [1, 3], "length": 1.0}]}
    path.write_text(json.dumps(model))
    return path


TURN = 2 * math.pi * math.sqrt(2)  # path length of one turn: both cranks move


def test_follow_reports_both_bifurcations_of_a_turn(tmp_path):
    a = libkin.Assembly.from_json(parallelogram(tmp_path / "p.json"))
    an = a.analyse()
    steps = int(0.99 * TURN / 0.1)
    path = cli.follow_path(a, an, steps, delta=0.1)
    ls, frames, passed = path.lengths, path.frames, path.passed
    assert len(ls) == steps + 1 and abs(ls[-1]) < TURN
    assert len(passed) == 2
    for k, l0, l1 in passed:
        assert ls[k - 1] == l0 and ls[k] == l1
        # the crank crossed the line of the supports between the two frames
        y0, y1 = frames[k - 1][0, 1], frames[k][0, 1]
        assert y0 * y1 <= 0
    r = subprocess.run([sys.executable, "-m", "libkin", "follow", str(tmp_path / "p.json"), "--steps", str(steps),
                        "--delta", "0.1", "--quiet"], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    m = re.search(r"passed (\d+) bifurcation", r.stdout)
    assert m and int(m.group(1)) == 2


def test_draw_tells_a_roller_from_a_pin(tmp_path):
    """A joint fixed in one coordinate (a roller) gets its own marker and
    legend entry, not the pinned supports' triangle."""
    from libkin import plot
    model = json.loads(parallelogram(tmp_path / "p.json").read_text())
    model["joints"][3]["free"] = [True, False]  # the right support rolls along x
    (tmp_path / "r.json").write_text(json.dumps(model))
    a = libkin.Assembly.from_json(tmp_path / "r.json")
    fig = plot.draw(a)
    ax = fig.axes[0]
    by_marker = {ln.get_marker(): ln for ln in ax.get_lines() if ln.get_marker() in ("^", "s")}
    assert set(by_marker) == {"^", "s"}
    np.testing.assert_array_equal(by_marker["^"].get_xydata(), [[0.0, 0.0]])
    np.testing.assert_array_equal(by_marker["s"].get_xydata(), [[2.0, 0.0]])
    legend = ax.get_legend()
    assert legend is not None and len(legend.get_texts()) == 2
    r = subprocess.run([sys.executable, "-m", "libkin", "draw", str(tmp_path / "r.json"), str(tmp_path / "r.png")],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "r.png").stat().st_size > 1000
