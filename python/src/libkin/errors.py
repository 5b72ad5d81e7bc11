"""KinError and one subclass per libkin status code, made from the status
list of the C header (via the generated declarations)."""
from ._cdef import STATUS_NAMES
from ._lib import ffi, lib


class KinError(Exception):
    """A libkin call failed. `.code` is the C status, `.name` its symbol,
    and the message carries the C library's detail."""

    code = -1
    name = "KIN_UNKNOWN"

    def __init__(self, message, code=None):
        super().__init__(message)
        if code is not None:
            self.code = code


class ModelFormatError(KinError, ValueError):
    """A JSON model (or a Python model description) is malformed; the message
    names the field and position."""

    name = "KIN_EINVAL"
    code = 2


def _class_name(name):
    words = name[len("KIN_E"):].lower().split("_")
    special = {"null": "NullPointer", "inval": "InvalidArgument", "dim": "Dimension",
               "joint": "JointIndex", "selfbar": "SelfBar", "dupbar": "DuplicateBar",
               "geom": "Geometry", "nofree": "NoFreeCoordinates", "nomem": "OutOfMemory",
               "lapack": "Lapack", "arg": "Argument", "conv": "Convergence",
               "notconverged": "NotConverged", "pathjump": "PathJump",
               "bifurcation": "AtBifurcation", "nomech": "NoMechanism", "range": "Range",
               "state": "State", "notfound": "NotFound", "gsl": "Gsl"}
    return "".join(special.get(w, w.capitalize()) for w in words) + "Error"


_BY_CODE = {}
for _code, _name in enumerate(STATUS_NAMES):
    if _name == "KIN_OK":
        continue
    _value = getattr(lib, _name)
    _cls = type(_class_name(_name), (KinError,), {"code": _value, "name": _name,
                                                    "__doc__": f"libkin status {_name}."})
    globals()[_cls.__name__] = _cls
    _BY_CODE[_value] = _cls

__all__ = ["KinError", "ModelFormatError"] + [c.__name__ for c in _BY_CODE.values()]


def error_class(code):
    """The KinError subclass of a status code."""
    return _BY_CODE.get(code, KinError)


def check(rc, handle=None, what=""):
    """Raise the KinError subclass of rc (with the handle's detail), or return."""
    if rc == 0:
        return
    detail = ""
    if handle is not None and handle != ffi.NULL:
        detail = ffi.string(lib.kin_last_error(handle)).decode()
    base = ffi.string(lib.kin_strerror(rc)).decode()
    msg = detail if detail else base
    if what:
        msg = f"{what}: {msg}"
    raise error_class(rc)(msg, rc)
