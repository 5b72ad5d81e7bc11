"""The JSON model format (schema in python/README.md).

{"name": str, "dimension": 2|3,
 "joints": [{"index": i, "label": str, "xyz": [x, y(, z)], "free": [bool, ...]}, ...],
 "bars":   [{"index": k, "joints": [i, j], "length": L (optional), "kind": str (optional)}, ...]}
Extra keys are kept out of the way (ignored). Indices are 0-based; joint
"index" values must be 0..n-1 in order, as must bar "index" values if given."""
from __future__ import annotations

import json
import math
import os
from typing import TYPE_CHECKING, Any, Dict, List, NoReturn, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

from .errors import ModelFormatError

if TYPE_CHECKING:
    from .assembly import Assembly

#: What `parse` returns: name, coords, bars, fixed, lengths (or None), labels.
ParsedModel = Tuple[str, npt.NDArray[np.float64], npt.NDArray[np.int32], npt.NDArray[np.bool_],
                    Optional[npt.NDArray[np.float64]], List[str]]


def _fail(where: str, msg: str) -> NoReturn:
    raise ModelFormatError(f"{where}: {msg}")


def _number(v: Any, where: str) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        _fail(where, f"expected a finite number, got {v!r}")
    return float(v)


def parse(doc: Any) -> ParsedModel:
    """Validate a model dict.

    Parameters
    ----------
    doc : dict
        A parsed JSON model.

    Returns
    -------
    tuple
        (name, coords (njoints, dim), bars (nbars, 2) int32, fixed
        (njoints, dim) bool, lengths (nbars,) or None, labels).

    Raises
    ------
    ModelFormatError
        The model is malformed; the message names the field and position.
    """
    if not isinstance(doc, dict):
        _fail("model", f"expected a JSON object, got {type(doc).__name__}")
    dim = doc.get("dimension")
    if dim not in (2, 3) or isinstance(dim, bool):
        _fail("dimension", f"expected 2 or 3, got {dim!r}")
    joints = doc.get("joints")
    if not isinstance(joints, list) or not joints:
        _fail("joints", "expected a non-empty list")
    coords = np.empty((len(joints), dim))
    fixed = np.zeros((len(joints), dim), dtype=bool)
    labels: List[str] = []
    for i, j in enumerate(joints):
        w = f"joints[{i}]"
        if not isinstance(j, dict):
            _fail(w, "expected an object")
        if "index" in j and j["index"] != i:
            _fail(f"{w}.index", f"expected {i}, got {j['index']!r}")
        xyz = j.get("xyz")
        if not isinstance(xyz, list) or len(xyz) != dim:
            _fail(f"{w}.xyz", f"expected {dim} numbers, got {xyz!r}")
        coords[i] = [_number(v, f"{w}.xyz[{c}]") for c, v in enumerate(xyz)]
        free = j.get("free", [True] * dim)
        if not isinstance(free, list) or len(free) != dim or not all(isinstance(f, bool) for f in free):
            _fail(f"{w}.free", f"expected {dim} booleans, got {free!r}")
        fixed[i] = [not f for f in free]
        label = j.get("label", f"J{i}")
        if not isinstance(label, str):
            _fail(f"{w}.label", f"expected a string, got {label!r}")
        labels.append(label)
    bars_doc = doc.get("bars")
    if not isinstance(bars_doc, list) or not bars_doc:
        _fail("bars", "expected a non-empty list")
    bars = np.empty((len(bars_doc), 2), dtype=np.int32)
    lengths = np.empty(len(bars_doc))
    have_len = [("length" in b) if isinstance(b, dict) else False for b in bars_doc]
    for k, b in enumerate(bars_doc):
        w = f"bars[{k}]"
        if not isinstance(b, dict):
            _fail(w, "expected an object")
        if "index" in b and b["index"] != k:
            _fail(f"{w}.index", f"expected {k}, got {b['index']!r}")
        ends = b.get("joints")
        if (not isinstance(ends, list) or len(ends) != 2 or
                not all(isinstance(e, int) and not isinstance(e, bool) for e in ends)):
            _fail(f"{w}.joints", f"expected two joint indices, got {ends!r}")
        for e in ends:
            if not 0 <= e < len(joints):
                _fail(f"{w}.joints", f"joint {e} out of range 0..{len(joints) - 1}")
        bars[k] = ends
        if have_len[k]:
            lengths[k] = _number(b["length"], f"{w}.length")
            if lengths[k] <= 0:
                _fail(f"{w}.length", f"expected > 0, got {lengths[k]}")
    if any(have_len) and not all(have_len):
        _fail("bars", "give a length for every bar or for none")
    name = doc.get("name", "model")
    return name, coords, bars, fixed, (lengths if all(have_len) else None), labels


def load_json(source: Union[str, "os.PathLike[str]", Dict[str, Any]]) -> "Assembly":
    """Build an Assembly from a JSON model.

    Parameters
    ----------
    source : str, path-like or dict
        A file path, a JSON text (starting with ``{``), or the parsed dict.

    Returns
    -------
    Assembly
        The model, with its labels and name.

    Raises
    ------
    ModelFormatError
        Malformed JSON or model (a ValueError); the message names the field
        and position.
    OSError
        The file cannot be read.
    """
    from .assembly import Assembly
    doc: Any
    if isinstance(source, dict):
        doc = source
    else:
        text = str(source) if not isinstance(source, str) else source
        if isinstance(source, (str, os.PathLike)) and not str(source).lstrip().startswith("{"):
            with open(source) as f:
                text = f.read()
        try:
            doc = json.loads(text)
        except json.JSONDecodeError as exc:
            raise ModelFormatError(f"JSON syntax: line {exc.lineno}, column {exc.colno}: {exc.msg}") from None
    name, coords, bars, fixed, lengths, labels = parse(doc)
    return Assembly(coords, bars, fixed=fixed, lengths=lengths, labels=labels, name=name)


def to_json(self: "Assembly", path: Union[str, "os.PathLike[str]", None] = None) -> Dict[str, Any]:
    """The assembly's current state as a model dict.

    Parameters
    ----------
    self : Assembly
        The assembly.
    path : str or path-like, optional
        Also write the model to this file.

    Returns
    -------
    dict
        The model (schema in python/README.md), with the rest lengths.
    """
    coords, fixed, bars, L0 = self.coords, self.fixed, self.bars, self.rest_lengths
    labels = self.labels or [f"J{i}" for i in range(self.njoints)]
    doc: Dict[str, Any] = {
        "name": self.name or "model",
        "dimension": self.dim,
        "joints": [{"index": i, "label": labels[i], "xyz": [float(v) for v in coords[i]],
                    "free": [not bool(f) for f in fixed[i]]} for i in range(self.njoints)],
        "bars": [{"index": k, "joints": [int(bars[k, 0]), int(bars[k, 1])], "length": float(L0[k])}
                 for k in range(self.nbars)],
    }
    if path is not None:
        with open(path, "w") as f:
            json.dump(doc, f, indent=1)
    return doc
