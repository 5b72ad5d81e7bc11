"""The JSON model format (schema in docs/model_format.md; C reads it too, kin_io.h).

`load_json` builds an Assembly with the Python loader, `load_model` with
either loader (Python or the C library's kin_assembly_load), `to_json`
writes an assembly's current state. The document itself (`parse`,
`read_json`, `to_json`) is the Assembly's own JSON form
(libkin/assembly/_json.py), re-exported here.
"""
from __future__ import annotations

import os
from typing import Optional

from .._native._lib import c_string, ffi, lib
from ..assembly import Assembly
from ..assembly._json import MAX_DEPTH, ModelSource, ParsedModel, parse, read_json, schema, to_json
from ..errors import ArgumentTypeError, InvalidArgumentError, error_class

__all__ = ["load_json", "load_model", "load_builtin", "BUILTIN_PREFIXES", "to_json", "parse", "read_json", "schema", "ModelSource", "ParsedModel",
           "MAX_DEPTH"]


#: Build an Assembly from a JSON model with the Python loader: the Assembly's
#: own reader, under the name the format's module has always had.
load_json = Assembly.from_json


#: how a built-in model's name starts ("threebar:RC", "sail:6:2")
BUILTIN_PREFIXES = ("threebar:", "sail:")


def load_builtin(spec: str) -> Assembly:
    """A built-in model by name: threebar:RA|RB|RC or sail:N_SIDES[:N_LOOPS]
    (the names `libkin explore` and libkin.explore accept);
    InvalidArgumentError for another name."""
    if spec.startswith("threebar:"):
        return Assembly.threebar(spec.split(":", 1)[1])
    parts = spec.split(":")
    if parts[0] != "sail" or len(parts) not in (2, 3) or not all(p.isdigit() for p in parts[1:]):
        raise InvalidArgumentError(f"MODEL {spec!r}: expected threebar:RA|RB|RC, sail:N_SIDES or "
                                   "sail:N_SIDES:N_LOOPS")
    return Assembly.sail(int(parts[1]), int(parts[2]) if len(parts) > 2 else 1)


def load_model(source: ModelSource, engine: str = "python", max_bytes: Optional[int] = None) -> "Assembly":
    """Build an Assembly from a JSON model with either loader.

    Parameters
    ----------
    source : str, path-like or dict
        A file path or a JSON text (starting with ``{``); a dict only with
        engine="python"; or a built-in model's name, "threebar:RA|RB|RC" or
        "sail:N_SIDES[:N_LOOPS]" (`load_builtin`, either engine).
    engine : {'python', 'c'}, optional
        'python': `load_json`; 'c': the C library's kin_assembly_load (the
        same rules and verdicts, docs/model_format.md; the name and joint
        labels are not kept).
    max_bytes : int, optional
        Largest file read (default 64 MiB, KIN_LOAD_MAX_BYTES): a larger file
        raises LimitError, a FIFO or a device FileAccessError (never read).

    Returns
    -------
    Assembly
        The model.

    Raises
    ------
    ModelFormatError
        A malformed model (KIN_EFORMAT; a ValueError).
    InvalidArgumentError
        An unknown `engine`.
    KinError
        The class of the C status otherwise (e.g. `FileAccessError`, an
        OSError, for an unreadable file with engine="c"; with
        engine="python" an unreadable file raises the built-in OSError).
    """
    if max_bytes is not None and max_bytes <= 0:
        raise InvalidArgumentError(f"max_bytes = {max_bytes}: must be > 0")
    if engine not in ("python", "c"):
        raise InvalidArgumentError(f"engine: expected 'python' or 'c', got {engine!r}")
    if isinstance(source, str) and source.startswith(BUILTIN_PREFIXES):
        return load_builtin(source)
    if engine == "python":
        return Assembly.from_json(source, max_bytes)
    if isinstance(source, dict):
        raise ArgumentTypeError("source: engine='c' reads a file path or a JSON text, not a dict")
    out, err = ffi.new("kin_assembly **"), ffi.new("char[512]")
    if isinstance(source, str) and source.lstrip().startswith("{"):
        data = source.encode("utf-8", "surrogatepass")
        rc = lib.kin_assembly_load_string(data, len(data), out, err, 512)
    else:
        rc = lib.kin_assembly_load_limited(os.fsencode(source), max_bytes or 0, out, err, 512)
    if rc:
        raise error_class(rc)(c_string(err), rc)
    return Assembly._from_handle(out[0])
