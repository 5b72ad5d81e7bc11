"""The handle an Assembly owns, the model it holds, and its first-order analysis.

`AssemblyBase` is the part of `libkin.Assembly` every other part builds on:
the lifetime of the C handle, the model's geometry and supports, and the
SVD analysis of the equilibrium matrix H. The path, branching and locating
methods are mixins over it (``_path.py``, ``_branching.py``, ``_locating.py``).

Units: coordinates and lengths are in the caller's length unit; singular
values and mechanisms are dimensionless (H holds direction cosines);
mechanism vectors have one entry per free coordinate, ordered joint by joint
and x, y, z within a joint (see `AssemblyBase.free_index`).
"""
from __future__ import annotations

import dataclasses
from typing import Any, List, Optional, Type, TypeVar

import numpy as np
import numpy.typing as npt

from .._native._arrays import as_c_array, read_ptr, write_ptr
from .._native._lib import ffi, lib, new_struct
from ..errors import StateError, check

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int32]
BoolArray = npt.NDArray[np.bool_]

_Self = TypeVar("_Self", bound="AssemblyBase")


@dataclasses.dataclass(frozen=True)
class Analysis:
    """First-order analysis (paper Section 3.1) of one configuration.

    Attributes
    ----------
    rank : int
        Rank r of the equilibrium matrix H (nfree x nbars).
    m : int
        Number of mechanisms, nfree - r.
    m_rigid, m_internal : int
        Rigid-body mechanisms (rigid motions that keep every support fixed)
        and internal ones; m = m_rigid + m_internal.
    s : int
        Number of states of self-stress, nbars - r.
    v_max, v_r : float
        Largest and lowest non-zero singular value of H.
    singular_values : ndarray, shape (min(nfree, nbars),) or (0,)
        Singular values of H, descending; empty after an analysis by the
        sparse route (``route == "sparse"``), which computes v_max and v_r
        but not the whole spectrum.
    internal_mechanisms : ndarray, shape (nfree, m_internal)
        Orthonormal internal mechanisms U_m (Fortran-ordered).
    rigid_mechanisms : ndarray, shape (nfree, m_rigid)
        Orthonormal rigid-body mechanisms.
    self_stresses : ndarray, shape (nbars, s)
        Orthonormal states of self-stress W_s.
    s_trivial : int
        Of the s, those of the bars with no free coordinate at either end
        (each alone in tension; a zero column of H at every configuration).
        The second order, `branches` and the explorer use the
        s - s_trivial others (``docs/generality.md``, "Bars between fixed
        joints").
    route : str
        Which computation answered (kin_get_analysis_route): ``"dense"``, the
        SVD of H (every mode; in the sparse mode, ``factorization="sparse"``,
        where it fits in memory and costs less than the sparse analysis), or
        ``"sparse"``, the sparse analysis.
    """

    rank: int
    m: int
    m_rigid: int
    m_internal: int
    s: int
    v_max: float
    v_r: float
    singular_values: FloatArray
    internal_mechanisms: FloatArray
    rigid_mechanisms: FloatArray
    self_stresses: FloatArray
    s_trivial: int = 0
    route: str = "dense"


class AssemblyBase:
    """The C handle of an assembly, its model and its first-order analysis.

    Not used on its own: `libkin.Assembly` is this class with the path,
    branching and locating methods.
    """

    labels: Optional[List[str]]
    name: Optional[str]
    _p: Any

    # ---- lifetime ------------------------------------------------------
    def _adopt(self, ptr: Any) -> None:
        self._p = ffi.gc(ptr, lib.kin_assembly_free)

    @classmethod
    def _from_handle(cls: Type[_Self], ptr: Any, labels: Optional[List[str]] = None,
                     name: Optional[str] = None) -> _Self:
        obj = cls.__new__(cls)
        obj._adopt(ptr)
        obj.labels = labels
        obj.name = name
        return obj

    def close(self) -> None:
        """Free the C handle now; closing twice is harmless.

        Any further use of the assembly raises `StateError`. The handle is
        also freed when the object is garbage-collected, or on leaving a
        ``with`` block.
        """
        if getattr(self, "_p", None) is not None:
            ffi.release(self._p)
            self._p = None

    def __enter__(self: _Self) -> _Self:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    @property
    def _h(self) -> Any:
        p = getattr(self, "_p", None)
        if p is None:
            raise StateError("the assembly is closed")
        return p

    def _check(self, rc: int, what: str = "") -> None:
        check(rc, self._h, what)

    def __repr__(self) -> str:
        if getattr(self, "_p", None) is None:
            return "<libkin.Assembly (closed)>"
        return (f"<libkin.Assembly {self.name or ''} dim={self.dim} joints={self.njoints} "
                f"bars={self.nbars} free={self.nfree}>")

    # ---- model ---------------------------------------------------------
    @property
    def dim(self) -> int:
        """Dimension of the assembly: 2 or 3."""
        return int(lib.kin_dim(self._h))

    @property
    def njoints(self) -> int:
        """Number of joints."""
        return int(lib.kin_njoints(self._h))

    @property
    def nbars(self) -> int:
        """Number of bars = columns of H = length of a self-stress."""
        return int(lib.kin_nbars(self._h))

    @property
    def nfree(self) -> int:
        """Number of free coordinates = rows of H = length of a mechanism."""
        return int(lib.kin_nfree(self._h))

    def free_index(self, joint: int, axis: int) -> int:
        """The row of H of one coordinate.

        Parameters
        ----------
        joint : int
            Joint index (0-based).
        axis : int
            0 = x, 1 = y, 2 = z.

        Returns
        -------
        int
            The row of H (the entry of a mechanism vector), or -1 if that
            coordinate is a support or the indices are out of range.
        """
        return int(lib.kin_free_index(self._h, int(joint), int(axis)))

    def free_map(self) -> npt.NDArray[np.int_]:
        """The row of H of every coordinate.

        Returns
        -------
        ndarray of int, shape (njoints, dim)
            Row of H of each coordinate, -1 where it is a support.
        """
        return np.array([[self.free_index(j, c) for c in range(self.dim)] for j in range(self.njoints)])

    @property
    def coords(self) -> FloatArray:
        """Current joint coordinates, (njoints, dim) float64 (a copy).

        Assigning moves the free coordinates; a support that would move
        raises `InvalidArgumentError`, a wrong shape `InvalidArgumentError`
        (both ValueErrors). The path state is reset.
        """
        out = np.empty((self.njoints, self.dim))
        self._check(lib.kin_get_coords(self._h, write_ptr(out, "double *")))
        return out

    @coords.setter
    def coords(self, value: npt.ArrayLike) -> None:
        arr = as_c_array(value, np.float64, (self.njoints, self.dim), "coords")
        self._check(lib.kin_set_coords(self._h, read_ptr(arr, "double *")), "set coords")

    @property
    def bars(self) -> IntArray:
        """Joint indices of each bar, (nbars, 2) int32 (a copy)."""
        out = np.empty((self.nbars, 2), dtype=np.int32)
        self._check(lib.kin_get_bars(self._h, write_ptr(out, "int *")))
        return out

    @property
    def rest_lengths(self) -> FloatArray:
        """The lengths the bars keep, (nbars,) float64."""
        out = np.empty(self.nbars)
        self._check(lib.kin_get_rest_lengths(self._h, write_ptr(out, "double *")))
        return out

    @property
    def lengths(self) -> FloatArray:
        """Current bar lengths, (nbars,) float64."""
        out = np.empty(self.nbars)
        self._check(lib.kin_get_lengths(self._h, write_ptr(out, "double *")))
        return out

    @property
    def fixed(self) -> BoolArray:
        """Supports, (njoints, dim) bool: True where the coordinate is fixed."""
        out = np.empty((self.njoints, self.dim), dtype=np.uint8)
        self._check(lib.kin_get_fixed(self._h, write_ptr(out, "unsigned char *")))
        return out.astype(bool)

    @property
    def max_strain(self) -> float:
        """Largest bar strain max |L - L0| / L0 (dimensionless)."""
        return float(lib.kin_max_strain(self._h))

    def equilibrium_matrix(self) -> FloatArray:
        """The equilibrium matrix H of the current configuration.

        Returns
        -------
        ndarray, shape (nfree, nbars), Fortran-ordered
            Column k holds bar k's direction cosines at its two joints.
        """
        out = np.empty((self.nfree, self.nbars), order="F")
        self._check(lib.kin_get_equilibrium_matrix(self._h, write_ptr(out, "double *"), self.nfree))
        return out

    # ---- analysis --------------------------------------------------------
    def analyse(self) -> Analysis:
        """Factorize H here (SVD) and report rank, mechanisms and self-stresses.

        Returns
        -------
        Analysis
            Counts, singular values, mechanisms and self-stresses.

        Raises
        ------
        LapackConvergenceError
            The SVD did not converge (an ArithmeticError).
        StateError
            The assembly is closed.
        """
        an = new_struct("kin_analysis")
        self._check(lib.kin_analyse(self._h, an), "analyse")
        return self._analysis(an)

    def current_analysis(self) -> Optional[Analysis]:
        """The last analysis, if it is still current (the configuration and
        options unchanged since: kin_get_analysis), else None; no SVD is
        made. After `follow_event` it is the follower's own analysis of the
        end point (at the tolerance it located that point to).

        Returns
        -------
        Analysis or None
            The current analysis, or None where there is none.

        Raises
        ------
        StateError
            The assembly is closed.
        """
        an = new_struct("kin_analysis")
        if lib.kin_get_analysis(self._h, an) != lib.KIN_OK:
            return None
        return self._analysis(an)

    def _analysis(self, an: Any) -> Analysis:
        nf, nb = self.nfree, self.nbars
        sv = np.empty(min(nf, nb))
        rc = lib.kin_get_singular_values(self._h, write_ptr(sv, "double *"), sv.size)
        if rc == lib.KIN_ESTATE:  # a sparse-mode analysis: no spectrum (kin_assembly.h)
            sv = np.empty(0)
        else:
            self._check(rc)

        def mech(kind: int, cols: int) -> FloatArray:
            out = np.empty((nf, cols), order="F")
            if cols:
                self._check(lib.kin_get_mechanisms(self._h, kind, write_ptr(out, "double *"), nf, cols))
            return out

        ws = np.empty((nb, an.s), order="F")
        if an.s:
            self._check(lib.kin_get_self_stresses(self._h, write_ptr(ws, "double *"), nb, an.s))
        route = ffi.new("int *")
        self._check(lib.kin_get_analysis_route(self._h, route))
        return Analysis(an.rank, an.m, an.m_rigid, an.m_internal, an.s, an.v_max, an.v_r, sv,
                        mech(lib.KIN_MECH_INTERNAL, an.m_internal), mech(lib.KIN_MECH_RIGID, an.m_rigid), ws,
                        int(an.s_trivial), "sparse" if route[0] == lib.KIN_ROUTE_SPARSE else "dense")
