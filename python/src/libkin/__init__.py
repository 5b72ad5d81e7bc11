"""libkin: kinematic paths and bifurcations of pin-jointed bar assemblies.

A thin numpy wrapper (cffi, ABI mode) over the libkin C library. Start with
`Assembly` (``help(libkin.Assembly)``); errors are in `libkin.errors`.

The package, layer by layer (each imports only the layers above it in this
list): `_native` (the cffi boundary) and `errors`; `assembly` (the Assembly
class and its result types); `io` (JSON models, FOLD files), `symmetry`,
`homotopy` (the complete solver in shards) and `parallel` (tasks on
executors); `atlas` (libkin.explore); `plot`; `studies` (the solar-sail
study, on the public API only); `cli` (the command line). The old flat
module names (libkin.model_json, libkin.fold, libkin.atlas_tasks, ...) still
import, with a DeprecationWarning (`_compat.ALIASES`).
"""
from typing import Any

from . import _compat, errors

_compat.install()

try:
    from ._native._lib import lib, library_path
except ImportError as _exc:  # no usable C library: the command line says so in one line
    from ._native._startup import exit_if_command

    exit_if_command(_exc)
    raise
from .assembly import (Analysis, Assembly, BranchPath, Branches, FollowEvent, LocateInfo, Options, SingularProof,
                       StepInfo, solve_quadrics)
from .errors import KinError, ModelFormatError
from .io.model_json import load_json, load_model, to_json
from .atlas import Atlas, explore

from .version import __version__

__all__ = ["Assembly", "Analysis", "Options", "StepInfo", "Branches", "BranchPath", "LocateInfo", "FollowEvent",
           "SingularProof", "solve_quadrics", "KinError", "ModelFormatError", "errors", "load_json", "load_model",
           "to_json", "lib",
           "library_path", "__version__", "explore", "Atlas"]


def __getattr__(name: str) -> Any:
    """libkin.<old flat module name> (e.g. ``libkin.fold``): the new module, with a DeprecationWarning."""
    return _compat.old_module(name)
