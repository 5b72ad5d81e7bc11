"""What the subcommands of the command line share: the exit statuses, the
checked argparse types and the MODEL argument. libkin.cli (the dispatcher),
libkin.atlas.cli (`libkin explore`) and libkin.studies.cli (`libkin study`)
build on it; it imports none of them.
"""
from __future__ import annotations

import argparse
import importlib
import math
import os
from typing import Any, Callable, Dict, Iterable, Optional, Union

from .assembly import Assembly

EXIT_ERROR = 1
EXIT_USAGE = 2
EXIT_STUDY_FAILED = 3
EXIT_PARTIAL = 4  # a path stopped before the steps asked: fewer frames written than asked
EXIT_STORE = 5  # the run's store cannot be used (not a store, damaged, truncated, a write failed: a full disk)
EXIT_INTERRUPTED = 130


#: the optional modules a command may need -> the extra of the package that brings each (pyproject.toml)
EXTRAS = {"matplotlib": "plot", "networkx": "atlas", "plotly": "viewer", "distributed": "dask", "tqdm": "progress"}


def require_extras(what: str, modules: Iterable[str]) -> None:
    """Check up front that every optional module `what` (a command, or the
    files it writes) will need can be imported: one ImportError naming all
    the missing ones and the extras that bring them, before any work (the
    command line prints it and exits 1, nothing written)."""
    missing = []
    for mod in dict.fromkeys(modules):
        try:
            importlib.import_module(mod)
        except ImportError:
            missing.append(mod)
    if missing:
        extras = ",".join(sorted({EXTRAS.get(m, m) for m in missing}))
        raise ImportError(f"{what} needs {' and '.join(missing)}, not installed: pip install 'libkin[{extras}]' "
                          f"(or pip install {' '.join(missing)})")


def finite(text: str) -> float:
    """argparse type: a finite number (inf and nan are refused as usage errors)."""
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not math.isfinite(v):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text!r}")
    return v


def positive(text: str) -> float:
    """argparse type: a finite number > 0."""
    v = finite(text)
    if v <= 0:
        raise argparse.ArgumentTypeError(f"expected a number > 0, got {text!r}")
    return v


def nonnegative(text: str) -> float:
    """argparse type: a finite number >= 0."""
    v = finite(text)
    if v < 0:
        raise argparse.ArgumentTypeError(f"expected a number >= 0, got {text!r}")
    return v


def add_input_arguments(s: argparse.ArgumentParser) -> None:
    """--fold-dim and --resolution: how a MODEL file's geometry is read."""
    s.add_argument("--fold-dim", type=int, choices=[2, 3], default=None,
                   help="read a .fold file in 2 or 3 dimensions (default: 3 for a sheet with faces, else as its "
                        "coordinates)")
    s.add_argument("--resolution", type=nonnegative, default=None, metavar="R",
                   help="how finely the model's coordinates were written (length unit, e.g. 1e-6 for 6 "
                        "decimals; 0 = exact): the corrector asks for no less strain than that rounding leaves "
                        "(default: a .fold file's decimals, exact for other models)")


def count(minimum: int) -> Callable[[str], int]:
    """argparse type: an integer >= minimum."""
    def parse(text: str) -> int:
        try:
            v = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None
        if v < minimum:
            raise argparse.ArgumentTypeError(f"expected an integer >= {minimum}, got {v}")
        return v
    return parse


def load_model_spec(spec: str, fold_dim: Optional[int] = None, resolution: Optional[float] = None) -> Assembly:
    """MODEL is a JSON file, or a built-in: threebar:RA|RB|RC, sail:N:LOOPS,
    or a .fold file (read in `fold_dim` dimensions if given, else 3D for a
    sheet with faces; `resolution` of its coordinates if given, else from
    its decimals). `resolution` given sets `Options.coord_resolution` of any
    model."""
    from .io.model_json import BUILTIN_PREFIXES, load_builtin
    if spec.startswith(BUILTIN_PREFIXES):
        return load_builtin(spec)
    if spec.endswith(".fold"):
        from .io.fold import read_fold
        return read_fold(spec, dim=fold_dim, resolution=resolution)
    a = Assembly.from_json(spec)
    if resolution is not None:
        import dataclasses
        a.options = dataclasses.replace(a.options, coord_resolution=resolution)
    return a


def as_assembly(model: Union[Assembly, str, "os.PathLike[str]", Dict[str, Any]]) -> Assembly:
    """An Assembly as given, or one read from a JSON model (file path, text
    or dict) or made from a built-in spec ("sail:6:2", "threebar:RC")."""
    from .io.model_json import load_json
    if isinstance(model, Assembly):
        return model
    from .io.model_json import BUILTIN_PREFIXES
    return load_model_spec(model) if isinstance(model, str) and model.startswith(BUILTIN_PREFIXES) \
        else load_json(model)
