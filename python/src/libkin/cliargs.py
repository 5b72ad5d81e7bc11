"""What the subcommands of the command line share: the exit statuses, the
checked argparse types and the MODEL argument. libkin.cli (the dispatcher),
libkin.atlas.cli (`libkin explore`) and libkin.studies.cli (`libkin study`)
build on it; it imports none of them.
"""
from __future__ import annotations

import argparse
import math
import os
from typing import Any, Callable, Dict, Optional, Union

from .assembly import Assembly
from .errors import InvalidArgumentError

EXIT_ERROR = 1
EXIT_USAGE = 2
EXIT_STUDY_FAILED = 3
EXIT_PARTIAL = 4  # a path stopped before the steps asked: fewer frames written than asked
EXIT_STORE = 5  # the run's store cannot be used (not a store, damaged, truncated, a write failed: a full disk)
EXIT_INTERRUPTED = 130


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
    if spec.startswith("threebar:"):
        return Assembly.threebar(spec.split(":", 1)[1])
    if spec.startswith("sail:"):
        parts = spec.split(":")
        if len(parts) not in (2, 3) or not all(p.isdigit() for p in parts[1:]):
            raise InvalidArgumentError(f"MODEL {spec!r}: expected sail:N_SIDES or sail:N_SIDES:N_LOOPS")
        return Assembly.sail(int(parts[1]), int(parts[2]) if len(parts) > 2 else 1)
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
    return load_model_spec(model) if isinstance(model, str) and model.startswith(("threebar:", "sail:")) \
        else load_json(model)
