"""FOLD files out: write_fold() writes an assembly, or a path followed from
it, as a FOLD file; check_fold() checks a document against the spec's
structural rules; graph_triangles() gives faces to models that have none.
(What is written, frame by frame, is described in reader.py's docstring.)
"""
from __future__ import annotations

import json
import os
from typing import Any, Dict, List, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

from ..._bounded import MAX_BYTES
from ...assembly import Assembly
from ...atomic import write_text
from ...errors import GeometryError, KinError, LimitError, ModelFormatError
from .reader import FIXED_KEY, FOLD_SPEC, FoldAssembly, FoldDoc, FoldSource, read_fold, resolve_frame

# the largest |coordinate| an Assembly takes (the C library's COORD_MAX)
_COORD_MAX = 1e150


def graph_triangles(bars: Any) -> List[List[int]]:
    """The triangles of a bar graph (three joints pairwise barred).

    Parameters
    ----------
    bars : (nbars, 2) int array
        Joint indices of each bar.

    Returns
    -------
    list of [i, j, k], i < j < k, sorted
        Faces for models that have none (the sails' panels are bar triangles).
    """
    adj: Dict[int, set[int]] = {}
    for p, q in np.asarray(bars).tolist():
        adj.setdefault(p, set()).add(q)
        adj.setdefault(q, set()).add(p)
    out = []
    for p in sorted(adj):
        for q in sorted(adj[p]):
            if q <= p:
                continue
            for r in sorted(adj[p] & adj[q]):
                if r > q:
                    out.append([p, q, r])
    return out


def _orient_ccw(tris: List[List[int]], x: npt.NDArray[np.float64]) -> List[List[int]]:
    """Faces counter-clockwise seen from +z (the spec's orientation for a
    flat pattern); a face lying in a vertical plane is left as it is."""
    out = []
    for t in tris:
        p = x[t]
        if p.shape[1] == 2:
            p = np.hstack([p, np.zeros((len(t), 1))])
        n = np.cross(p[1] - p[0], p[2] - p[0])
        out.append(list(t) if n[2] >= 0 else [t[0], t[2], t[1]])
    return out


def write_fold(path: Union[None, str, "os.PathLike[str]"], assembly: Assembly,
               path_coords: Optional[Sequence[Any]] = None, faces: Any = None, title: Optional[str] = None,
               description: Optional[str] = None) -> FoldDoc:
    """Write an assembly, or a path followed from it, as a FOLD file.

    Parameters
    ----------
    path : path or None
        Where to write; None = only return the dict.
    assembly : Assembly
        The model (a FoldAssembly writes back its file's vertices, edges,
        assignment and faces; apexes and added diagonals are dropped).
    path_coords : sequence of (njoints, dim) arrays, optional
        A followed path: frame 0 (top level) is the first configuration, each
        further one a frame in file_frames inheriting the mesh. Without it,
        the single frame is the assembly's current configuration.
    faces : None, "triangles" or a list of vertex lists
        None = the faces read from a FOLD file (if any), else the
        assembly's panels; "triangles" = the bar graph's triangles. Every
        side of a face written is an edge: a side that is no bar (a panel
        side, a face read with faces="ignore") is added after the bars, its
        length that in the first configuration.
    title, description : str, optional
        file_title and file_description.

    Returns
    -------
    dict
        The FOLD document (supports in "vertices_libkin:fixed", rest lengths
        in edges_length).

    Raises
    ------
    GeometryError
        A configuration holds a non-finite coordinate or one beyond 1e150,
        or a face has a side that is no bar and has zero length.
    LimitError
        The text would be larger than read_fold reads by default (64 MiB).
    ModelFormatError (or the class read_fold raises)
        read_fold would reject the document (e.g. a face out of range or
        degenerate). Nothing is written or returned then: every document
        write_fold returns or writes reads back with read_fold (its key
        frame is read back first).
    """
    src: Optional[FoldSource] = getattr(assembly, "fold", None)
    nv = src.n_vertices if src is not None else assembly.njoints
    # the file's edges and the face sides it gave no edge for; never the
    # fan diagonals and apex bars added after them (an apex is no vertex)
    ne = src.n_edges + getattr(src, "n_sides", 0) if src is not None else assembly.nbars
    bars = assembly.bars[:ne]
    dim = assembly.dim
    if path_coords is None:
        configs = [assembly.coords]
    else:
        configs = [np.asarray(c, dtype=float) for c in path_coords]
        if not configs:
            raise ValueError("path_coords: expected at least one configuration")
        for i, c in enumerate(configs):
            if c.shape != (assembly.njoints, dim):
                raise ValueError(f"path_coords[{i}]: expected shape {(assembly.njoints, dim)}, got {c.shape}")
    for i, c in enumerate(configs):
        bad = ~np.isfinite(c) | (np.abs(np.nan_to_num(c, nan=0.0)) > _COORD_MAX)
        if bad.any():
            j, k = map(int, np.argwhere(bad)[0])
            raise GeometryError(f"write_fold: configuration {i}, joint {j}, coordinate {k} is {c[j, k]!r}: "
                                f"not finite or beyond {_COORD_MAX:g}; not written")
    face_list: Optional[List[List[int]]]
    if faces is None and src is not None:
        face_list = src.faces
    elif faces is None and assembly.npanels:
        face_list = [f for f in assembly.panels if max(f) < nv]
    elif isinstance(faces, str):
        if faces != "triangles":
            raise ValueError(f"faces: expected None, 'triangles' or a list, got {faces!r}")
        face_list = _orient_ccw([t for t in graph_triangles(bars) if max(t) < nv], configs[0][:nv])
    else:
        face_list = [list(map(int, f)) for f in faces] if faces is not None else None

    for i, f in enumerate(face_list or []):
        # a face read_fold would refuse is refused here, returned or written
        if len(f) < 3 or not all(0 <= v < nv for v in f):
            raise ModelFormatError(f"write_fold: faces[{i}] = {f}: expected 3 or more vertex indices in "
                                   f"0..{nv - 1}; not written")

    def coords_of(c: npt.NDArray[np.float64]) -> List[List[float]]:
        return [[float(v) for v in row] for row in c[:nv]]

    fixed = assembly.fixed[:nv]
    doc: FoldDoc = {"file_spec": FOLD_SPEC, "file_creator": "libkin", "file_classes": ["singleModel"]}
    if title or (src is None and assembly.name):
        doc["file_title"] = title or assembly.name
    if description:
        doc["file_description"] = description
    frame_classes = ["foldedForm"] if face_list else ["linkage"]
    doc["frame_classes"] = frame_classes
    doc["frame_attributes"] = ["3D" if dim == 3 else "2D"]
    doc["vertices_coords"] = coords_of(configs[0])
    edges = [(int(p), int(q)) for p, q in bars]
    lengths = [float(v) for v in assembly.rest_lengths[:ne]]
    have = {frozenset(e) for e in edges}
    count: Dict[frozenset[int], int] = {}
    for f in face_list or []:
        for k in range(len(f)):
            p, q = f[k], f[(k + 1) % len(f)]
            e = frozenset((p, q))
            count[e] = count.get(e, 0) + 1
            if p != q and e not in have:
                # a face's side is an edge of the file (the spec's faces lie
                # between edges; read_fold makes it a bar anyway): a panel
                # side that is no bar, or a face read with faces="ignore",
                # gets one at its length in the first frame
                side = float(np.linalg.norm(configs[0][p] - configs[0][q]))
                if not side > 0.0:
                    raise GeometryError(f"write_fold: face {f}: its side {p}-{q} has no length (the joints "
                                        "coincide) and is no bar to take a rest length from; not written")
                have.add(e)
                edges.append((p, q))
                lengths.append(side)
    doc["edges_vertices"] = [[p, q] for p, q in edges]
    # an edge on one face is border, else a fold whose sense the geometry
    # does not fix here: unassigned (the file's own letters kept)
    letters = ["B" if count.get(frozenset(e), 0) == 1 else "U" for e in edges]
    if src is not None and src.assignment is not None:
        doc["edges_assignment"] = list(src.assignment) + letters[len(src.assignment):]
    elif face_list:
        doc["edges_assignment"] = letters
    doc["edges_length"] = lengths
    if face_list:
        doc["faces_vertices"] = [list(map(int, f)) for f in face_list]
    if fixed.any():
        doc[FIXED_KEY] = [bool(r[0]) if r.all() or not r.any() else [bool(b) for b in r] for r in fixed]
    if len(configs) > 1:
        doc["file_classes"] = ["animation"]
        doc["file_frames"] = [{"frame_parent": 0, "frame_inherit": True, "frame_classes": frame_classes,
                               "vertices_coords": coords_of(c)} for c in configs[1:]]
    # returned or written, the document is one read_fold reads: its key
    # frame is read back (a face whose vertices coincide, say, is refused)
    _check_reads_back(doc)
    if path is not None:  # whole or not at all: the file saved before stays on a failure
        text = json.dumps(doc, separators=(",", ":"), allow_nan=False) + "\n"
        size = len(text.encode("utf-8"))
        if size > MAX_BYTES:
            raise LimitError(f"write_fold: {size} bytes, more than read_fold reads by default ({MAX_BYTES}); "
                             "not written")
        write_text(path, text)
    return doc


def _check_reads_back(doc: FoldDoc) -> None:
    """Raise what read_fold would raise on `doc`'s key frame."""
    try:
        read_fold(doc)
    except KinError as exc:
        raise type(exc)(f"write_fold: read_fold would reject the file ({exc}); not written", exc.code) from None


def check_fold(doc: FoldDoc) -> List[str]:
    """The spec's structural rules that a viewer relies on.

    Parameters
    ----------
    doc : dict
        A FOLD document.

    Returns
    -------
    list of str
        The problems found (empty = none): vertices_coords present; every
        index in range; per-edge and per-vertex arrays as long as the lists
        they describe; file_* keys only at the top level; frame_parent in
        range; standard assignment letters; custom keys namespaced by a colon.
    """
    probs = []
    std = {"file_spec", "file_creator", "file_author", "file_title", "file_description", "file_classes",
           "file_frames", "frame_author", "frame_title", "frame_description", "frame_classes", "frame_attributes",
           "frame_unit", "frame_parent", "frame_inherit", "vertices_coords", "vertices_vertices", "vertices_edges",
           "vertices_faces", "edges_vertices", "edges_faces", "edges_assignment", "edges_foldAngle",
           "edges_length", "faces_vertices", "faces_edges", "faces_faces", "faceOrders", "edgeOrders"}
    for k in doc:
        if k not in std and ":" not in k:
            probs.append(f"non-standard key without a namespace: {k}")
    frames = doc.get("file_frames", [])
    for i in range(len(frames) + 1):
        where = "key frame" if i == 0 else f"file_frames[{i - 1}]"
        if i > 0:
            raw = frames[i - 1]
            if any(k.startswith("file_") for k in raw):
                probs.append(f"{where}: file_ keys inside a frame")
            par = raw.get("frame_parent")
            if par is not None and not 0 <= par < len(frames) + 1:
                probs.append(f"{where}: frame_parent {par} out of range")
        try:
            fr = resolve_frame(doc, i)
        except ModelFormatError as exc:
            probs.append(f"{where}: {exc}")
            continue
        vc = fr.get("vertices_coords")
        if not isinstance(vc, list) or not vc:
            probs.append(f"{where}: no vertices_coords")
            continue
        nv = len(vc)
        for key in ("edges_vertices", "faces_vertices"):
            for e in fr.get(key, []):
                if not all(isinstance(j, int) and 0 <= j < nv for j in e):
                    probs.append(f"{where}: {key} has an index out of range")
                    break
        ne = len(fr.get("edges_vertices", []))
        for key in ("edges_assignment", "edges_foldAngle", "edges_length"):
            if key in fr and len(fr[key]) != ne:
                probs.append(f"{where}: {key} has {len(fr[key])} entries for {ne} edges")
        for a in fr.get("edges_assignment", []):
            if a not in ("B", "M", "V", "F", "U", "C", "J"):
                probs.append(f"{where}: edges_assignment letter {a!r}")
                break
        if FIXED_KEY in fr and len(fr[FIXED_KEY]) != nv:
            probs.append(f"{where}: {FIXED_KEY} has {len(fr[FIXED_KEY])} entries for {nv} vertices")
    return probs
