"""FOLD import and export (libkin.io.fold): round trips, frames of a followed
path, supports, faces made rigid, and malformed files refused."""
import json
import pathlib

import numpy as np
import pytest

from libkin import Assembly
from libkin.io import fold
from libkin.cli import main as cli_main
from libkin.errors import ModelFormatError

EXAMPLES = pathlib.Path(__file__).resolve().parents[2] / "examples" / "fold"
# coordinates go through JSON as shortest round-trip decimal strings: exact
EXACT = 0.0


def _doc(name):
    return json.loads((EXAMPLES / name).read_text())


@pytest.mark.parametrize("name", ["fourbar.fold", "square_crease.fold"])
def test_round_trip_keeps_vertices_edges_faces_supports(name, tmp_path):
    src = _doc(name)
    a = fold.read_fold(EXAMPLES / name)
    out = tmp_path / "back.fold"
    back = fold.write_fold(out, a)
    assert json.loads(out.read_text()) == back
    assert np.abs(np.array(back["vertices_coords"]) - np.array(src["vertices_coords"])).max() <= EXACT
    assert back["edges_vertices"] == src["edges_vertices"]
    assert back["edges_assignment"] == src["edges_assignment"]
    assert back.get("faces_vertices") == src.get("faces_vertices")
    assert back["vertices_libkin:fixed"] == src["vertices_libkin:fixed"]
    assert fold.check_fold(back) == []
    # and in again: the same assembly
    b = fold.read_fold(out)
    assert b.njoints == a.njoints and b.nbars == a.nbars
    assert np.array_equal(b.bars, a.bars) and np.array_equal(b.fixed, a.fixed)
    assert np.abs(b.rest_lengths - a.rest_lengths).max() <= EXACT


def test_fourbar_is_a_one_degree_of_freedom_linkage():
    a = fold.read_fold(EXAMPLES / "fourbar.fold")
    assert (a.dim, a.njoints, a.nbars, a.nfree) == (2, 4, 3, 4)
    an = a.analyse()
    assert (an.m_internal, an.m_rigid, an.s) == (1, 0, 0)


def test_exported_path_has_one_frame_per_configuration(tmp_path):
    a = fold.read_fold(EXAMPLES / "square_crease.fold")
    frames = [a.coords]
    for _ in a.follow(steps=12):
        frames.append(a.coords)
    out = tmp_path / "path.fold"
    doc = fold.write_fold(out, a, path_coords=frames)
    assert 1 + len(doc["file_frames"]) == len(frames) == 13
    assert doc["file_classes"] == ["animation"]
    assert fold.check_fold(doc) == []
    for i, c in enumerate(frames):
        fr = fold.resolve_frame(doc, i)
        # every frame has the whole mesh (inherited) and its own coordinates
        assert fr["edges_vertices"] == doc["edges_vertices"] and fr["faces_vertices"] == doc["faces_vertices"]
        assert np.abs(np.array(fr["vertices_coords"]) - c).max() <= EXACT
    for f in doc["file_frames"]:
        assert f["frame_parent"] == 0 and f["frame_inherit"] is True and set(f) >= {"vertices_coords"}
    # the panel turned about the crease v0-v2 without stretching any edge
    last = fold.read_fold(out, frame=len(frames) - 1)
    assert last.coords[3, 2] > 0.1
    L = np.linalg.norm(last.coords[last.bars[:, 0]] - last.coords[last.bars[:, 1]], axis=1)
    assert np.abs(L - a.rest_lengths).max() < 1e-10


def test_supports_from_argument_override_the_file():
    a = fold.read_fold(EXAMPLES / "fourbar.fold", fixed=[0, 1, 3])
    assert a.fixed.all(axis=1).tolist() == [True, True, False, True]
    b = fold.read_fold(EXAMPLES / "fourbar.fold", fixed=np.array([[True, True], [False] * 2, [False] * 2,
                                                                   [False, True]]))
    assert b.nfree == 5
    with pytest.raises(ModelFormatError):
        fold.read_fold(EXAMPLES / "fourbar.fold", fixed=[7])


def test_quad_panel_is_rigid_with_an_apex_and_folds_when_only_triangulated():
    sq = {"vertices_coords": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], "faces_vertices": [[0, 1, 2, 3]]}
    rigid = fold.read_fold(sq, fixed=[0, 1], faces="rigid")
    assert rigid.njoints == 5 and rigid.labels[4] == "apex0"
    assert rigid.analyse().m_internal == 0  # only the rigid turn about v0-v1 is left
    tri = fold.read_fold(sq, fixed=[0, 1], faces="triangulate")
    assert tri.njoints == 4 and tri.analyse().m_internal == 1  # folds along the diagonal v0-v2
    with pytest.raises(ModelFormatError):  # no edges, and the face ignored: no bars
        fold.read_fold(sq, fixed=[0, 1], faces="ignore")
    # written back: the file's 4 vertices, the face, and its 4 sides as edges
    doc = fold.write_fold(None, rigid)
    assert len(doc["vertices_coords"]) == 4 and doc["faces_vertices"] == [[0, 1, 2, 3]]


def test_frame_inheritance_and_selection():
    doc = _doc("fourbar.fold")
    doc["file_frames"] = [{"frame_parent": 0, "frame_inherit": True,
                           "vertices_coords": [[0, 0], [1, 0], [3.0, 0.8], [2, 0]]}]
    a = fold.read_fold(doc, frame=1)
    assert a.coords[2].tolist() == [3.0, 0.8] and a.nbars == 3
    with pytest.raises(ModelFormatError):
        fold.read_fold(doc, frame=2)


@pytest.mark.parametrize("bad", [
    {},
    {"vertices_coords": [[0, 0], [1, 0]]},
    {"vertices_coords": [[0, 0], [1, 0]], "edges_vertices": [[0, 2]]},
    {"vertices_coords": [[0, 0], [1, 0]], "edges_vertices": [[0, 0]]},
    {"vertices_coords": [[0, 0], ["a", 0]], "edges_vertices": [[0, 1]]},
    {"vertices_coords": [[0, 0], [1, 0]], "edges_vertices": [[0, 1]], "vertices_libkin:fixed": [True]},
    {"vertices_coords": [[0, 0], [1, 0]], "edges_vertices": [[0, 1]], "edges_assignment": ["B", "B"]},
    {"vertices_coords": [[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0]], "faces_vertices": [[0, 1, 2, 3]]},
    {"vertices_coords": [[0, 0]], "file_frames": [{"frame_inherit": True, "frame_parent": 1}]},
])
def test_malformed_files_are_refused(bad):
    frame = 1 if "file_frames" in bad else 0
    with pytest.raises(ModelFormatError):
        fold.read_fold(bad, frame=frame)


def test_unparsable_text_is_refused():
    with pytest.raises(ModelFormatError):
        fold.read_fold('{"vertices_coords": [')


def test_sail_exports_with_triangle_faces(tmp_path):
    a = Assembly.sail(4, 1)
    doc = fold.write_fold(None, a, faces="triangles")
    assert len(doc["vertices_coords"]) == 8 and len(doc["edges_vertices"]) == 16
    # two triangles per quadrilateral V_k O_k O_{k+1} V_{k+1} (split by its
    # diagonal); the square hub has no diagonal, so it is a hole in the mesh:
    # hub edges and ring edges O_k-O_{k+1} are on one face (border), folds
    # and diagonals on two
    assert len(doc["faces_vertices"]) == 8
    assert doc["edges_assignment"].count("B") == 8 and doc["edges_assignment"].count("U") == 8
    assert fold.check_fold(doc) == []


def test_cli_fold_export(tmp_path):
    out = tmp_path / "fourbar_path.fold"
    rc = cli_main(["fold-export", str(EXAMPLES / "fourbar.fold"), "--follow", "20", "--out", str(out), "--quiet"])
    assert rc == 0
    doc = json.loads(out.read_text())
    assert len(doc["file_frames"]) == 20 and fold.check_fold(doc) == []
