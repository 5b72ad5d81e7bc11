"""Following a kinematic path: options, steps, direction, relaxation.

`PathMixin` holds the path methods of `libkin.Assembly` (paper Section 3.2:
the predictor-corrector step along the single internal mechanism).
"""
from __future__ import annotations

import dataclasses
import math
import numbers
from typing import Any, Iterator, Optional

import numpy as np
import numpy.typing as npt

from .._native._arrays import as_c_array, read_ptr, write_ptr
from ._base import AssemblyBase, FloatArray
from .._native._lib import ffi, lib, new_struct
from ..errors import ArgumentTypeError, InvalidArgumentError


@dataclasses.dataclass(frozen=True)
class StepInfo:
    """What one predictor-corrector step did (kin_step_info in kin_path.h).

    Attributes
    ----------
    l : float
        Signed path length after the step (length unit).
    delta : float
        Step amplitude used (after any halvings).
    v_r : float
        Lowest non-zero singular value of H at the new point (an upper-bound
        estimate in the LU factorization mode).
    residual : float
        Largest bar strain max |L - L0| / L0 at the new point.
    cos_turn : float
        Cosine between the mechanisms before and after the step.
    iterations, halvings, factorizations : int
        Corrector iterations, step halvings and matrix factorizations used.
    m_internal : int
        Internal mechanisms at the new point.
    strain_floor : float
        The strain the input allows: the larger of the path start's own
        strain and sqrt(dim) * `Options.coord_resolution` / shortest rest
        length (rest lengths from rounded coordinates carry that much).
    tol_used : float
        The corrector's strain tolerance in effect:
        max(`Options.corrector_tol`, `strain_floor`).
    """

    l: float
    delta: float
    v_r: float
    residual: float
    cos_turn: float
    iterations: int
    halvings: int
    factorizations: int
    m_internal: int
    strain_floor: float = 0.0
    tol_used: float = 0.0


@dataclasses.dataclass
class Options:
    """Tolerances of a handle (kin_options; see ``include/libkin/kin_path.h``).

    Attributes
    ----------
    rank_tol : float
        Singular values below ``rank_tol * v_max`` count as zero.
    corrector_tol : float
        The corrector stops at this strain and relative correction.
    corrector_max_iter : int
        Corrector iterations before a step is retried smaller.
    step_fraction : float
        Largest step as a fraction of the RMS bar length.
    max_halvings : int
        Retries of a failed step, each with half the amplitude.
    direction_tol : float
        Smallest cosine between the mechanisms before and after a step.
    max_correction : float
        Largest correction relative to the step before it is retried.
    factorization : int
        0 = ``lib.KIN_STEP_SVD`` (default: the full SVD analysis of every
        point); 1 = ``lib.KIN_STEP_LU`` (LU/QR of the bordered matrix, the
        SVD only near a bifurcation: the same points to rounding for a
        fraction of the cost; `StepInfo.v_r` is then an upper-bound estimate);
        2 = ``lib.KIN_STEP_SPARSE`` (the LU mode with a sparse LU, SuiteSparse
        KLU: for large structures).
    step_control : int
        0 = ``lib.KIN_STEP_CONTROL_MODE`` (default: automatic steps in the LU
        modes halve a stalling chord before paying for Newton); 1 =
        ``lib.KIN_STEP_CONTROL_SHARED`` (the SVD mode's amplitudes in every mode).
    coord_resolution : float
        How finely the input coordinates were given (length unit, e.g. 1e-6
        for 6 decimals; 0 = exact, the default). The corrector does not ask
        for less strain than rounding that fine leaves in rest lengths taken
        from the coordinates (`StepInfo.strain_floor`). `read_fold` sets it
        from the file's decimals.
    """

    rank_tol: float = 1e-9
    corrector_tol: float = 1e-12
    corrector_max_iter: int = 60
    step_fraction: float = 0.1
    max_halvings: int = 12
    direction_tol: float = 0.9
    max_correction: float = 0.5
    factorization: int = 0
    step_control: int = 0
    coord_resolution: float = 0.0


_OPTION_FIELDS = [f.name for f in dataclasses.fields(Options)]


class PathMixin(AssemblyBase):
    """Path following methods of `libkin.Assembly`."""

    @property
    def options(self) -> Options:
        """The handle's tolerances (a copy; assign an `Options` to change them).

        Assigning a value outside its domain raises `InvalidArgumentError`,
        anything but an `Options` `ArgumentTypeError`.
        """
        o = new_struct("kin_options")
        self._check(lib.kin_get_options(self._h, o))
        return Options(**{k: getattr(o, k) for k in _OPTION_FIELDS})

    @options.setter
    def options(self, value: Options) -> None:
        if not isinstance(value, Options):
            raise ArgumentTypeError(f"options: expected a libkin.Options, got {type(value).__name__}")
        o = new_struct("kin_options")
        for k in _OPTION_FIELDS:
            setattr(o, k, getattr(value, k))
        self._check(lib.kin_set_options(self._h, o), "options")

    def step(self, delta: float = 0.0) -> StepInfo:
        """One predictor-corrector step along the path.

        Parameters
        ----------
        delta : float, optional
            Step amplitude (length unit); 0 = the largest allowed
            (`Options.step_fraction`), negative = backwards.

        Returns
        -------
        StepInfo
            What the step did.

        Raises
        ------
        InvalidArgumentError
            `delta` is not a finite number.
        AtBifurcationError, MultipleMechanismsError
            Several internal mechanisms here: call `set_direction` first.
        NoMechanismError
            The assembly cannot move.
        NotConvergedError, PathJumpError
            Every retry failed; the assembly is unchanged.
        """
        value: object = delta  # any real number: float, int, numpy scalars
        if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value):
            raise InvalidArgumentError(f"delta: expected a finite number, got {delta!r}")
        info = new_struct("kin_step_info")
        self._check(lib.kin_step(self._h, float(delta), info), "step")
        return StepInfo(info.l, info.delta, info.v_r, info.residual, info.cos_turn,
                        info.iterations, info.halvings, info.factorizations, info.m_internal,
                        info.strain_floor, info.tol_used)

    def follow(self, steps: Optional[int] = None, length: Optional[float] = None, delta: float = 0.0,
               progress: bool = False) -> Iterator[StepInfo]:
        """Follow the path step by step.

        Parameters
        ----------
        steps : int, optional
            Number of steps to take.
        length : float, optional
            Stop once the path length has grown by this much.
        delta : float, optional
            Step amplitude, as in `step`.
        progress : bool, optional
            Show a progress bar (needs tqdm: ``pip install 'libkin[progress]'``).

        Yields
        ------
        StepInfo
            One per step.

        Raises
        ------
        InvalidArgumentError
            Neither `steps` nor `length` is given.
        KinError
            As `step`; the steps already yielded stand.
        """
        if steps is None and length is None:
            raise InvalidArgumentError("follow: give steps or length")
        start = self.path_length
        bar: Any = None
        if progress:
            try:
                from tqdm import tqdm
                bar = tqdm(total=steps if steps is not None else float(length or 0.0),
                           unit="step" if steps else "len")
            except ImportError:
                bar = None
        k = 0
        try:
            while (steps is None or k < steps) and (length is None or abs(self.path_length - start) < length):
                info = self.step(delta)
                k += 1
                if bar is not None:
                    bar.update(1 if steps is not None else abs(info.l - start) - bar.n)
                yield info
        finally:
            if bar is not None:
                bar.close()

    @property
    def path_length(self) -> float:
        """Signed path length travelled since the last reset (sum of step chords)."""
        return float(lib.kin_path_length(self._h))

    def set_direction(self, direction: npt.ArrayLike) -> None:
        """Choose the direction of motion, e.g. at a bifurcation.

        Parameters
        ----------
        direction : array_like, shape (nfree,)
            A first-order mechanism, e.g. ``internal_mechanisms @ beta``.

        Raises
        ------
        InvalidArgumentError
            Wrong length, or not a first-order mechanism here.
        """
        arr = as_c_array(direction, np.float64, (self.nfree,), "direction")
        self._check(lib.kin_path_set_direction(self._h, read_ptr(arr, "double *"), arr.size), "direction")

    def tangent(self) -> FloatArray:
        """The oriented unit tangent the next step uses.

        Returns
        -------
        ndarray, shape (nfree,)
            The tangent.

        Raises
        ------
        AtBifurcationError
            Several internal mechanisms and no direction chosen.
        """
        out = np.empty(self.nfree)
        self._check(lib.kin_get_tangent(self._h, write_ptr(out, "double *"), self.nfree), "tangent")
        return out

    def relax(self, max_iter: int = 100) -> float:
        """Move to a nearby strain-free configuration (supports stay put).

        Parameters
        ----------
        max_iter : int, optional
            Newton iterations allowed.

        Returns
        -------
        float
            The largest bar strain left.

        Raises
        ------
        NotConvergedError
            No strain-free configuration was reached; the assembly is unchanged.
        """
        res = ffi.new("double *")
        self._check(lib.kin_relax(self._h, int(max_iter), res), "relax")
        return float(res[0])

    def reset_path(self) -> None:
        """Forget the path state: path length 0, no direction chosen."""
        self._check(lib.kin_path_reset(self._h))
