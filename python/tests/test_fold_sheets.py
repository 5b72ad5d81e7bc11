"""Crease patterns as real files give them (issue 21, items 1 and 2).

1. A FOLD file with faces is a sheet, read in 3D even with 2-number
   coordinates; crease patterns whose degrees of freedom are known by hand
   (python/tests/data/fold/make_cases.py) have them.
2. Coordinates rounded to 6 decimals: the square twist (an overconstrained
   mechanism, which rounding breaks) is followed from near flat to near
   flat-folded with default settings; commands that write fewer frames than
   asked say so in their exit status.
"""
import json
import pathlib

import numpy as np
import pytest

from libkin.cli import main as cli_main
from libkin.errors import ModelFormatError
from libkin.io import fold

DATA = pathlib.Path(__file__).resolve().parent / "data" / "fold"
EXAMPLES = pathlib.Path(__file__).resolve().parents[2] / "examples" / "fold"
CASES = ["single_fold", "degree4_vertex", "miura_cell", "square_twist"]
# first-order internal mechanisms of the flat sheet: one fold 1; a flat
# degree-n vertex n - 2 (its crease rotations need only sum to zero in the
# plane); the twist's four vertices 4
FLAT_M = {"single_fold": 1, "degree4_vertex": 2, "miura_cell": 2, "square_twist": 4}


def fold_angles(a, faces):
    """The fold angle (degrees, 0 = flat) of every crease: the angle between
    the normals of the two faces that share it."""
    x = a.coords
    normals = []
    for f in faces:
        p = x[f] - x[f].mean(axis=0)
        n = sum(np.cross(p[k], p[(k + 1) % len(f)]) for k in range(len(f)))
        normals.append(n / np.linalg.norm(n))
    out = []
    for i in range(len(faces)):
        for j in range(i + 1, len(faces)):
            if len(set(faces[i]) & set(faces[j])) == 2:
                out.append(np.degrees(np.arccos(np.clip(normals[i] @ normals[j], -1.0, 1.0))))
    return np.array(out)


@pytest.mark.parametrize("name", CASES)
def test_flat_crease_pattern_is_a_sheet_in_3d(name):
    doc = json.loads((DATA / f"{name}.fold").read_text())
    assert all(len(p) == 2 for p in doc["vertices_coords"])  # a flat pattern, as files give it
    a = fold.read_fold(DATA / f"{name}.fold")
    assert a.dim == 3 and np.all(a.coords[:len(doc["vertices_coords"]), 2] == 0.0)
    an = a.analyse()
    # no supports: the 6 rigid-body motions of space come on top
    assert (an.m_internal, an.m_rigid) == (FLAT_M[name], 6)


@pytest.mark.parametrize("name", CASES)
def test_folded_crease_pattern_has_the_degrees_of_freedom_known_by_hand(name):
    a = fold.read_fold(DATA / f"{name}.fold", frame=1)
    assert a.dim == 3 and fold_angles(a, a.fold.faces).max() > 5.0
    an = a.analyse()
    assert (an.m_internal, an.m_rigid) == (1, 6)
    # the twist: 12 creases - 3 x 4 vertices = 0 by count, folding all the
    # same: one self-stress; the others have none
    assert an.s == (1 if name == "square_twist" else 0)


def test_single_fold_moves_out_of_its_plane():
    a = fold.read_fold(DATA / "single_fold.fold")
    for _ in a.follow(steps=5):
        pass
    assert np.abs(a.coords[:, 2]).max() > 0.1 and a.max_strain < 1e-10


def test_dimension_rule_and_its_override():
    sq = json.loads((DATA / "single_fold.fold").read_text())
    flat = fold.read_fold(sq, dim=2)  # a planar reading asked for: rigid in its plane
    assert flat.dim == 2 and flat.analyse().m_internal == 0
    assert fold.read_fold(sq, faces="ignore").dim == 2  # faces ignored: edges only, planar
    assert fold.read_fold(EXAMPLES / "fourbar.fold").dim == 2  # bars only
    with pytest.raises(ModelFormatError):
        fold.read_fold(sq, frame=1, dim=2)  # the folded frame has z != 0
    with pytest.raises(ModelFormatError):
        fold.read_fold(sq, dim=4)
    # a flat pattern's per-coordinate supports [x, y] read in 3D leave z free
    sq["vertices_libkin:fixed"] = [True, [True, True], False, False]
    a = fold.read_fold(sq)
    assert a.fixed.tolist()[:2] == [[True] * 3, [True, True, False]]


def test_cli_fold_dim_flag(tmp_path):
    path = str(DATA / "single_fold.fold")
    out = tmp_path / "out.fold"
    assert cli_main(["fold-export", path, "--follow", "3", "--out", str(out), "--quiet"]) == 0
    doc = json.loads(out.read_text())
    assert len(doc["vertices_coords"][0]) == 3 and len(doc["file_frames"]) == 3
    assert max(abs(p[2]) for p in doc["file_frames"][-1]["vertices_coords"]) > 0.01  # folded out of the plane
    # read as a planar framework it cannot move: nothing to follow (a usage error)
    assert cli_main(["fold-export", path, "--fold-dim", "2", "--follow", "3", "--out", str(out), "--quiet"]) == 2


def test_resolution_detected_from_the_file():
    assert fold.detect_resolution([0.0, 1.0, 2.2, 1.6]) == 0.0  # typed by hand: exact
    assert fold.detect_resolution([0.1 + 0.2, 1.0]) == 0.0  # full precision: exact
    assert fold.detect_resolution([2.308595, 0.5, -1.0]) == pytest.approx(1e-6)
    a = fold.read_fold(DATA / "square_twist.fold", frame=1)
    assert a.options.coord_resolution == pytest.approx(1e-6)
    assert fold.read_fold(DATA / "square_twist.fold", frame=1, resolution=0).options.coord_resolution == 0.0
    assert fold.read_fold(EXAMPLES / "square_crease.fold") \
        .options.coord_resolution == 0.0


def _toward_folding(a, faces):
    """Orient the path toward more folding (the default orientation is the
    mechanism's largest entry, which may unfold)."""
    a.analyse()
    t = a.tangent()
    b = a.clone()
    x = b.coords
    fm = b.free_map()
    x[fm >= 0] += 1e-5 * t[fm[fm >= 0]]
    b.coords = x
    a.set_direction(t if fold_angles(b, faces).max() > fold_angles(a, faces).max() else -t)


def test_rounded_square_twist_folds_from_near_flat_to_near_flat_folded():
    # 6-decimal coordinates (rest lengths from them): the rounded twist has
    # no exactly strain-free motion; its strain floor grows past 1e-12 within
    # a few degrees. How folded: the largest crease fold angle.
    a = fold.read_fold(DATA / "square_twist.fold", frame=1)
    faces = a.fold.faces
    start = fold_angles(a, faces).max()
    assert start < 10.0
    _toward_folding(a, faces)
    infos = []
    for info in a.follow(steps=300):  # default options
        infos.append(info)
        if fold_angles(a, faces).max() > 170.0:
            break
    assert fold_angles(a, faces).max() > 170.0
    # the tolerance in effect is what 6 decimals allow, and stated
    floor = np.sqrt(3) * 1e-6 / a.rest_lengths.min()
    assert all(i.strain_floor == pytest.approx(floor) and i.tol_used == pytest.approx(floor) for i in infos)
    assert max(i.residual for i in infos) <= floor and a.max_strain <= floor


def test_exact_input_keeps_the_corrector_tolerance():
    a = fold.read_fold(EXAMPLES / "square_crease.fold")
    info = a.step()
    assert info.strain_floor == 0.0 and info.tol_used == a.options.corrector_tol
    assert info.residual <= 1e-12


def _folded_twist_file(tmp_path):
    """The twist's folded frame as a file of its own (what `libkin` reads)."""
    doc = fold.resolve_frame(json.loads((DATA / "square_twist.fold").read_text()), 1)
    path = tmp_path / "twist_folded.fold"
    path.write_text(json.dumps(doc))
    return str(path)


def test_resolution_on_the_command_line(tmp_path):
    from libkin.cli import EXIT_PARTIAL
    path = _folded_twist_file(tmp_path)
    out = tmp_path / "t.fold"
    # detected from the file's 6 decimals: followed
    assert cli_main(["fold-export", path, "--follow", "30", "--out", str(out), "--quiet"]) == 0
    assert len(json.loads(out.read_text())["file_frames"]) == 30
    # --resolution 0 (exact): held to 1e-12, the rounded twist stops within a few
    # degrees; fewer frames than asked, and the exit status says so
    assert cli_main(["fold-export", path, "--follow", "30", "--resolution", "0", "--out", str(out),
                     "--quiet"]) == EXIT_PARTIAL
    assert len(json.loads(out.read_text())["file_frames"]) < 30
    assert cli_main(["follow", path, "--steps", "30", "--quiet", "--resolution", "0"]) == EXIT_PARTIAL
    assert cli_main(["follow", path, "--steps", "30", "--quiet"]) == 0


def _stop_after(monkeypatch, k):
    """Make every path stop (NotConvergedError) after k steps."""
    from libkin.assembly._path import PathMixin
    from libkin.errors import NotConvergedError
    real = PathMixin.step
    calls = {"n": 0}

    def step(self, delta=0.0):
        calls["n"] += 1
        if calls["n"] > k:
            raise NotConvergedError("step: stopped for the test", 0)
        return real(self, delta)

    monkeypatch.setattr(PathMixin, "step", step)


def test_fold_export_that_writes_fewer_frames_than_asked_fails(tmp_path, monkeypatch):
    _stop_after(monkeypatch, 3)
    out = tmp_path / "partial.fold"
    rc = cli_main(["fold-export", str(EXAMPLES / "square_crease.fold"), "--follow", "10", "--out", str(out), "--quiet"])
    assert rc != 0
    assert len(json.loads(out.read_text())["file_frames"]) == 3  # what was reached is written


def test_follow_that_stops_early_fails(tmp_path, monkeypatch):
    _stop_after(monkeypatch, 2)
    rc = cli_main(["follow", str(EXAMPLES / "square_crease.fold"), "--steps", "10", "--quiet"])
    assert rc != 0
