"""`libkin follow` counts the bifurcations it passes with the library's
detector (kin_follow_event: the signed test function and the turn of v_r,
then location, which must bring v_r to zero: what `libkin locate` and
`libkin explore` use), prints v_r as the library defines it, and calls a
rigid structure rigid (issue 36 item 1).

Before: a sign change of kin_test_function alone counted. With the 6 rigid
mechanisms of a free structure its sign flips where nothing happens (the
free two-triangle crease: 6 "bifurcations" in 40 steps, v_r >= 0.765); on a
path with a self-stress (s >= 1) it has no sign and every bifurcation was
missed; its "smallest v_r" was the smallest positive singular value of all
of H (a rounding zero where s >= 1)."""
import json
import math
import pathlib
import re

import numpy as np
import pytest

from libkin import cli
from libkin.assembly import solve_quadrics
from libkin.cliargs import EXIT_USAGE, load_model_spec

ROOT = pathlib.Path(__file__).resolve().parents[2]
SINGLE_FOLD = ROOT / "python" / "tests" / "data" / "fold" / "single_fold.fold"
SQUARE_SAIL = ROOT / "examples" / "models" / "square_sail.json"

# a unit square folded about its diagonal 3-1, no supports (6 rigid mechanisms in 3D)
CREASE_FOLD = {"vertices_coords": [[0, 0], [1, 0], [1, 1], [0, 1]],
               "edges_vertices": [[0, 1], [1, 2], [2, 3], [3, 0], [3, 1]],
               "edges_assignment": ["B", "B", "B", "B", "V"], "faces_vertices": [[0, 1, 3], [1, 2, 3]]}


def _model(name, coords, free, bars):
    return {"name": name, "dimension": len(coords[0]),
            "joints": [{"index": i, "xyz": [float(c) for c in x], "free": f}
                       for i, (x, f) in enumerate(zip(coords, free))],
            "bars": [{"index": k, "joints": b, "length": math.dist(coords[b[0]], coords[b[1]])}
                     for k, b in enumerate(bars)]}


@pytest.fixture
def models(tmp_path):
    crease = [[x, y, 0.0] for x, y in CREASE_FOLD["vertices_coords"]]
    # the parallelogram four-bar whose coupler is a braced quadrilateral (one
    # redundant bar: s = 1 all along the path); it passes the flat state where
    # the cranks lie along the line of the supports
    braced = [[0.0, 1.0], [2.0, 1.0], [0.0, 0.0], [2.0, 0.0], [0.3, 1.7], [2.1, 1.9]]
    files = {
        "crease.fold": CREASE_FOLD,
        "crease.json": _model("crease", crease, [[True] * 3] * 4, CREASE_FOLD["edges_vertices"]),
        "braced.json": _model("braced", braced, [[True, True]] * 2 + [[False, False]] * 2 + [[True, True]] * 2,
                              [[0, 2], [0, 1], [1, 3], [0, 4], [1, 5], [4, 5], [0, 5], [1, 4]]),
    }
    for name, m in files.items():
        (tmp_path / name).write_text(json.dumps(m))
    return tmp_path


def follow(capsys, *args):
    rc = cli.main(["follow", *map(str, args), "--quiet"])
    out, err = capsys.readouterr()
    return rc, out, err


def passed_count(out):
    m = re.search(r"passed (no|\d+) bifurcation", out)
    assert m, out
    return 0 if m.group(1) == "no" else int(m.group(1))


def free_vector(a, xyz):
    fm = a.free_map()
    v = np.zeros(a.nfree)
    v[fm[fm >= 0]] = np.asarray(xyz)[fm >= 0]
    return v


def branch(a, k):
    """--branch k's direction: real second-order solution k // 2, sign + for even k."""
    betas, _ = solve_quadrics(a.second_order())
    return (1.0 if k % 2 == 0 else -1.0) * (a.analyse().internal_mechanisms @ betas[k // 2])


def located_bifurcations(a, length, direction=None):
    """The oracle: path lengths of the bifurcations kin_follow_event (what
    `libkin locate --branch` and `libkin explore` follow with) locates along
    the path from a within `length`, going on through each along the branch
    that continues the path, and past a near miss with one plain step."""
    a = a.clone()
    found, l, d = [], 0.0, direction
    while l < length:
        x_start = a.coords
        ev = a.follow_event(d, max_length=length - l, samples=100000)
        l += ev.length
        if ev.event in ("length-limit", "step-limit", "failed") or l >= length:
            break
        d = None
        if ev.event == "bifurcation":
            found.append(l)
            before = [x_start] + [x for x, s in zip(ev.samples, ev.sample_lengths) if s < ev.length]
            into = free_vector(a, a.coords) - free_vector(a, before[-1])
            betas, _ = solve_quadrics(a.second_order())
            dirs = [a.analyse().internal_mechanisms @ b for b in betas]
            cos = [float(v @ into) / float(np.linalg.norm(v)) for v in dirs]
            j = int(np.argmax(np.abs(cos)))
            d = math.copysign(1.0, cos[j]) * dirs[j]
        else:
            x0 = free_vector(a, a.coords)
            a.step()
            l += float(np.linalg.norm(free_vector(a, a.coords) - x0))
    return found


def followed(a, steps, direction=None):
    """The library's v_r, v_max and path length at each frame of the path the command follows."""
    a = a.clone()
    if direction is not None:
        a.set_direction(direction)
    an = a.analyse()
    rows = [(an.v_r, an.v_max, 0.0)]
    for info in a.follow(steps=steps):
        an = a.analyse()
        rows.append((an.v_r, an.v_max, info.l))
    return np.array(rows)


@pytest.mark.parametrize("name", ["crease.fold", "crease.json"])
def test_a_free_crease_passes_no_bifurcation(models, capsys, name):
    rc, out, _ = follow(capsys, models / name, "--steps", 40)
    assert rc == 0
    a = load_model_spec(str(models / name))
    path = followed(a, 40)
    # nothing happens on this path: v_r / v_max never below 0.4 (the test
    # function's sign, bordered with the SVD's rigid mechanisms, flips anyway)
    assert (path[:, 0] / path[:, 1]).min() > 0.4
    assert located_bifurcations(a, abs(path[-1, 2])) == []
    assert passed_count(out) == 0


@pytest.mark.parametrize("name", ["crease.json", "braced.json", "crease.fold"])
def test_printed_v_r_is_the_librarys(models, capsys, name):
    rc, out, _ = follow(capsys, models / name, "--steps", 40)
    assert rc == 0
    printed = float(re.search(r"smallest v_r ([^\s,(]+)", out).group(1))
    path = followed(load_model_spec(str(models / name)), 40)
    k = int(np.argmin(path[:, 0]))
    assert abs(printed - path[k, 0]) <= 4 * np.finfo(float).eps * path[k, 1]


@pytest.mark.parametrize("spec", [SINGLE_FOLD, "crease.fold"])
def test_a_rigid_crease_pattern_is_called_rigid(models, capsys, spec):
    path = spec if isinstance(spec, pathlib.Path) else models / spec
    assert load_model_spec(str(path), fold_dim=2).analyse().m_internal == 0
    for cmd in ("follow", "locate"):
        rc = cli.main([cmd, str(path), "--fold-dim", "2"])
        _, err = capsys.readouterr()
        assert rc == EXIT_USAGE
        assert "rigid" in err and "bifurcation" not in err


@pytest.mark.parametrize("case", ["braced", "threebar-RC-branch-0", "threebar-RC-branch-1", "square-sail-branch-0"])
def test_a_real_bifurcation_is_counted_as_the_detector_locates_it(models, capsys, case):
    """A path with s = 1 throughout (the test function has no sign there),
    the paper's three-bar linkage from R^C along P^1 to R^A, the square sail
    from its flat state to R^C: one bifurcation each on the followed range,
    where kin_follow_event locates it."""
    spec, k, steps = {"braced": (models / "braced.json", None, 40),
                      "threebar-RC-branch-0": ("threebar:RC", 0, 60),
                      "threebar-RC-branch-1": ("threebar:RC", 1, 60),
                      "square-sail-branch-0": (SQUARE_SAIL, 0, 60)}[case]
    extra = [] if k is None else ["--branch", k]
    rc, out, _ = follow(capsys, spec, "--steps", steps, *extra)
    assert rc == 0
    a = load_model_spec(str(spec))
    d = None if k is None else branch(a, k)
    path = followed(a, steps, d)
    expected = located_bifurcations(a, abs(path[-1, 2]), d)
    assert len(expected) == 1
    assert passed_count(out) == len(expected)
    # the API's record: the step that passed it brackets where the detector located it
    b = a.clone()
    if d is not None:
        b.set_direction(d)
    got = cli.follow_path(b, b.analyse(), steps, direction=d).passed
    assert len(got) == 1
    _, l0, l1 = got[0]
    step = abs(l1 - l0)
    assert min(abs(l0), abs(l1)) - 0.01 * step <= expected[0] <= max(abs(l0), abs(l1)) + 0.01 * step
