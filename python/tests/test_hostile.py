"""Hostile input through the Python wrapper and the command line: each case
raises the KinError subclass of its C status (checked by class and .code),
leaves the assembly as it was, and on the command line gives a non-zero exit
status with a one-line message, no traceback."""
import json
import subprocess
import sys

import numpy as np
import pytest

import libkin
from libkin import errors, lib
from libkin.assembly import solve_quadrics


TRIANGLE = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]
TRI_BARS = [[0, 1], [1, 2], [2, 0]]


@pytest.mark.parametrize("coords", [
    [[-1e308, 0.0], [1e308, 0.0]],   # finite coordinates, infinite length
    [[0.0, 0.0], [1e200, 0.0]],      # finite length, its square overflows
    [[0.0, 0.0], [1e-200, 0.0]],     # its square underflows
])
def test_overflowing_geometry(coords):
    with pytest.raises(errors.GeometryError) as e:
        libkin.Assembly(coords, [[0, 1]])
    assert e.value.code == lib.KIN_EGEOM


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), 1e300, 1e-300, -1.0])
def test_bad_rest_lengths(bad):
    with pytest.raises(errors.GeometryError) as e:
        libkin.Assembly(TRIANGLE, TRI_BARS, lengths=[1.0, bad, 1.0])
    assert e.value.code == lib.KIN_EGEOM


def test_large_but_valid_scale():
    """The bounds leave room: a bar across the allowed box (3.5e150 long)."""
    a = libkin.Assembly([[-1e150] * 3, [1e150] * 3], [[0, 1]])
    assert a.clone().analyse().rank == 1


@pytest.mark.parametrize("value", [1e308, float("nan"), float("inf")])
def test_set_coords_refused_and_unchanged(value):
    a = libkin.Assembly.threebar("RC")
    before = a.coords
    xyz = before.copy()
    xyz[0, 0] = value
    with pytest.raises(errors.GeometryError) as e:
        a.coords = xyz
    assert e.value.code == lib.KIN_EGEOM
    assert np.array_equal(a.coords, before)


@pytest.mark.parametrize("solver", ["scan", "homotopy"])
@pytest.mark.parametrize("bad", [float("nan"), float("inf")])
def test_non_finite_q(solver, bad):
    Q = np.array([[[1.0, 0.0], [0.0, -1.0]]])
    Q[0, 0, 1] = bad
    with pytest.raises(errors.InvalidArgumentError) as e:
        solve_quadrics(Q, solver=solver)
    assert e.value.code == lib.KIN_EINVAL


@pytest.fixture
def bifurcation():
    a = libkin.Assembly.threebar("RB")
    betas, _ = solve_quadrics(a.second_order(), solver="scan", starts=32)
    assert len(betas) == 2
    return a, betas


@pytest.mark.parametrize("length", [float("inf"), float("nan"), -1.0])
def test_bad_branch_length(bifurcation, length):
    a, betas = bifurcation
    before = a.coords
    with pytest.raises(errors.InvalidArgumentError) as e:
        a.follow_branches(betas, length=length)
    assert e.value.code == lib.KIN_EINVAL
    assert np.array_equal(a.coords, before)


def test_absurd_branch_length(bifurcation):
    a, betas = bifurcation
    with pytest.raises(errors.RangeError) as e:
        a.follow_branches(betas, length=1e300)
    assert e.value.code == lib.KIN_ERANGE


def test_non_finite_betas(bifurcation):
    a, betas = bifurcation
    betas = betas.copy()
    betas[0, 1] = np.nan
    with pytest.raises(errors.InvalidArgumentError) as e:
        a.follow_branches(betas, length=0.5)
    assert e.value.code == lib.KIN_EINVAL


@pytest.mark.parametrize("kw", [{"side": 1e300}, {"widths": [1e308, 1e308]}, {"side": float("nan")}])
def test_sail_parameters(kw):
    with pytest.raises(errors.InvalidArgumentError) as e:
        libkin.Assembly.sail(6, 2, **kw)
    assert e.value.code == lib.KIN_EINVAL


def run_cli(*args):
    return subprocess.run([sys.executable, "-m", "libkin", *args], capture_output=True, text=True, timeout=120)


@pytest.mark.parametrize("doc", [
    {"dimension": 2, "joints": [{"xyz": [-1e308, 0]}, {"xyz": [1e308, 0]}], "bars": [{"joints": [0, 1]}]},
    {"dimension": 2, "joints": [{"xyz": [0, 0]}, {"xyz": [1e-200, 0]}], "bars": [{"joints": [0, 1]}]},
    {"dimension": 2, "joints": [{"xyz": [0, 0]}, {"xyz": [1, 0]}], "bars": [{"joints": [0, 1], "length": 1e300}]},
    {"dimension": 2, "joints": [{"xyz": [float("nan"), 0]}, {"xyz": [1, 0]}], "bars": [{"joints": [0, 1]}]},
])
def test_cli_hostile_model(tmp_path, doc):
    path = tmp_path / "hostile.json"
    path.write_text(json.dumps(doc))
    r = run_cli("analyse", str(path))
    assert r.returncode != 0
    assert "Traceback" not in r.stderr and r.stderr.strip()


@pytest.mark.parametrize("args", [
    ("analyse", "sail:3:1"),                                         # odd hub
    ("analyse", "sail:6:100"),                                       # too many loops
    ("follow", "threebar:RC", "--perturb", "1e308", "--quiet"),      # coordinates past the bound
])
def test_cli_hostile_arguments(args):
    r = run_cli(*args)
    assert r.returncode != 0
    assert "Traceback" not in r.stderr and r.stderr.strip()


@pytest.mark.parametrize("args", [
    ("follow", "sail:6:2", "--perturb", "0.5", "--delta", "inf"),
    ("follow", "sail:6:2", "--perturb", "0.5", "--delta", "nan"),
    ("follow", "threebar:RC", "--steps", "-1"),
    ("locate", "threebar:RA", "--vr-tol", "0"),
    ("analyse", "sail:6:x"),
    ("no-such-command",),
])
def test_cli_usage_errors_are_one_line(args):
    """Bad options are usage errors (exit 2), one line on stderr, nothing done."""
    r = run_cli(*args)
    assert r.returncode == 2 or (args[1] == "sail:6:x" and r.returncode == 1)
    assert "Traceback" not in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1
    assert r.stdout == ""
