"""Detecting and locating the next bifurcation along a path (``docs/locate.md``).

`LocatingMixin` holds the locating methods of `libkin.Assembly`.
"""
from __future__ import annotations

import dataclasses

from ._base import AssemblyBase
from ._lib import ffi, lib, new_struct
from ._progress import Progress, reporting
from .errors import InvalidArgumentError

_METHODS = {"fast": "KIN_LOCATE_FAST", "paper": "KIN_LOCATE_PAPER", "illinois": "KIN_LOCATE_ILLINOIS"}


@dataclasses.dataclass(frozen=True)
class LocateInfo:
    """How `LocatingMixin.locate` found a bifurcation (kin_locate_info).

    Attributes
    ----------
    event : int
        0 none, 1 sign change of the test function, 2 the paper's switch
        rule, 3 a step landed on it, 4 v_r turned near zero without a sign change.
    located : bool
        Whether the bifurcation was located to the tolerance.
    steps : int
        Path steps before detection.
    factorizations, forward : int
        Factorizations and forward calculations after detection.
    v_r, v_r_rel : float
        The vanishing singular value, absolute and relative to v_max.
    distance : float
        Distance moved while locating.
    path_kept : bool
        Whether the located point continues the path it was approached on (eq. 26).
    m_internal, s : int
        Internal mechanisms and self-stresses at the final point.
    zero_order : int
        How many singular values vanish there.
    """

    event: int
    located: bool
    steps: int
    factorizations: int
    forward: int
    v_r: float
    v_r_rel: float
    distance: float
    path_kept: bool
    m_internal: int
    s: int
    zero_order: int = 0


class LocatingMixin(AssemblyBase):
    """Locating methods of `libkin.Assembly`."""

    def locate(self, method: str = "fast", delta: float = 0.0, vr_tol: float = 1e-10,
               max_steps: int = 1000, progress: Progress = None) -> LocateInfo:
        """Follow the path until a bifurcation is detected, and converge onto it.

        Parameters
        ----------
        method : {'fast', 'paper', 'illinois'}, optional
            'fast': Hermite interpolation of the path and of the signed
            vanishing singular value (default); 'paper': the paper's quadratic
            (eq. 23-26); 'illinois': Illinois on the signed test function.
        delta : float, optional
            Step amplitude while following: > 0 forwards, < 0 backwards,
            0 = the largest allowed.
        vr_tol : float, optional
            Located when v_r / v_max is at most this.
        max_steps : int, optional
            Steps to look for a bifurcation.
        progress : None, bool or callable, optional
            Progress in steps and forward calculations (see
            `libkin._progress`); Ctrl-C or a cancel leaves the assembly at the
            last regular point reached on the path.

        Returns
        -------
        LocateInfo
            How the bifurcation was found and located; the assembly is on it.

        Raises
        ------
        InvalidArgumentError
            Unknown `method` (a ValueError).
        NotFoundError
            None found within `max_steps`, or location gave up; the assembly
            stays on the path.
        AtBifurcationError
            The start is itself a bifurcation and no direction was chosen.
        CancelledError
            The `progress` callable asked to stop.
        """
        if method not in _METHODS:
            raise InvalidArgumentError(f"method: expected one of {sorted(_METHODS)}, got {method!r}")
        o = new_struct("kin_locate_options")
        lib.kin_locate_options_default(o)
        o.method = getattr(lib, _METHODS[method])
        o.delta = float(delta)
        o.vr_tol = float(vr_tol)
        o.max_steps = int(max_steps)
        info = new_struct("kin_locate_info")
        with reporting(progress, "locate", "step", self._h):
            rc = lib.kin_locate_next(self._h, o, info)
        self._check(rc, "locate")
        return LocateInfo(info.event, bool(info.located), info.steps, info.factorizations, info.forward,
                          info.v_r, info.v_r_rel, info.distance, bool(info.path_kept), info.m_internal, info.s,
                          info.zero_order)

    def test_function(self) -> float:
        """The signed test function here.

        Returns
        -------
        float
            tau = sign(det [C; t^T; R^T]) * v_r, which changes sign at a
            bifurcation a step passes over.
        """
        tau = ffi.new("double *")
        self._check(lib.kin_test_function(self._h, tau), "test function")
        return float(tau[0])
