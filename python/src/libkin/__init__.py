"""libkin: kinematic paths and bifurcations of pin-jointed bar assemblies.

A thin numpy wrapper (cffi, ABI mode) over the libkin C library. Start with
`Assembly` (``help(libkin.Assembly)``); errors are in `libkin.errors`.
"""
from . import errors

try:
    from ._lib import lib, library_path
except ImportError as _exc:  # no usable C library: the command line says so in one line
    from ._startup import exit_if_command

    exit_if_command(_exc)
    raise
from ._lib import c_string as _c_string
from .assembly import (Analysis, Assembly, BranchPath, Branches, FollowEvent, LocateInfo, Options, StepInfo,
                       solve_quadrics)
from .errors import KinError, ModelFormatError
from .model_json import load_json, load_model, to_json
from .atlas import Atlas, explore

#: The version of the loaded C library (``kin_version_string()``), which is
#: also the version of this package.
__version__: str = _c_string(lib.kin_version_string())

__all__ = ["Assembly", "Analysis", "Options", "StepInfo", "Branches", "BranchPath", "LocateInfo", "FollowEvent",
           "solve_quadrics", "KinError", "ModelFormatError", "errors", "load_json", "load_model", "to_json", "lib",
           "library_path", "__version__", "explore", "Atlas"]
