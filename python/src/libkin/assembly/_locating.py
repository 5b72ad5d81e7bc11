"""Detecting and locating the next bifurcation along a path (``docs/locate.md``).

`LocatingMixin` holds the locating methods of `libkin.Assembly`.
"""
from __future__ import annotations

import dataclasses
from typing import Any, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

from .._native._arrays import as_c_array, read_ptr
from ._base import AssemblyBase
from ._branch_lines import BranchLines
from .._native._lib import c_string, default_struct, ffi, lib, new_struct
from .._native._progress import Progress, reporting
from ..errors import InvalidArgumentError

#: follow_event(branches=BranchLines, own_branch=k): the most the direction may
#: be off line k (radians)
OWN_BRANCH_TOL = 1e-8

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
    v_r_bound : tuple of float or None
        A proven enclosure at the final point (Arb's ball arithmetic on the
        exact H at the final coordinates, Weyl's bound on the SVD's
        residual): (lo, hi, rel_hi) with lo <= v_r <= hi for the exact
        singular value and rel_hi >= its ratio to the largest; None where it
        was not computed (no dense SVD there).
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
    v_r_bound: Optional[Tuple[float, float, float]] = None
    singular: Optional["SingularProof"] = None


@dataclasses.dataclass(frozen=True)
class SingularProof:
    """A proven exactly singular configuration near a point (kin_prove_singular).

    Krawczyk's test in Arb's ball arithmetic on Moore's extended system
    (docs/locate.md, "Certified bifurcations"). A backward-error theorem:
    where `proven`, the structure whose bar lengths differ from the given
    ones by at most `dlength` is exactly singular at a configuration within
    `distance` (max norm over the free coordinates) of the point; that the
    given structure itself is singular there is not proven.

    Attributes
    ----------
    proven : bool
        The bounds below hold.
    corank : int
        Non-trivial self-stresses at the point; a proof needs at most 1.
    distance, dlength, unique : float
        Bounds (model units) on the distance to the singular configuration
        and on the bar-length change; no other such point within `unique`.
    """

    proven: bool
    corank: int
    distance: float
    dlength: float
    unique: float


def _singular(info: Any) -> SingularProof:
    return SingularProof(bool(info.sing_proven), int(info.sing_corank), float(info.sing_distance),
                         float(info.sing_dlength), float(info.sing_unique))


#: kin_follow_event's events, by enum value
FOLLOW_EVENTS = ("none", "bifurcation", "near-miss", "closed-loop", "length-limit", "step-limit", "failed",
                 "contact", "hinge-closed", "held-rigid", "hinge-reopened")


@dataclasses.dataclass(frozen=True)
class FollowEvent:
    """How `LocatingMixin.follow_event` ended (kin_follow_info, ``docs/follow.md``).

    Attributes
    ----------
    event : str
        'bifurcation' (located; the assembly is on it), 'near-miss' (v_r has a
        non-zero minimum), 'closed-loop' (back at the start), 'length-limit',
        'step-limit', 'failed' (see `status` and `message`) or 'contact' (two
        parts touched: only after `set_contact_events`; `last_contact()`
        names them); with ``hold_hinges``: 'hinge-closed' (a hinge closed
        and is held; the held structure still moves), 'held-rigid' (it
        closed and the held structure has no motion, or the motion asked
        for presses a held hinge through: nothing moved), 'hinge-reopened'
        (the motion opened a held hinge; the hold released).
    status : str
        The C status name ('KIN_OK' unless failed).
    message : str
        The handle's last-error message when failed, else ''.
    steps, forward, factorizations, attempts : int
        Following steps, forward calculations, factorizations, location attempts.
    length : float
        Path length travelled.
    vr_tol_used : float
        The tolerance a bifurcation was located to (vr_tol up to vr_floor;
        a corank-1 point only a relaxed tolerance accepts is decided at the
        minimum of v_r instead). For a near miss whose minimum was located:
        the floor a crossing would leave at that width; the minimum is
        undecided where v_r_rel is not 10 x above it (atlas.tasks.near_verdict).
    v_r_rel : float
        v_r / v_max at the end point.
    m_internal, s : int
        Analysis at the end point.
    zero_order : int
        1 a crossing, 2 a tangency, 0 not estimated.
    path_kept, at_start : bool
        Location stayed on the path; the end point is the start configuration.
    start_distance : float
        |end - start| / RMS rest length.
    tangent_cos : float
        Cosine between the first chord and the branch direction (1 at a regular start).
    cheap_steps, handovers : int
        Steps taken with LU factors only; handovers to the SVD locator.
    return_branch : int
        With `branches`: the branch a return to the start came back along, or -1.
    return_angle, return_gap : float
        That return: the angle (radians) between its direction and that
        branch, and how much farther the next nearest branch is (0.0 without
        a return; inf with one branch).
    min_located : bool
        A near miss ending at the located minimum of v_r / v_max along the
        path (v_r_rel is the value there); False: at the regular point
        before the dip.
    min_width : float
        That minimum's position is known to this path length / RMS rest
        length (0.0 where not located).
    min_evals : int
        Points computed to locate it.
    hinge : int
        'hinge-closed' / 'held-rigid': the first hinge held there;
        'hinge-reopened': the hinge reopened; else -1.
    held : int
        Hinges held at the end point.
    held_m : int
        Motions of the structure with those hinges held (0: rigid), -1 where
        none is held or it was not analysed.
    reopened : int
        Holds the direction released at the start (it opens those hinges).
    samples : numpy.ndarray, shape (k, njoints, dim)
        With ``samples > 0``: configurations the steps reached, evenly spread
        by steps over the path (start and end excluded).
    sample_lengths : numpy.ndarray, shape (k,)
        Their path lengths.
    """

    event: str
    status: str
    message: str
    steps: int
    forward: int
    factorizations: int
    attempts: int
    length: float
    vr_tol_used: float
    v_r_rel: float
    m_internal: int
    s: int
    zero_order: int
    path_kept: bool
    at_start: bool
    start_distance: float
    tangent_cos: float
    cheap_steps: int = 0
    handovers: int = 0
    return_branch: int = -1
    return_angle: float = 0.0
    return_gap: float = 0.0
    samples: Any = None
    sample_lengths: Any = None
    min_located: bool = False
    min_width: float = 0.0
    min_evals: int = 0
    hinge: int = -1
    held: int = 0
    held_m: int = -1
    reopened: int = 0


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
        o = default_struct("kin_locate_options")
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
                          info.zero_order,
                          (info.v_r_lo, info.v_r_hi, info.v_r_rel_hi) if info.v_r_bounded else None,
                          _singular(info) if info.located else None)

    def prove_singular(self) -> SingularProof:
        """Prove an exactly singular configuration near the current point (kin_prove_singular).

        Returns
        -------
        SingularProof
            `proven` False where no proof was found (corank > 1, or no
            simple bifurcation near); the configuration is not changed.
        """
        info = new_struct("kin_locate_info")
        self._check(lib.kin_prove_singular(self._h, info), "prove_singular")
        return _singular(info)

    def follow_event(self, direction: Optional[npt.ArrayLike] = None, vr_tol: float = 1e-10,
                     vr_floor: float = 1e-6, delta: float = 0.0, max_steps: int = 1000,
                     max_length: float = 0.0, loop_tol: float = 1e-2,
                     progress: Progress = None, branches: Union[None, npt.ArrayLike, BranchLines] = None,
                     samples: int = 0, steps_mode: str = "cheap", own_branch: Optional[int] = None,
                     hold_hinges: bool = False, hold_rate_tol: float = 1e-6) -> FollowEvent:
        """Follow the path to its next event and say what it was (kin_follow_event).

        Parameters
        ----------
        direction : array_like, shape (nfree,), optional
            None at a regular point (the current orientation); at a
            bifurcation the branch direction, e.g. ``U_m @ beta`` (times -1
            for the other sign); at a regular point it orients the path.
        vr_tol, vr_floor : float, optional
            A bifurcation is located to vr_tol, or where that is out of reach
            to the best accuracy up to vr_floor (reported as `vr_tol_used`).
        delta : float, optional
            Step amplitude (0 = automatic).
        max_steps : int, optional
            Step budget.
        max_length : float, optional
            Path-length budget (0 = none).
        loop_tol : float, optional
            Closed-loop tolerance, relative to the RMS rest length.
        progress : None, bool or callable, optional
            Progress in steps (see `libkin._progress`).
        branches : array_like, shape (nbranch, nfree), optional
            At a bifurcation: every real branch direction of the start (e.g.
            ``U_m @ beta`` for each solution); a return to the start is then a
            closed loop only along `direction`'s own branch, and located as a
            bifurcation along any other (kin_follow_event_ex). Or a
            `BranchLines` (many lines checked once for many follows: the
            decision made by `BranchLines.nearest`, the same) with
            `own_branch`.
        samples : int, optional
            Room for this many configurations recorded along the path
            (`FollowEvent.samples`).
        steps_mode : {'cheap', 'svd'}, optional
            LU steps on regular stretches and the SVD locator near events
            (default: the same events and points, ``docs/follow.md``), or an
            SVD at every step.
        own_branch : int, optional
            With `branches` a `BranchLines`: the index of `direction`'s own
            line among them (`direction` along it, to OWN_BRANCH_TOL rad).
        hold_hinges : bool, optional
            Hold hinges that close closed, and release them only where the
            motion opens them (needs `set_contact_events` with hinge contact
            on; ``docs/contact.md``, "Held hinges"). The holds stay with the
            configuration: the next follow from it goes on with them.
        hold_rate_tol : float, optional
            A held hinge's angle rate (x the RMS rest length) below this is zero.

        Returns
        -------
        FollowEvent
            The event; a failure after following started is returned as
            event 'failed' (the assembly at the last regular point reached).

        Raises
        ------
        InvalidArgumentError
            Options or `direction` invalid (a ValueError).
        AtBifurcationError
            At a bifurcation without a direction.
        CancelledError
            The `progress` callable asked to stop (or Ctrl-C).
        """
        o = default_struct("kin_follow_options")
        o.vr_tol, o.vr_floor, o.delta = float(vr_tol), float(vr_floor), float(delta)
        o.max_steps, o.max_length, o.loop_tol = int(max_steps), float(max_length), float(loop_tol)
        if steps_mode not in ("cheap", "svd"):
            raise InvalidArgumentError(f"steps_mode must be 'cheap' or 'svd', not {steps_mode!r}")
        o.steps_mode = lib.KIN_FOLLOW_STEPS_CHEAP if steps_mode == "cheap" else lib.KIN_FOLLOW_STEPS_SVD
        o.hold_hinges, o.hold_rate_tol = int(bool(hold_hinges)), float(hold_rate_tol)
        d = ffi.NULL
        if direction is not None:
            arr = as_c_array(direction, np.float64, (self.nfree,), "direction")
            d = read_ptr(arr, "double *")
        br, nbr, lines = ffi.NULL, 0, None
        if isinstance(branches, BranchLines):
            lines = branches
            k = own_branch
            if not isinstance(k, (int, np.integer)) or not 0 <= k < lines.shape[0]:
                raise InvalidArgumentError(f"own_branch: expected an index in [0, {lines.shape[0]}), got {k!r}")
            if lines.shape[1] != self.nfree:
                raise InvalidArgumentError(f"branches must have shape (nbranch, {self.nfree}), not {lines.shape}")
            if direction is None or not float(lines.angle(direction, int(k))) <= OWN_BRANCH_TOL:
                raise InvalidArgumentError(f"direction is not along branch line own_branch = {k}")
            o.return_fn, o.return_own = lines.c_fn, int(k)
        elif own_branch is not None:
            raise InvalidArgumentError("own_branch is only for branches given as BranchLines")
        elif branches is not None:
            barr = np.asarray(branches, dtype=np.float64)
            if barr.ndim != 2 or barr.shape[1] != self.nfree:
                raise InvalidArgumentError(f"branches must have shape (nbranch, {self.nfree}), not {barr.shape}")
            barr = as_c_array(barr, np.float64, barr.shape, "branches")
            br, nbr = read_ptr(barr, "double *"), int(barr.shape[0])
        ns = int(samples)
        if ns < 0:
            raise InvalidArgumentError(f"samples must be >= 0, not {samples}")
        nj, dim = self.njoints, self.dim
        sbuf = np.zeros((max(ns, 1), nj, dim))
        lbuf = np.zeros(max(ns, 1))
        count = ffi.new("int *")
        info = new_struct("kin_follow_info")
        with reporting(progress, "follow", "step", self._h):
            rc = lib.kin_follow_event_ex(self._h, d, o, br, nbr, read_ptr(sbuf, "double *"),
                                         read_ptr(lbuf, "double *"), ns, count, info)
        event = FOLLOW_EVENTS[info.event] if 0 <= info.event < len(FOLLOW_EVENTS) else str(info.event)
        hook_error = lines.take_error() if lines is not None else None
        if hook_error is not None:
            raise hook_error
        if rc != lib.KIN_OK and (info.event != lib.KIN_FOLLOW_FAILED or rc == lib.KIN_ECANCELLED):
            self._check(rc, "follow_event")
        message = c_string(lib.kin_last_error(self._h)) if rc != lib.KIN_OK else ""
        return FollowEvent(event, c_string(lib.kin_status_name(rc)), message, info.steps, info.forward,
                           info.factorizations, info.attempts, info.length, info.vr_tol_used, info.v_r_rel,
                           info.m_internal, info.s, info.zero_order, bool(info.path_kept), bool(info.at_start),
                           info.start_distance, info.tangent_cos, info.cheap_steps, info.handovers,
                           info.return_branch, info.return_angle, info.return_gap, sbuf[:count[0]].copy(),
                           lbuf[:count[0]].copy(), bool(info.min_located), float(info.min_width),
                           int(info.min_evals), int(info.hinge), int(info.held), int(info.held_m),
                           int(info.reopened))

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
