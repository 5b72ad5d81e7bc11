"""write_fold on models given as faces only (issue 39 item 7): FOLD files
with faces_vertices and no edges_vertices, read in every faces mode, and
assemblies whose panels are not all barred. Every document write_fold
returns is checked by `_fold_problems`, written here from the FOLD spec
(github.com/edemaine/fold, doc/spec.md) and sharing no code with the writer
or with check_fold: indices in range, one entry per edge in every edges_*
array, every face side an edge, a border letter exactly on the edges of one
face; and it must read back to the same bars among the file's vertices.
write_fold may refuse (a libkin error), never return what fails these."""
import math
import os

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from libkin import Assembly
from libkin.errors import KinError
from libkin.io import fold

EXAMPLES_N = int(os.environ.get("LIBKIN_FUZZ_EXAMPLES", "150"))
LETTERS = set("BMVFUCJ")


def _fold_problems(doc):
    """What makes `doc` an invalid or self-inconsistent FOLD key frame."""
    probs = []
    vc = doc.get("vertices_coords")
    if not isinstance(vc, list) or not vc:
        return ["no vertices_coords"]
    for p in vc:
        if not (isinstance(p, list) and len(p) in (2, 3) and all(isinstance(v, float) and math.isfinite(v)
                                                                 for v in p)):
            probs.append(f"vertex {p!r}")
    nv = len(vc)
    edges = doc.get("edges_vertices", [])
    seen = set()
    for e in edges:
        if not (isinstance(e, list) and len(e) == 2 and all(isinstance(j, int) and 0 <= j < nv for j in e)):
            probs.append(f"edge {e!r} not two vertex indices in 0..{nv - 1}")
            continue
        if e[0] == e[1] or frozenset(e) in seen:
            probs.append(f"edge {e!r} a loop or a duplicate")
        seen.add(frozenset(e))
    for key in ("edges_assignment", "edges_length", "edges_foldAngle"):
        if key in doc and len(doc[key]) != len(edges):
            probs.append(f"{key}: {len(doc[key])} entries for {len(edges)} edges")
    if any(a not in LETTERS for a in doc.get("edges_assignment", [])):
        probs.append("an assignment letter outside the spec's")
    if any(not (isinstance(v, float) and math.isfinite(v) and v > 0) for v in doc.get("edges_length", [])):
        probs.append("an edge length not positive and finite")
    on_faces = {}
    for f in doc.get("faces_vertices", []):
        if not (isinstance(f, list) and len(f) >= 3 and all(isinstance(j, int) and 0 <= j < nv for j in f)):
            probs.append(f"face {f!r} not 3 or more vertex indices in 0..{nv - 1}")
            continue
        for k in range(len(f)):
            side = frozenset((f[k], f[(k + 1) % len(f)]))
            if len(side) == 2:
                on_faces[side] = on_faces.get(side, 0) + 1
                if side not in seen:
                    probs.append(f"face {f!r}: side {sorted(side)} is no edge")
    if "edges_assignment" in doc and len(doc["edges_assignment"]) == len(edges):
        for e, a in zip(edges, doc["edges_assignment"]):
            if (a == "B") != (on_faces.get(frozenset(e), 0) == 1) and on_faces:
                probs.append(f"edge {e}: letter {a} on {on_faces.get(frozenset(e), 0)} faces")
    fixed = doc.get("vertices_libkin:fixed")
    if fixed is not None and len(fixed) != nv:
        probs.append("vertices_libkin:fixed not one entry per vertex")
    return probs


def _check_written(doc, bars_expected):
    probs = _fold_problems(doc)
    assert probs == [], probs
    # what write_fold returns reads back, its edges the model's bars among
    # the vertices and the faces' sides (no diagonal, no apex) ...
    edges_only = fold.read_fold(doc, faces="ignore")
    assert {frozenset(map(int, b)) for b in edges_only.bars} == bars_expected
    fold.read_fold(doc)  # ... and with its faces made rigid


coord = st.integers(-3, 3).map(float)


@st.composite
def faces_only_docs(draw):
    nv = draw(st.integers(3, 8))
    d = draw(st.sampled_from([2, 3]))
    vc = [[draw(coord) for _ in range(d)] for _ in range(nv)]
    face = st.lists(st.integers(0, nv - 1), min_size=3, max_size=min(6, nv + 1))
    doc = {"file_spec": 1.1, "vertices_coords": vc, "faces_vertices": draw(st.lists(face, min_size=1, max_size=4))}
    if draw(st.booleans()):
        doc["vertices_libkin:fixed"] = [draw(st.booleans()) for _ in range(nv)]
    return doc


@settings(max_examples=EXAMPLES_N, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(doc=faces_only_docs(), mode=st.sampled_from(["rigid", "triangulate", "ignore"]),
       write_faces=st.sampled_from([None, "triangles"]))
def test_faces_only_files_write_valid_fold(doc, mode, write_faces):
    try:
        a = fold.read_fold(doc, faces=mode)
    except KinError:
        return  # a file read_fold refuses (collinear face, a face of < 3 vertices, ...) has nothing to write
    try:
        out = fold.write_fold(None, a, faces=write_faces)
    except KinError:
        return  # refused with libkin's class (read_fold would refuse it), never an invalid document
    # the file's edges are its faces' sides (no fan diagonal, no apex)
    written = set()
    for f in doc["faces_vertices"] + out.get("faces_vertices", []):
        written |= {frozenset((f[k], f[(k + 1) % len(f)])) for k in range(len(f)) if f[k] != f[(k + 1) % len(f)]}
    _check_written(out, written)


@st.composite
def panelled_assemblies(draw):
    nv = draw(st.integers(3, 7))
    d = draw(st.sampled_from([2, 3]))
    x = np.array([[draw(coord) for _ in range(d)] for _ in range(nv)])
    pairs = [(i, j) for i in range(nv) for j in range(i + 1, nv)]
    bars = draw(st.lists(st.sampled_from(pairs), min_size=1, max_size=len(pairs), unique=True))
    panels = draw(st.lists(st.lists(st.integers(0, nv - 1), min_size=3, max_size=min(5, nv), unique=True),
                           min_size=1, max_size=3))
    return x, bars, panels


@settings(max_examples=EXAMPLES_N, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(model=panelled_assemblies(), write_faces=st.sampled_from([None, "triangles"]))
def test_assemblies_with_panels_write_valid_fold(model, write_faces):
    x, bars, panels = model
    try:
        a = Assembly(x, np.array(bars), fixed=np.zeros(x.shape, bool))
        a.panels = panels
        out = fold.write_fold(None, a, faces=write_faces)
    except KinError:
        return
    written = {frozenset(b) for b in bars}
    for f in out.get("faces_vertices", []):
        written |= {frozenset((f[k], f[(k + 1) % len(f)])) for k in range(len(f))}
    _check_written(out, written)


def test_quad_given_as_a_face_only_writes_its_sides_and_no_apex(tmp_path):
    # the smallest case of the 57 of 4,000: one quad, no edges, read rigid in
    # 3D (an apex joint and its bars), written back
    doc = {"vertices_coords": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], "faces_vertices": [[0, 1, 2, 3]]}
    a = fold.read_fold(doc)
    assert a.njoints == 5  # the apex
    out = fold.write_fold(tmp_path / "quad.fold", a)
    assert sorted(map(sorted, out["edges_vertices"])) == [[0, 1], [0, 3], [1, 2], [2, 3]]
    assert out["edges_assignment"] == ["B"] * 4
    assert _fold_problems(out) == []
    b = fold.read_fold(tmp_path / "quad.fold")
    assert np.array_equal(b.bars, a.bars)
