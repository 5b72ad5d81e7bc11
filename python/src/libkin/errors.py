"""Exceptions raised by libkin: `KinError` and one subclass per C status code.

Every class is declared here (so IDEs, type checkers and ``help()`` see it)
and carries the C status as ``.code`` and its symbol as ``.name``. Each one
also derives from the built-in exception that says what kind of failure it
is, so ``except ValueError`` catches bad input whether Python or C found it:

=========================  ======================  ====================
class                      C status                built-in base
=========================  ======================  ====================
NullPointerError           KIN_ENULL               ValueError
InvalidArgumentError       KIN_EINVAL              ValueError
DimensionError             KIN_EDIM                ValueError
JointIndexError            KIN_EJOINT              IndexError
SelfBarError               KIN_ESELFBAR            ValueError
DuplicateBarError          KIN_EDUPBAR             ValueError
GeometryError              KIN_EGEOM               ValueError
NoFreeCoordinatesError     KIN_ENOFREE             ValueError
OutOfMemoryError           KIN_ENOMEM              MemoryError
LapackArgumentError        KIN_ELAPACK_ARG         RuntimeError
LapackConvergenceError     KIN_ELAPACK_CONV        ArithmeticError
NotConvergedError          KIN_ENOTCONVERGED       ArithmeticError
PathJumpError              KIN_EPATHJUMP           ArithmeticError
AtBifurcationError         KIN_EBIFURCATION        RuntimeError
NoMechanismError           KIN_ENOMECH             RuntimeError
RangeError                 KIN_ERANGE              IndexError
StateError                 KIN_ESTATE              RuntimeError
NotFoundError              KIN_ENOTFOUND           RuntimeError
GslError                   KIN_EGSL                ArithmeticError
CancelledError             KIN_ECANCELLED          (KinError only)
MultipleMechanismsError    KIN_EMULTIDOF           RuntimeError
LimitError                 KIN_ELIMIT              ValueError
FileAccessError            KIN_EIO                 OSError
ModelFormatError           KIN_EFORMAT             ValueError
=========================  ======================  ====================

Errors found in Python before C is called use the same classes: a wrong
shape or an unknown option name raises `InvalidArgumentError` (a
ValueError), a non-numeric array or an argument of the wrong kind
`ArgumentTypeError` (an InvalidArgumentError and a TypeError), a malformed
JSON model `ModelFormatError`.

``tests/test_errors_py.py`` checks that the classes cover exactly the codes of
the C header's status list, so the two cannot drift apart.
"""
from __future__ import annotations

from typing import Dict, Optional, Type

__all__ = [
    "KinError", "NullPointerError", "InvalidArgumentError", "ArgumentTypeError", "DimensionError",
    "JointIndexError", "SelfBarError", "DuplicateBarError", "GeometryError", "NoFreeCoordinatesError",
    "OutOfMemoryError", "LapackArgumentError", "LapackConvergenceError", "NotConvergedError",
    "PathJumpError", "AtBifurcationError", "NoMechanismError", "RangeError", "StateError",
    "NotFoundError", "GslError", "CancelledError", "MultipleMechanismsError", "LimitError",
    "FileAccessError", "ModelFormatError", "error_class", "check",
]


class KinError(Exception):
    """A libkin operation failed.

    Parameters
    ----------
    message : str
        What went wrong, with the C library's detail where C found it.
    code : int, optional
        The C status; defaults to the class's own code.

    Attributes
    ----------
    code : int
        The C status code (``libkin.lib.KIN_E...``); -1 for the base class.
    name : str
        The status's symbol, e.g. ``"KIN_EINVAL"``.
    """

    code: int = -1
    name: str = "KIN_UNKNOWN"

    def __init__(self, message: str, code: Optional[int] = None) -> None:
        super().__init__(message)
        if code is not None:
            self.code = code


class NullPointerError(KinError, ValueError):
    """A required argument was missing (KIN_ENULL)."""

    code = 1
    name = "KIN_ENULL"


class InvalidArgumentError(KinError, ValueError):
    """An argument has a value the call does not accept (KIN_EINVAL): a
    wrong shape, a value out of its domain, an unknown option name."""

    code = 2
    name = "KIN_EINVAL"


class ArgumentTypeError(InvalidArgumentError, TypeError):
    """An argument is of the wrong kind: not numeric, ragged, or not the
    expected type (KIN_EINVAL, found in Python)."""


class DimensionError(KinError, ValueError):
    """The dimension is not 2 or 3 (KIN_EDIM)."""

    code = 3
    name = "KIN_EDIM"


class JointIndexError(KinError, IndexError):
    """A bar names a joint that does not exist (KIN_EJOINT)."""

    code = 4
    name = "KIN_EJOINT"


class SelfBarError(KinError, ValueError):
    """A bar connects a joint to itself (KIN_ESELFBAR)."""

    code = 5
    name = "KIN_ESELFBAR"


class DuplicateBarError(KinError, ValueError):
    """Two bars connect the same pair of joints (KIN_EDUPBAR)."""

    code = 6
    name = "KIN_EDUPBAR"


class GeometryError(KinError, ValueError):
    """A non-finite coordinate or length, or a zero-length bar (KIN_EGEOM)."""

    code = 7
    name = "KIN_EGEOM"


class NoFreeCoordinatesError(KinError, ValueError):
    """Every coordinate is a support: nothing can move (KIN_ENOFREE)."""

    code = 8
    name = "KIN_ENOFREE"


class OutOfMemoryError(KinError, MemoryError):
    """The C library could not allocate its workspace (KIN_ENOMEM)."""

    code = 9
    name = "KIN_ENOMEM"


class LapackArgumentError(KinError, RuntimeError):
    """LAPACK rejected an argument (info < 0): an internal error (KIN_ELAPACK_ARG)."""

    code = 10
    name = "KIN_ELAPACK_ARG"


class LapackConvergenceError(KinError, ArithmeticError):
    """A LAPACK factorization did not converge (info > 0, KIN_ELAPACK_CONV)."""

    code = 11
    name = "KIN_ELAPACK_CONV"


class NotConvergedError(KinError, ArithmeticError):
    """An iteration (corrector, relaxation) did not converge (KIN_ENOTCONVERGED)."""

    code = 12
    name = "KIN_ENOTCONVERGED"


class PathJumpError(KinError, ArithmeticError):
    """A step would leave the path: the mechanism direction jumped (KIN_EPATHJUMP)."""

    code = 13
    name = "KIN_EPATHJUMP"


class AtBifurcationError(KinError, RuntimeError):
    """The assembly is at a bifurcation: choose a direction first (KIN_EBIFURCATION)."""

    code = 14
    name = "KIN_EBIFURCATION"


class NoMechanismError(KinError, RuntimeError):
    """The assembly has no internal mechanism: it cannot move (KIN_ENOMECH)."""

    code = 15
    name = "KIN_ENOMECH"


class RangeError(KinError, IndexError):
    """A size or index is out of range (KIN_ERANGE)."""

    code = 16
    name = "KIN_ERANGE"


class StateError(KinError, RuntimeError):
    """The operation is not valid in the current state, e.g. on a closed
    assembly or away from a bifurcation (KIN_ESTATE)."""

    code = 17
    name = "KIN_ESTATE"


class NotFoundError(KinError, RuntimeError):
    """No bifurcation was located: the locator gave up (KIN_ENOTFOUND)."""

    code = 18
    name = "KIN_ENOTFOUND"


class GslError(KinError, ArithmeticError):
    """GSL reported an error (KIN_EGSL)."""

    code = 19
    name = "KIN_EGSL"


class CancelledError(KinError):
    """The caller's progress callback asked to stop (KIN_ECANCELLED)."""

    code = 20
    name = "KIN_ECANCELLED"


class MultipleMechanismsError(KinError, RuntimeError):
    """Several internal mechanisms at a regular point: choose a direction (KIN_EMULTIDOF)."""

    code = 21
    name = "KIN_EMULTIDOF"


class LimitError(KinError, ValueError):
    """The problem is larger than the limit set for this call (KIN_ELIMIT)."""

    code = 22
    name = "KIN_ELIMIT"


class FileAccessError(KinError, OSError):
    """A file could not be opened, read or written (KIN_EIO)."""

    code = 23
    name = "KIN_EIO"


class ModelFormatError(KinError, ValueError):
    """A model file or model description is malformed; the message names the
    field and its position (KIN_EFORMAT)."""

    code = 24
    name = "KIN_EFORMAT"


#: The class of each C status code (every code but KIN_OK).
BY_CODE: Dict[int, Type[KinError]] = {
    cls.code: cls
    for cls in (NullPointerError, InvalidArgumentError, DimensionError, JointIndexError, SelfBarError,
                DuplicateBarError, GeometryError, NoFreeCoordinatesError, OutOfMemoryError,
                LapackArgumentError, LapackConvergenceError, NotConvergedError, PathJumpError,
                AtBifurcationError, NoMechanismError, RangeError, StateError, NotFoundError, GslError,
                CancelledError, MultipleMechanismsError, LimitError, FileAccessError, ModelFormatError)
}


def error_class(code: int) -> Type[KinError]:
    """The exception class of a C status code.

    Parameters
    ----------
    code : int
        A libkin status (non-zero).

    Returns
    -------
    type
        The `KinError` subclass of `code`, or `KinError` itself for a code
        this package does not know.
    """
    return BY_CODE.get(code, KinError)


def check(rc: int, handle: object = None, what: str = "") -> None:
    """Raise the exception of a C status, or return if it is KIN_OK.

    Parameters
    ----------
    rc : int
        The status a libkin call returned.
    handle : cffi pointer to kin_assembly, optional
        The handle the call used: its last-error message (with detail)
        becomes the exception's message.
    what : str, optional
        A prefix naming the operation.

    Raises
    ------
    KinError
        The subclass of `rc` (see `error_class`), unless `rc` is 0.
    """
    if rc == 0:
        return
    from ._native._lib import c_string, ffi, lib

    detail = ""
    if handle is not None and handle != ffi.NULL:
        detail = c_string(lib.kin_last_error(handle))
    msg = detail if detail else c_string(lib.kin_strerror(rc))
    if what:
        msg = f"{what}: {msg}"
    raise error_class(rc)(msg, rc)
