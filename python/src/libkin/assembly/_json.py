"""The JSON model format (docs/model_format.md; its JSON Schema is
model.schema.json beside this file, checked with jsonschema; C reads the
format too, kin_io.h).

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

import functools
import json
import math
import os
from importlib import resources
from typing import Any, Dict, List, NoReturn, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

from ..atomic import write_text
from .._bounded import decode_utf8, read_bounded
from ..errors import ModelFormatError
from ._base import AssemblyBase

#: What `parse` returns: name, coords, bars, fixed, lengths (or None), labels.
ParsedModel = Tuple[str, npt.NDArray[np.float64], npt.NDArray[np.int32], npt.NDArray[np.bool_],
                    Optional[npt.NDArray[np.float64]], List[str]]
#: A model source: a file path, a JSON text starting with "{", or a parsed dict.
ModelSource = Union[str, "os.PathLike[str]", Dict[str, Any]]


def _fail(where: str, msg: str) -> NoReturn:
    raise ModelFormatError(f"{where}: {msg}")


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


#: The format as a JSON Schema (draft 2020-12), shipped in the package:
#: docs/model_format.md. The C loader (model_io.c) checks the same rules.
SCHEMA_FILE = "model.schema.json"


@functools.lru_cache(maxsize=None)
def schema() -> Dict[str, Any]:
    """The model format's JSON Schema (model.schema.json), as a dict."""
    text = resources.files(__package__).joinpath(SCHEMA_FILE).read_text(encoding="utf-8")
    out: Dict[str, Any] = json.loads(text)
    return out


@functools.lru_cache(maxsize=None)
def _validator() -> Any:
    """A jsonschema validator of schema(); "integer" means an integer literal
    (2, not 2.0 or true), as jansson and Python's json read them."""
    import jsonschema
    cls = jsonschema.validators.validator_for(schema())
    checker = cls.TYPE_CHECKER.redefine("integer", lambda _, v: _is_int(v))
    return jsonschema.validators.extend(cls, type_checker=checker)(schema())


# where each part of the model is checked, for the order of the messages:
# the document's parts, then each joint's and bar's fields, in this order
_TOP = {"dimension": 0, "joints": 1, "bars": 2, "name": 3}
_FIELD = {"joints": {"index": 0, "xyz": 1, "free": 2, "label": 3}, "bars": {"index": 0, "joints": 1, "length": 2}}
_Problem = Tuple[Tuple[float, ...], str, str]  # (order, where, message)


def _bad_number(v: Any) -> bool:
    # integers beyond 64 bits are refused, as C (jansson) refuses them
    return (isinstance(v, bool) or not isinstance(v, (int, float)) or
            (isinstance(v, int) and not -2**63 <= v < 2**63) or not math.isfinite(v))


def _problem(doc: Any, path: List[Any]) -> _Problem:
    """The message for a rule broken at `path` (a list of keys and indices)."""
    if not path:
        return (-1.0,), "model", f"expected a JSON object, got {type(doc).__name__}"
    top = str(path[0])
    v = doc.get(top)
    if len(path) == 1:
        if top == "dimension":
            return (0.0,), top, f"expected 2 or 3, got {v!r}"
        if top == "name":
            return (3.0,), top, f"expected a string, got {v!r}"
        return (float(_TOP[top]),), top, "expected a non-empty list"
    i = int(path[1])
    if len(path) == 2:
        return (float(_TOP[top]), i), f"{top}[{i}]", "expected an object"
    field = str(path[2])
    item = v[i]
    order, where, v = (float(_TOP[top]), i, _FIELD[top][field]), f"{top}[{i}].{field}", item.get(field)
    dim = doc.get("dimension")
    if field == "index":
        return order, where, f"expected {i}, got {v!r}"
    if field == "xyz":
        if len(path) > 3:
            c = int(path[3])
            return order + (c,), f"{where}[{c}]", f"expected a finite number, got {v[c]!r}"
        return order, where, f"expected {dim} numbers, got {v!r}"
    if field == "free":
        return order, where, f"expected {dim} booleans, got {v!r}"
    if field == "label":
        return order, where, f"expected a string, got {v!r}"
    if field == "joints":
        if isinstance(v, list) and len(v) == 2 and all(_is_int(e) for e in v):
            n = len(doc["joints"]) if isinstance(doc.get("joints"), list) else 0
            e = next(e for e in v if not 0 <= e < n)
            return order, where, f"joint {e} out of range 0..{n - 1}"
        return order, where, f"expected two joint indices, got {v!r}"
    # the rest length
    if _bad_number(v):
        return order, where, f"expected a finite number, got {v!r}"
    return order, where, f"expected > 0, got {float(v)}"


def _problems(doc: Any) -> List[_Problem]:
    """Every rule of the format that doc breaks: the schema's, and what a
    schema cannot say (indices equal to positions, bar ends below the joint
    count, numbers finite and integers within 64 bits)."""
    out: List[_Problem] = []
    for err in _validator().iter_errors(doc):
        path = list(err.absolute_path)
        if err.validator == "required":
            out += [_problem(doc, path + [k]) for k in err.validator_value if k not in err.instance]
        elif path == ["bars"] and err.validator == "anyOf":
            out.append(((2.0, math.inf), "bars", "give a length for every bar or for none"))
        else:
            out.append(_problem(doc, path))
    if not isinstance(doc, dict):
        return out
    joints, bars = doc.get("joints"), doc.get("bars")
    n = len(joints) if isinstance(joints, list) else 0
    for top, items in (("joints", joints), ("bars", bars)):
        for i, item in enumerate(items if isinstance(items, list) else []):
            if not isinstance(item, dict):
                continue
            if "index" in item and item["index"] != i:
                out.append(_problem(doc, [top, i, "index"]))
            xyz = item.get("xyz") if top == "joints" else None
            for c, x in enumerate(xyz if isinstance(xyz, list) else []):
                if isinstance(x, (int, float)) and not isinstance(x, bool) and _bad_number(x):
                    out.append(_problem(doc, [top, i, "xyz", c]))
            ends = item.get("joints") if top == "bars" else None
            if isinstance(ends, list) and any(_is_int(e) and e >= n for e in ends):
                out.append(_problem(doc, [top, i, "joints"]))
            if top == "bars" and isinstance(item.get("length"), (int, float)) and _bad_number(item["length"]):
                out.append(_problem(doc, [top, i, "length"]))
    return out


#: A parsed model (a dict) with more joints and bars than this together is
#: checked by the C loader (its JSON text, json.dumps, to
#: kin_assembly_load_string) instead of jsonschema, as a long text is: the
#: schema pass costs about 1 s a MB, the C loader about 30 ms. The library
#: itself has no limit on the counts below its int indices (a model whose
#: dense analysis would not fit is still made: the sparse mode needs no dense
#: matrix; docs/model_format.md).
LARGE_COUNT = 20000

#: A JSON text longer than this (bytes) is checked by the C loader
#: (kin_assembly_load_string: about 30 ms a MB) instead of jsonschema (about
#: 1 s a MB): validation and parsing stay bounded in time and memory.
LARGE_TEXT = 2 * 1024 * 1024


def _large_checked_by_c(doc: Any) -> bool:
    """For a dict with more than LARGE_COUNT joints and bars: check it with
    the C loader (raising its verdict, e.g. ModelFormatError) and return
    True, so that parse() builds it without the schema pass; False for a
    smaller dict or one too malformed to count (left to the schema)."""
    if not isinstance(doc, dict):
        return False
    joints, bars = doc.get("joints"), doc.get("bars")
    if not isinstance(joints, list) or not isinstance(bars, list) or len(joints) + len(bars) <= LARGE_COUNT:
        return False
    try:
        data = json.dumps(doc, allow_nan=False).encode("utf-8", "surrogatepass")
    except (TypeError, ValueError):
        return False  # not a JSON document (NaN, objects): the Python loader's own verdict
    _c_check(data)
    return True


def parse(doc: Any) -> ParsedModel:
    """Validate a model dict against the format (schema() and the rules a
    schema cannot say, docs/model_format.md).

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
        The model is malformed; the message names the field and position
        (of the first problem, in the order of the document's parts, the
        joints and the bars, each field in turn).
    """
    if _large_checked_by_c(doc):
        try:  # the C loader checked the same rules (docs/model_format.md): no schema pass
            return _build(doc)
        except (KeyError, TypeError, ValueError, IndexError, AttributeError):
            pass  # the loaders disagree: the Python loader's own verdict
    problems = _problems(doc)
    if problems:
        _, where, msg = min(problems, key=lambda p: p[0])
        _fail(where, msg)
    return _build(doc)


def _build(doc: Dict[str, Any]) -> ParsedModel:
    """parse()'s result from a model already found valid."""
    dim, joints, bars_doc = doc["dimension"], doc["joints"], doc["bars"]
    coords = np.array([j["xyz"] for j in joints], dtype=float).reshape(len(joints), dim)
    fixed = np.array([[not f for f in j.get("free", [True] * dim)] for j in joints], dtype=bool).reshape(-1, dim)
    labels = [j.get("label", f"J{i}") for i, j in enumerate(joints)]
    bars = np.array([b["joints"] for b in bars_doc], dtype=np.int32).reshape(-1, 2)
    lengths = np.array([float(b["length"]) for b in bars_doc]) if "length" in bars_doc[0] else None
    out = _Parsed((doc.get("name", "model"), coords, bars, fixed, lengths, labels))
    out.contact = _contact_fields(doc, len(joints), len(bars_doc))
    return out


class _Parsed(tuple):  # type: ignore[type-arg]
    """parse()'s 6-tuple, with the contact fields (panels, thickness, radii)
    as `.contact` (None for a model without them)."""
    contact: Optional[Dict[str, Any]] = None


def _thick(v: Any, where: str) -> float:
    if _bad_number(v) or v < 0 or v > 1e150:
        _fail(where, f"expected a finite number >= 0, got {v!r}")
    return float(v)


def _contact_fields(doc: Dict[str, Any], nj: int, nb: int) -> Optional[Dict[str, Any]]:
    """The optional "thickness", bars[k].radius and "panels" (docs/model_format.md),
    checked as the C loader checks them."""
    t0 = _thick(doc["thickness"], "thickness") if "thickness" in doc else 0.0
    radii = [_thick(b["radius"], f"bars[{k}].radius") if "radius" in b else -1.0
             for k, b in enumerate(doc["bars"])]
    devices = []
    for k, b in enumerate(doc["bars"]):
        if "device" in b and not isinstance(b["device"], bool):
            _fail(f"bars[{k}].device", f"expected true or false, got {b['device']!r}")
        if b.get("device") is True:
            devices.append(k)
    panels_doc = doc.get("panels")
    if panels_doc is None and t0 == 0.0 and all(r < 0 for r in radii) and not devices:
        return None
    if panels_doc is not None and not isinstance(panels_doc, list):
        _fail("panels", f"expected a list, got {type(panels_doc).__name__}")
    panels: List[List[int]] = []
    thick: List[float] = []
    for i, p in enumerate(panels_doc or []):
        if not isinstance(p, dict):
            _fail(f"panels[{i}]", "expected an object")
        if "index" in p and not (_is_int(p["index"]) and p["index"] == i):
            _fail(f"panels[{i}].index", f"expected {i}, got {p['index']!r}")
        js = p.get("joints")
        if not isinstance(js, list) or not 3 <= len(js) <= 1024:
            _fail(f"panels[{i}].joints", f"expected a list of 3 to 1024 joint indices, got {js!r}")
        for q, j in enumerate(js):
            if not _is_int(j):
                _fail(f"panels[{i}].joints[{q}]", f"expected a joint index, got {j!r}")
            if not 0 <= j < nj:
                _fail(f"panels[{i}].joints[{q}]", f"joint {j} out of range 0..{nj - 1}")
            if j in js[:q]:
                _fail(f"panels[{i}].joints[{q}]", f"joint {j} repeated")
        panels.append([int(j) for j in js])
        thick.append(_thick(p["thickness"], f"panels[{i}].thickness") if "thickness" in p else -1.0)
    return {"panels": panels, "thickness": t0, "bar_radii": radii, "panel_thicknesses": thick,
            "device_bars": devices}


def apply_contact(a: Any, contact: Optional[Dict[str, Any]]) -> None:
    """Set what _contact_fields read on a new Assembly."""
    if not contact:
        return
    if contact["panels"]:
        a.panels = contact["panels"]
    a.set_thickness(contact["thickness"], contact["bar_radii"], contact["panel_thicknesses"] or None)
    if contact.get("device_bars"):
        a.device_bars = contact["device_bars"]


def read_json(source: ModelSource, max_bytes: Optional[int] = None) -> ParsedModel:
    """Read and check a JSON model with the Python loader: what
    `Assembly.from_json` (and `libkin.load_json`) build the Assembly from.
    The source is a file path, a JSON text (starting with ``{``) or the
    parsed dict, as there; the result is (name, coords, bars, fixed, lengths
    or None, labels), see `parse`. Raises ModelFormatError for a malformed
    model (a ValueError; the message names the field and position) and
    OSError for an unreadable file. A file is read only if it is a regular
    file of at most max_bytes bytes (default 64 MiB, the C loader's
    KIN_LOAD_MAX_BYTES): LimitError for a larger one, FileAccessError (an
    OSError) for a FIFO or a device, never read."""
    if isinstance(source, dict):
        return parse(source)
    text: Any = source
    if isinstance(source, (str, os.PathLike)) and not str(source).lstrip().startswith("{"):
        text = decode_utf8(read_bounded(source, max_bytes))
    return _parse_text(text) if isinstance(text, (str, bytes)) else _parse_text.__wrapped__(text)


@functools.lru_cache(maxsize=16)
def _parse_text(text: Any) -> ParsedModel:
    """parse() of a JSON text, remembered for the last few texts: the atlas
    rebuilds its model from one text in every task, and the schema check
    (jsonschema) costs milliseconds. The arrays are only read (Assembly
    copies them into the C handle)."""
    data = text if isinstance(text, bytes) else text.encode("utf-8", "surrogatepass") if isinstance(text, str) else None
    large = data is not None and len(data) > LARGE_TEXT
    if large and data is not None:
        _c_check(data)  # raises the C loader's verdict: before Python builds a single object
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as exc:
        raise ModelFormatError(f"JSON syntax: line {exc.lineno}, column {exc.colno}: {exc.msg}") from None
    except RecursionError:
        _fail("JSON text", f"lists or objects nested deeper than {MAX_DEPTH}")
    if large:
        try:  # the C loader checked the same rules (docs/model_format.md): no schema pass
            return _build(doc)
        except (KeyError, TypeError, ValueError, IndexError, AttributeError):
            pass  # the loaders disagree: the Python loader's own verdict
    _check_text(doc)
    return parse(doc)


def _c_check(data: bytes) -> None:
    """Check a JSON model text with the C loader (kin_assembly_load_string:
    the same rules, in bounded time and memory) and raise its verdict (a
    KinError: ModelFormatError, ...); nothing if the model is valid."""
    from .._native._lib import c_string, ffi, lib
    from ..errors import error_class
    out, err = ffi.new("kin_assembly **"), ffi.new("char[512]")
    rc = lib.kin_assembly_load_string(data, len(data), out, err, 512)
    if out[0] != ffi.NULL:
        lib.kin_assembly_free(out[0])
    if rc:
        raise error_class(rc)(c_string(err), rc)


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
    t0 = float(getattr(self, "thickness", 0.0))
    for k in getattr(self, "device_bars", []):
        doc["bars"][k]["device"] = True
    if getattr(self, "has_contact_model", False):
        for k, r in enumerate(getattr(self, "bar_radii")):
            if r != 0.5 * t0:
                doc["bars"][k]["radius"] = float(r)
        if t0 > 0.0:
            doc["thickness"] = t0
        panels = getattr(self, "panels")
        if panels:
            tp = getattr(self, "panel_thicknesses")
            doc["panels"] = [dict({"index": i, "joints": f}, **({"thickness": float(tp[i])} if tp[i] != t0 else {}))
                             for i, f in enumerate(panels)]
    if path is not None:  # whole or not at all: the file saved before stays on a failure
        write_text(path, json.dumps(doc, indent=1))
    return doc
