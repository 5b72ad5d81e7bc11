"""libkin: kinematic paths and bifurcations of pin-jointed bar assemblies.

A thin numpy wrapper (cffi, ABI mode) over the libkin C library."""
from ._cdef import VERSION
from ._lib import lib, library_path
from .assembly import Analysis, Assembly, Options, StepInfo
from .errors import KinError, ModelFormatError  # noqa: F401
from . import errors  # noqa: F401
from .model_json import load_json, load_model, to_json  # noqa: F401

__version__ = ".".join(map(str, VERSION))
Assembly.from_json = staticmethod(load_json)
Assembly.to_json = to_json

__all__ = ["Assembly", "Analysis", "Options", "StepInfo", "KinError", "ModelFormatError", "errors",
           "load_json", "load_model", "to_json", "lib", "library_path", "__version__"]
