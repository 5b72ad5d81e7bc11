"""FOLD files in and out (https://github.com/edemaine/fold, doc/spec.md).

read_fold() turns a FOLD frame into an Assembly: every vertex a joint, every
edge a bar. FOLD faces are panels; bars alone do not keep a panel rigid, so
faces are handled by `faces=`:
  "rigid" (default)  triangles as they are; a face of k >= 4 vertices gets
                     the diagonals of a fan triangulation from its first vertex
                     as bars and, in 3D, one extra joint (an apex off the face,
                     at the mean edge length from its centroid) barred to each
                     of its vertices: every fan triangle and the apex make a
                     tetrahedron, and tetrahedra glued on triangles are rigid,
                     planar face or not. (Bars among a planar face's own
                     vertices cannot be: every out-of-plane velocity of a flat
                     framework is orthogonal to all its bars.)
  "triangulate"      only the fan diagonals: each face becomes triangles that
                     may fold along the diagonals (like Origami Simulator's
                     facet creases, without their stiffness)
  "ignore"           faces add nothing; edges only (a linkage)
In 2D the fan diagonals alone make a face rigid, so no apex is added.

Dimension (`dim=`): a frame with faces (not ignored) is a sheet and is
read in 3D even when its coordinates have 2 numbers (the spec allows them
for a flat crease pattern; z = 0 is added): a sheet folds out of its
plane. A frame of edges only keeps the dimension of its coordinates (2
numbers: a planar linkage). dim=2 or 3 overrides both.

Rounding (`resolution=`): files carry rounded coordinates (6 decimals,
say); rest lengths taken from them are off by that much, and an
overconstrained sheet (most rigid origami: a self-stress along its motion)
then has no exactly strain-free motion, only one whose strain stays below
that bound. The resolution, from the file's decimals unless given, becomes
the assembly's `Options.coord_resolution`, so following the path asks for
no less strain than the input allows (kin_path.h, STRAIN FLOOR).

Supports: FOLD has no standard field for them. A libkin-namespaced vertex
property (the spec's custom-property rule: a colon in the key) gives them,
in the frame read or inherited: "vertices_libkin:fixed", per vertex either
true/false (every coordinate) or a list of booleans per coordinate. The
`fixed=` argument overrides it: vertex indices, or an (nvertices, dim)
boolean array.

write_fold() writes the assembly (its FOLD vertices and edges; apexes and
added diagonals are dropped when the assembly came from read_fold) as the
key frame, and a followed path as further frames in "file_frames", each
inheriting the key frame's mesh (frame_parent 0, frame_inherit true) and
giving only its vertices_coords; file_classes is ["animation"] then. One
frame per configuration: the key frame is the first.
"""
from __future__ import annotations

import dataclasses
import json
import math
import os
from typing import Any, Dict, List, NoReturn, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

from ..._bounded import decode_utf8, documented_errors, read_bounded
from ...assembly import Assembly
from ...errors import ModelFormatError

FoldDoc = Dict[str, Any]
FoldSourceArg = Union[str, "os.PathLike[str]", FoldDoc]

FOLD_SPEC = 1.1
FIXED_KEY = "vertices_libkin:fixed"
_FACE_MODES = ("rigid", "triangulate", "ignore")


class FoldSource:
    """What read_fold() keeps of the file to write the mesh back: the first
    n_vertices joints and n_edges bars are the file's vertices and edges, in
    order; the next n_sides bars are the sides of faces that the file gave
    no edge for (a file may give faces only); the rest are what was added to
    keep faces rigid (fan diagonals, apexes)."""

    def __init__(self, n_vertices: int, n_edges: int, assignment: Optional[List[str]],
                 faces: Optional[List[List[int]]], frame_fields: FoldDoc, n_sides: int = 0) -> None:
        self.n_vertices = n_vertices
        self.n_edges = n_edges
        self.n_sides = n_sides
        self.assignment = assignment
        self.faces = faces
        self.frame_fields = frame_fields

    def __repr__(self) -> str:
        return (f"FoldSource({self.n_vertices} vertices, {self.n_edges} edges, {self.n_sides} face sides, "
                f"{len(self.faces or [])} faces)")


class FoldAssembly(Assembly):
    """An Assembly read from a FOLD file: `fold` says which joints and bars
    are the file's vertices and edges (write_fold writes those back)."""

    fold: FoldSource


def _fail(where: str, msg: str) -> NoReturn:
    raise ModelFormatError(f"FOLD {where}: {msg}")


def _load_doc(source: FoldSourceArg, max_bytes: Optional[int] = None) -> FoldDoc:
    if isinstance(source, dict):
        return source
    try:
        if isinstance(source, (str, os.PathLike)) and not str(source).lstrip().startswith("{"):
            doc = json.loads(decode_utf8(read_bounded(source, max_bytes)))
        else:
            doc = json.loads(str(source))
    except json.JSONDecodeError as exc:
        raise ModelFormatError(f"FOLD JSON syntax: line {exc.lineno}, column {exc.colno}: {exc.msg}") from None
    if not isinstance(doc, dict):
        _fail("file", f"expected a JSON object, got {type(doc).__name__}")
    return doc


def resolve_frame(doc: FoldDoc, frame: int = 0) -> FoldDoc:
    """Frame `frame` of a FOLD dict with inheritance applied.

    Parameters
    ----------
    doc : dict
        A parsed FOLD file.
    frame : int
        0 is the top level (the key frame), i >= 1 is file_frames[i - 1].

    Returns
    -------
    dict
        The frame's properties, those it inherits included (no file_ keys).
    """
    if not isinstance(doc, dict):
        _fail("file", f"expected a JSON object, got {type(doc).__name__}")
    frames = doc.get("file_frames", [])
    if not isinstance(frames, list):
        _fail("file_frames", "expected a list of frame objects")
    if isinstance(frame, bool) or not isinstance(frame, int) or not 0 <= frame <= len(frames):
        _fail("frame", f"expected 0..{len(frames)}, got {frame!r}")
    seen = set()
    chain: List[FoldDoc] = []
    k = frame
    while True:
        if k in seen:
            _fail("frame_parent", f"cycle through frame {k}")
        seen.add(k)
        f = doc if k == 0 else frames[k - 1]
        if not isinstance(f, dict):
            _fail(f"file_frames[{k - 1}]", "expected an object")
        chain.append(f)
        if k == 0 or not f.get("frame_inherit", False):
            break
        parent = f.get("frame_parent", 0)
        if isinstance(parent, bool) or not isinstance(parent, int) or not 0 <= parent <= len(frames):
            _fail(f"file_frames[{k - 1}].frame_parent", f"expected 0..{len(frames)}, got {parent!r}")
        k = parent
    out: FoldDoc = {}
    for f in reversed(chain):
        out.update({key: v for key, v in f.items() if not key.startswith("file_")})
    return out


def _coords(fr: FoldDoc, sheet: bool, dim: Optional[int]) -> npt.NDArray[np.float64]:
    """The frame's coordinates in `dim` dimensions: as given (2 numbers: a
    plane, any 3: space), but a sheet (a frame with faces) in 3D; an
    explicit dim (2 or 3) overrides both."""
    vc = fr.get("vertices_coords")
    if not isinstance(vc, list) or not vc:
        _fail("vertices_coords", "expected a non-empty list (abstract frames have no geometry to simulate)")
    dims = set()
    for i, p in enumerate(vc):
        if not isinstance(p, list) or not 2 <= len(p) <= 3:
            _fail(f"vertices_coords[{i}]", f"expected 2 or 3 numbers, got {p!r}")
        for v in p:
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                _fail(f"vertices_coords[{i}]", f"expected finite numbers, got {p!r}")
        dims.add(len(p))
    given = max(dims)
    if dim is None:
        # a crease pattern with 2-number coordinates is a flat sheet, which
        # still folds out of its plane: faces make it 3D
        dim = 3 if sheet else given
    x = np.zeros((len(vc), max(dim, given)))
    for i, p in enumerate(vc):
        x[i, :len(p)] = p  # missing coordinates are implicitly zero (spec)
    if dim < x.shape[1]:
        if np.any(x[:, dim:] != 0.0):
            _fail("vertices_coords", f"dim={dim} asked, but a vertex has a non-zero z")
        x = x[:, :dim]
    return x


# A coordinate written with this many significant digits or more is a
# full-precision double (exact as far as the file can say); with this many
# or fewer it was typed by hand (0, 1, 2.5: exact by intent). Between, the
# file was written rounded, and its decimals are its resolution.
_EXACT_DIGITS = 13
_TYPED_DIGITS = 3


def _digits(v: float) -> Tuple[int, int]:
    """Significant digits and decimals of v's shortest round-trip decimal."""
    if v == 0.0:
        return 0, 0
    text = repr(abs(float(v)))
    mant, _, exp = text.partition("e")
    whole, _, frac = mant.partition(".")
    frac = frac.rstrip("0")
    sig = len((whole + frac).lstrip("0"))
    return sig, max(0, len(frac) - (int(exp) if exp else 0))


def detect_resolution(coords: Any) -> float:
    """How finely a file's coordinates were written: 10^-d for d decimals
    when they look rounded (between 4 and 12 significant digits somewhere,
    none with more), else 0 (exact).

    Parameters
    ----------
    coords : array_like of float
        The coordinates as read (shortest round-trip decimals of the JSON text).

    Returns
    -------
    float
        The resolution (length unit), 0 for full-precision or hand-typed values.
    """
    digits = [_digits(v) for v in np.asarray(coords, dtype=float).ravel().tolist()]
    sig = max((s for s, _ in digits), default=0)
    if sig >= _EXACT_DIGITS or sig <= _TYPED_DIGITS:
        return 0.0
    return 10.0 ** -max(d for _, d in digits)


def _index_lists(fr: FoldDoc, key: str, n: int, length: Optional[int] = None) -> Optional[List[List[int]]]:
    v = fr.get(key)
    if v is None:
        return None
    if not isinstance(v, list):
        _fail(key, "expected a list")
    for i, e in enumerate(v):
        if (not isinstance(e, list) or (length is not None and len(e) != length) or
                not all(isinstance(j, int) and not isinstance(j, bool) and 0 <= j < n for j in e)):
            want = f"{length} vertex indices" if length else "vertex indices"
            _fail(f"{key}[{i}]", f"expected {want} in 0..{n - 1}, got {e!r}")
    return [list(e) for e in v]


def _fixed_from_field(fr: FoldDoc, nv: int, dim: int) -> npt.NDArray[np.bool_]:
    f = fr.get(FIXED_KEY)
    out = np.zeros((nv, dim), dtype=bool)
    if f is None:
        return out
    if not isinstance(f, list) or len(f) != nv:
        _fail(FIXED_KEY, f"expected one entry per vertex ({nv})")
    for i, v in enumerate(f):
        if isinstance(v, bool):
            out[i] = v
        elif isinstance(v, list) and 2 <= len(v) <= dim and all(isinstance(b, bool) for b in v):
            out[i, :len(v)] = v  # a flat pattern's [x, y] flags read in 3D: z free
        else:
            _fail(f"{FIXED_KEY}[{i}]", f"expected true/false or {dim} booleans, got {v!r}")
    return out


def _fixed_from_arg(fixed: Any, nv: int, dim: int) -> npt.NDArray[np.bool_]:
    arr = np.asarray(fixed)
    if arr.dtype == bool and arr.ndim == 2 and arr.shape[0] == nv and 2 <= arr.shape[1] <= dim:
        out = np.zeros((nv, dim), dtype=bool)
        out[:, :arr.shape[1]] = arr  # (nv, 2) flags of a flat pattern read in 3D: z free
        return out
    if arr.dtype == bool and arr.shape == (nv,):
        return np.repeat(arr[:, None], dim, axis=1)
    out = np.zeros((nv, dim), dtype=bool)
    for i in np.atleast_1d(arr).tolist():
        if isinstance(i, bool) or not isinstance(i, int) or not 0 <= i < nv:
            raise ModelFormatError(f"fixed: expected vertex indices in 0..{nv - 1} or an ({nv}, {dim}) "
                                   f"boolean array, got {fixed!r}")
        out[i] = True
    return out


@documented_errors("FOLD file")
def read_fold(source: FoldSourceArg, fixed: Any = None, frame: int = 0, faces: str = "rigid",
              dim: Optional[int] = None, resolution: Optional[float] = None,
              max_bytes: Optional[int] = None) -> FoldAssembly:
    """An assembly from a FOLD file.

    Parameters
    ----------
    source : path, JSON text or dict
        The FOLD file.
    fixed : vertex indices, or an (nvertices, dim) / (nvertices,) bool array, optional
        The supports; None = the file's "vertices_libkin:fixed" (none if absent).
    frame : int
        0 = the key frame (top level), i = file_frames[i - 1] (frame_inherit honoured).
    faces : {"rigid", "triangulate", "ignore"}
        How faces are kept rigid (module docstring).
    dim : {None, 2, 3}
        None: a frame with faces (not ignored) is a sheet, in 3D even when
        its coordinates have 2 numbers (z = 0 added: a flat crease pattern
        folds out of its plane); a frame of edges only has the dimension of
        its coordinates (2 numbers: a planar linkage). 2 or 3 overrides
        both (2 refuses a non-zero z).
    resolution : float, optional
        How finely the coordinates were written (length unit); None = from
        the file's decimals (`detect_resolution`: 6 decimals give 1e-6;
        full-precision or hand-typed values 0). Set as
        `Options.coord_resolution`: the corrector and the rank test do not
        ask for more than rounding that fine allows (kin_path.h, STRAIN
        FLOOR); 0 = exact.
    max_bytes : int, optional
        Largest file read (default 64 MiB, libkin._bounded.MAX_BYTES).

    Returns
    -------
    FoldAssembly
        Rest lengths are the frame's edges_length if given for every edge,
        else the lengths in vertices_coords; its `fold` attribute lets
        write_fold() write back the file's own mesh.

    Raises ModelFormatError on anything malformed (OutOfMemoryError if
    parsing runs out of memory: only libkin's classes, whatever the input),
    LimitError for a file above max_bytes, FileAccessError for one that is
    not a regular file (a FIFO, a device: never read), OSError for one
    that cannot be opened.
    """
    if faces not in _FACE_MODES:
        raise ModelFormatError(f"faces: expected one of {_FACE_MODES}, got {faces!r}")
    if dim is not None and (isinstance(dim, bool) or dim not in (2, 3)):
        raise ModelFormatError(f"dim: expected None, 2 or 3, got {dim!r}")
    doc = _load_doc(source, max_bytes)
    fr = resolve_frame(doc, frame)
    x = _coords(fr, sheet=bool(fr.get("faces_vertices")) and faces != "ignore", dim=dim)
    nv, dim = x.shape
    edges = _index_lists(fr, "edges_vertices", nv, 2)
    face_list = _index_lists(fr, "faces_vertices", nv)
    if not edges and not face_list:
        _fail("edges_vertices", "no edges and no faces: nothing to make bars of")
    edges = edges or []
    for i, (p, q) in enumerate(edges):
        if p == q:
            _fail(f"edges_vertices[{i}]", f"an edge from vertex {p} to itself")
    assignment = fr.get("edges_assignment")
    if assignment is not None and (not isinstance(assignment, list) or len(assignment) != len(edges)):
        _fail("edges_assignment", f"expected one entry per edge ({len(edges)})")
    lengths = None
    el = fr.get("edges_length", fr.get("edges_lengths"))
    if el is not None:
        if (not isinstance(el, list) or len(el) != len(edges) or
                not all(isinstance(v, (int, float)) and not isinstance(v, bool) and v > 0 for v in el)):
            _fail("edges_length", f"expected {len(edges)} positive numbers")
        lengths = list(map(float, el))
    bars: List[Tuple[int, int]] = [(e[0], e[1]) for e in edges]
    have = {frozenset(e) for e in edges}
    labels = [f"v{i}" for i in range(nv)]
    coords: List[npt.NDArray[np.float64]] = [row for row in x]
    fix = _fixed_from_arg(fixed, nv, dim) if fixed is not None else _fixed_from_field(fr, nv, dim)
    fixed_rows = [row for row in fix]

    def add_bar(p: int, q: int) -> None:
        if frozenset((p, q)) not in have:
            have.add(frozenset((p, q)))
            bars.append((p, q))

    if faces != "ignore" and face_list:
        # a face's own sides are bars too (a file may give faces without edges)
        for f in face_list:
            for k in range(len(f)):
                if f[k] != f[(k + 1) % len(f)]:
                    add_bar(f[k], f[(k + 1) % len(f)])
    n_sides = len(bars) - len(edges)
    if faces != "ignore" and face_list:
        for fi, f in enumerate(face_list):
            if len(f) < 3:
                _fail(f"faces_vertices[{fi}]", f"a face needs 3 or more vertices, got {f!r}")
            if len(f) == 3:
                continue
            for k in range(2, len(f) - 1):
                add_bar(f[0], f[k])
            if faces == "rigid" and dim == 3:
                pts = x[f]
                c = pts.mean(axis=0)
                side = float(np.mean([np.linalg.norm(pts[k] - pts[(k + 1) % len(f)]) for k in range(len(f))]))
                nrm = np.zeros(3)
                for k in range(len(f)):  # the face's vector area: a normal for non-planar faces too
                    nrm += np.cross(pts[k] - c, pts[(k + 1) % len(f)] - c)
                if not np.linalg.norm(nrm) > 1e-12 * side * side:  # all vertices coincident too
                    _fail(f"faces_vertices[{fi}]", "a degenerate face (its vertices are collinear)")
                apex = len(coords)
                coords.append(c + side * nrm / np.linalg.norm(nrm))
                labels.append(f"apex{fi}")
                fixed_rows.append(np.zeros(dim, dtype=bool))
                for v in f:
                    add_bar(apex, v)
    if not bars:
        _fail("edges_vertices", "no edges, and faces ignored: nothing to make bars of")
    xa = np.array(coords)
    if lengths is not None:
        extra = [float(np.linalg.norm(xa[p] - xa[q])) for p, q in bars[len(edges):]]
        lengths = lengths + extra
    name = fr.get("frame_title") or doc.get("file_title") or "fold"
    a = FoldAssembly(xa, np.array(bars, dtype=np.int32).reshape(-1, 2), fixed=np.array(fixed_rows),
                     lengths=lengths, labels=labels, name=name)
    n_edges = len(edges) if edges else 0
    keep = {k: v for k, v in fr.items() if k.startswith("frame_") and k not in ("frame_parent", "frame_inherit")}
    a.fold = FoldSource(nv, n_edges, list(assignment) if assignment is not None else None, face_list, keep,
                        n_sides)
    if faces != "ignore" and face_list:
        # the faces are the model's panels (parts that can touch, docs/contact.md)
        a.panels = [f for f in face_list if len(set(f)) == len(f)]
    res = detect_resolution(x) if resolution is None else float(resolution)
    if not (math.isfinite(res) and res >= 0.0):
        raise ModelFormatError(f"resolution: expected a finite number >= 0, got {resolution!r}")
    if res > 0.0:
        a.options = dataclasses.replace(a.options, coord_resolution=res)
    return a
