"""The JSON model format (schema in docs/model_format.md; C reads it too, kin_io.h).

{"name": str, "dimension": 2|3,
 "joints": [{"index": i, "label": str, "xyz": [x, y(, z)], "free": [bool, ...]}, ...],
 "bars":   [{"index": k, "joints": [i, j], "length": L (optional), "kind": str (optional)}, ...]}
Extra keys are kept out of the way (ignored). Indices are 0-based; joint
"index" values must be 0..n-1 in order, as must bar "index" values if given.

This is the Assembly's own form (`Assembly.from_json`, `Assembly.to_json`):
it reads and writes plain data and knows the class only through
`AssemblyBase`. The public module of the format, with the loaders that build
an Assembly (`load_json`, `load_model`), is `libkin.io.model_json`."""
from __future__ import annotations

import json
import math
import os
from typing import Any, Dict, List, NoReturn, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

from ..errors import ModelFormatError
from ._base import AssemblyBase

#: What `parse` returns: name, coords, bars, fixed, lengths (or None), labels.
ParsedModel = Tuple[str, npt.NDArray[np.float64], npt.NDArray[np.int32], npt.NDArray[np.bool_],
                    Optional[npt.NDArray[np.float64]], List[str]]
#: A model source: a file path, a JSON text starting with "{", or a parsed dict.
ModelSource = Union[str, "os.PathLike[str]", Dict[str, Any]]


def _fail(where: str, msg: str) -> NoReturn:
    raise ModelFormatError(f"{where}: {msg}")


def _number(v: Any, where: str) -> float:
    # integers beyond 64 bits are refused, as C (jansson) refuses them
    if (isinstance(v, bool) or not isinstance(v, (int, float)) or
            (isinstance(v, int) and not -2**63 <= v < 2**63) or not math.isfinite(v)):
        _fail(where, f"expected a finite number, got {v!r}")
    return float(v)


#: Lists and objects nest at most this deep (the document is depth 1).
MAX_DEPTH = 64


def _check_text(doc: Any) -> None:
    """Refuse what valid JSON may hold but C's reader (jansson) refuses, so
    both loaders agree: nesting deeper than MAX_DEPTH, an unpaired surrogate
    escape ("\\ud800") in a string, a NUL in a key."""
    stack: List[Tuple[Any, int]] = [(doc, 1)]
    while stack:
        v, depth = stack.pop()
        if isinstance(v, (dict, list)):
            if depth > MAX_DEPTH:
                _fail("JSON text", f"lists or objects nested deeper than {MAX_DEPTH}")
            if isinstance(v, dict):
                if any("\0" in k for k in v):
                    _fail("JSON text", "a key holds U+0000")
                stack.extend((k, depth) for k in v)
            stack.extend((c, depth + 1) for c in (v.values() if isinstance(v, dict) else v))
        elif isinstance(v, str):
            try:
                v.encode("utf-8")
            except UnicodeEncodeError:
                _fail("JSON text", f"a string holds an unpaired surrogate: {v!r}")


def _is_int(v: Any) -> bool:
    return isinstance(v, int) and not isinstance(v, bool)


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
    if dim not in (2, 3) or not _is_int(dim):
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
        if "index" in j and not (_is_int(j["index"]) and j["index"] == i):
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
        if "index" in b and not (_is_int(b["index"]) and b["index"] == k):
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
    if not isinstance(name, str):
        _fail("name", f"expected a string, got {name!r}")
    return name, coords, bars, fixed, (lengths if all(have_len) else None), labels


def read_json(source: ModelSource) -> ParsedModel:
    """Read and check a JSON model with the Python loader (`Assembly.from_json`
    and `libkin.load_json` build the Assembly from it).

    Parameters
    ----------
    source : str, path-like or dict
        A file path, a JSON text (starting with ``{``), or the parsed dict.

    Returns
    -------
    ParsedModel
        name, coords, bars, fixed, lengths (or None), labels (see `parse`).

    Raises
    ------
    ModelFormatError
        Malformed JSON or model (a ValueError); the message names the field
        and position.
    OSError
        The file cannot be read.
    """
    doc: Any
    if isinstance(source, dict):
        doc = source
    else:
        text: Any = source
        if isinstance(source, (str, os.PathLike)) and not str(source).lstrip().startswith("{"):
            try:
                with open(source, encoding="utf-8") as f:
                    text = f.read()
            except UnicodeDecodeError as exc:
                raise ModelFormatError(f"not UTF-8 text: byte {exc.start}: {exc.reason}") from None
        try:
            doc = json.loads(text)
        except json.JSONDecodeError as exc:
            raise ModelFormatError(f"JSON syntax: line {exc.lineno}, column {exc.colno}: {exc.msg}") from None
        except RecursionError:
            _fail("JSON text", f"lists or objects nested deeper than {MAX_DEPTH}")
        _check_text(doc)
    return parse(doc)


def to_json(self: AssemblyBase, path: Union[str, "os.PathLike[str]", None] = None) -> Dict[str, Any]:
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
        The model (schema in docs/model_format.md), with the rest lengths.
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
