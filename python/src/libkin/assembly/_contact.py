"""Parts that can touch (kin_contact.h, docs/contact.md): panels, thicknesses
and the clearance between parts that share no joint."""
from __future__ import annotations

import dataclasses
from typing import Any, List, Optional, Sequence, Tuple

import numpy as np
import numpy.typing as npt

from .._native._arrays import as_c_array, read_ptr, write_ptr
from .._native._lib import ffi, lib
from ..errors import InvalidArgumentError

PART_KINDS = ("bar", "panel")


@dataclasses.dataclass(frozen=True)
class Clearance:
    """The smallest clearance between two parts that share no joint.

    value : float
        Distance of the centre geometries minus the two radii (a panel's
        radius is half its thickness); <= 0 is contact; inf when every pair
        of parts shares a joint.
    parts : tuple of two (kind, index)
        kind 'bar' or 'panel', index among the bars or the panels; empty
        when value is inf.
    points : (2, dim) array
        The closest points of the two centre geometries.
    """
    value: float
    parts: Tuple[Tuple[str, int], ...]
    points: npt.NDArray[np.float64]

    @property
    def contact(self) -> bool:
        """True when the parts touch or overlap (value <= 0)."""
        return self.value <= 0.0


class ContactMixin:
    """Panels, thicknesses and clearance of an Assembly."""

    _h: Any
    nbars: int
    njoints: int
    dim: int

    _check: Any  # AssemblyBase's

    @property
    def panels(self) -> List[List[int]]:
        """The panels: lists of 3 or more joints in loop order (FOLD's
        faces_vertices). Assigning replaces them ([] removes them) and resets
        the panel thicknesses to the default."""
        n = int(lib.kin_npanels(self._h))
        off = np.zeros(n + 1, dtype=np.int32)
        self._check(lib.kin_get_panels(self._h, write_ptr(off, "int *"), ffi.NULL))
        js = np.zeros(max(int(off[-1]), 1), dtype=np.int32)
        self._check(lib.kin_get_panels(self._h, ffi.NULL, write_ptr(js, "int *")))
        return [js[off[i]:off[i + 1]].tolist() for i in range(n)]

    @panels.setter
    def panels(self, value: Sequence[Sequence[int]]) -> None:
        faces = [list(f) for f in value]
        for i, f in enumerate(faces):
            if not all(isinstance(j, (int, np.integer)) and not isinstance(j, bool) for j in f):
                raise InvalidArgumentError(f"panels[{i}]: expected joint indices, got {f!r}")
        off = np.zeros(len(faces) + 1, dtype=np.int32)
        off[1:] = np.cumsum([len(f) for f in faces]) if faces else []
        try:
            flat = np.ascontiguousarray([j for f in faces for j in f] or [0], dtype=np.int32)
        except OverflowError:
            raise InvalidArgumentError("panels: a joint index out of range") from None
        self._check(lib.kin_set_panels(self._h, len(faces), read_ptr(off, "int *"), read_ptr(flat, "int *")),
                    "panels")

    @property
    def npanels(self) -> int:
        """Number of panels."""
        return int(lib.kin_npanels(self._h))

    @property
    def thickness(self) -> float:
        """The model-wide thickness t0 (a bar's radius t0/2, a panel's
        thickness t0 unless set one by one). Assigning keeps no per-part value."""
        t = ffi.new("double *")
        self._check(lib.kin_get_thickness(self._h, t, ffi.NULL, ffi.NULL))
        return float(t[0])

    @thickness.setter
    def thickness(self, value: float) -> None:
        self.set_thickness(value)

    @property
    def bar_radii(self) -> npt.NDArray[np.float64]:
        """The radius of each bar (defaults resolved), (nbars,)."""
        out = np.empty(self.nbars)
        self._check(lib.kin_get_thickness(self._h, ffi.NULL, write_ptr(out, "double *"), ffi.NULL))
        return out

    @property
    def panel_thicknesses(self) -> npt.NDArray[np.float64]:
        """The thickness of each panel (defaults resolved), (npanels,)."""
        out = np.empty(max(self.npanels, 1))
        self._check(lib.kin_get_thickness(self._h, ffi.NULL, ffi.NULL, write_ptr(out, "double *")))
        return out[:self.npanels]

    def set_thickness(self, default: float, bar_radii: Optional[npt.ArrayLike] = None,
                      panel_thicknesses: Optional[npt.ArrayLike] = None) -> None:
        """Set the model-wide thickness and, optionally, each bar's radius and
        each panel's thickness.

        Parameters
        ----------
        default : float
            The model-wide thickness t0 >= 0 (a bar's radius t0/2, a panel's thickness t0).
        bar_radii : array_like, shape (nbars,), optional
            Each bar's radius; an entry < 0 means the default.
        panel_thicknesses : array_like, shape (npanels,), optional
            Each panel's thickness; an entry < 0 means the default.

        Raises
        ------
        GeometryError
            A negative default, or a non-finite value.
        InvalidArgumentError
            An array of the wrong length.
        """
        rb = None if bar_radii is None else as_c_array(bar_radii, np.float64, (self.nbars,), "bar_radii")
        tp = None if panel_thicknesses is None else as_c_array(panel_thicknesses, np.float64, (self.npanels,),
                                                                "panel_thicknesses")
        self._check(lib.kin_set_thickness(self._h, float(default),
                                          ffi.NULL if rb is None else read_ptr(rb, "double *"),
                                          ffi.NULL if tp is None or self.npanels == 0 else read_ptr(tp, "double *")),
                    "thickness")

    @property
    def has_contact_model(self) -> bool:
        """True when the model carries panels or a nonzero thickness."""
        return bool(lib.kin_has_contact_model(self._h) == 1)

    def clearance(self, coords: Optional[npt.ArrayLike] = None, cutoff: float = np.inf) -> Clearance:
        """The smallest clearance between parts that share no joint, and,
        with `hinge_contact` on (the default), of the hinges: two panels on
        one fold line, named as their two panels, at 2 h sin(delta / 2) less
        their half thicknesses (0 where the hinge is folded flat).

        Parameters
        ----------
        coords : array_like, shape (njoints, dim), optional
            A configuration to measure; None = the current one.
        cutoff : float, optional
            Resolve only clearances below this (a contact margin: much
            cheaper); value is inf when none is below it.

        Returns
        -------
        Clearance
        """
        c = ffi.new("double *")
        parts = ffi.new("int[4]")
        pts = np.zeros((2, self.dim))
        x = None if coords is None else as_c_array(coords, np.float64, (self.njoints, self.dim), "coords")
        self._check(lib.kin_clearance(self._h, ffi.NULL if x is None else read_ptr(x, "double *"), float(cutoff), c, parts,
                                      write_ptr(pts, "double *")), "clearance")
        named: Tuple[Tuple[str, int], ...] = ()
        if parts[0] >= 0:
            named = ((PART_KINDS[parts[0]], int(parts[1])), (PART_KINDS[parts[2]], int(parts[3])))
        return Clearance(float(c[0]), named, pts)

    def set_contact_events(self, on: bool = True, tol: float = 1e-9) -> None:
        """Make `follow_event` stop at the first contact of two parts
        (event 'contact'), located along the path (kin_set_contact_events).

        Parameters
        ----------
        on : bool, optional
            Watch for contact (off by default).
        tol : float, optional
            Location tolerance, a fraction of the RMS rest length, in (0, 1].
        """
        self._check(lib.kin_set_contact_events(self._h, int(bool(on)), float(tol)), "contact events")

    def last_contact(self) -> Clearance:
        """The contact the last `follow_event` located (event 'contact').

        Returns
        -------
        Clearance
            Its clearance (<= 0 up to rounding), the two parts and their closest points.

        Raises
        ------
        StateError
            The last follow located no contact.
        """
        c = ffi.new("double *")
        br = ffi.new("double *")
        parts = ffi.new("int[4]")
        pts = np.zeros((2, self.dim))
        self._check(lib.kin_last_contact(self._h, c, parts, write_ptr(pts, "double *"), br), "last contact")
        named = ((PART_KINDS[parts[0]], int(parts[1])), (PART_KINDS[parts[2]], int(parts[3])))
        return Clearance(float(c[0]), named, pts)

    @property
    def device_bars(self) -> List[int]:
        """The bars marked as modelling devices (a sail's spokes), which are
        no parts that can touch: the clearance and the contact event leave
        them out. Assigning replaces them ([] marks none)."""
        n = ffi.new("int *")
        self._check(lib.kin_get_device_bars(self._h, n, ffi.NULL))
        out = np.zeros(max(int(n[0]), 1), dtype=np.int32)
        self._check(lib.kin_get_device_bars(self._h, n, write_ptr(out, "int *")))
        return out[:int(n[0])].tolist()

    @device_bars.setter
    def device_bars(self, value: Sequence[int]) -> None:
        bars = list(value)
        if not all(isinstance(k, (int, np.integer)) and not isinstance(k, bool) for k in bars):
            raise InvalidArgumentError(f"device_bars: expected bar indices, got {bars!r}")
        try:
            arr = np.ascontiguousarray(bars or [0], dtype=np.int32)
        except OverflowError:
            raise InvalidArgumentError("device_bars: a bar index out of range") from None
        self._check(lib.kin_set_device_bars(self._h, len(bars), read_ptr(arr, "int *")), "device bars")

    @property
    def hinge_contact(self) -> bool:
        """Whether hinges (two panels on one fold line) count in the
        clearance and the contact event (on by default; kin_contact.h)."""
        return bool(lib.kin_get_hinge_contact(self._h) == 1)

    @hinge_contact.setter
    def hinge_contact(self, on: bool) -> None:
        self._check(lib.kin_set_hinge_contact(self._h, int(bool(on))), "hinge contact")

    def hinges(self) -> Tuple[npt.NDArray[np.int32], npt.NDArray[np.int32]]:
        """The hinges: two panels that share an edge (3D models).

        Returns
        -------
        joints : (nhinges, 4) int array
            The edge i < j, then the far joints a, b of the two panels' fan
            triangles that hold it.
        panels : (nhinges, 2) int array
            The two panels pa < pb.
        """
        n = int(lib.kin_nhinges(self._h))
        j = np.zeros((max(n, 1), 4), dtype=np.int32)
        p = np.zeros((max(n, 1), 2), dtype=np.int32)
        self._check(lib.kin_get_hinges(self._h, write_ptr(j, "int *"), write_ptr(p, "int *")))
        return j[:n], p[:n]

    def hinge_angles(self, coords: Optional[npt.ArrayLike] = None) -> npt.NDArray[np.float64]:
        """The fold angle psi of each hinge in (-pi, pi], radians: 0 flat
        open, +-pi folded flat (closed); its sign is the sign of the signed
        volume of (x_i, x_j, x_a, x_b). psi jumps from pi to -pi where a
        hinge passes through flat-folded (the panels through each other).

        Parameters
        ----------
        coords : array_like, shape (njoints, 3), optional
            A configuration; None = the current one.

        Returns
        -------
        ndarray, shape (nhinges,)
            psi per hinge (NaN where a panel has zero height over the edge).
        """
        n = int(lib.kin_nhinges(self._h))
        out = np.zeros(max(n, 1))
        x = None if coords is None else as_c_array(coords, np.float64, (self.njoints, self.dim), "coords")
        self._check(lib.kin_hinge_angles(self._h, ffi.NULL if x is None else read_ptr(x, "double *"),
                                         write_ptr(out, "double *")), "hinge angles")
        return out[:n]

    def hinge_sides(self) -> npt.NDArray[np.int32]:
        """The fold side each hinge was tracked on by the last `follow_event`
        with contact events (+1, -1; 0 unknown: open wider than 90 degrees,
        or closed since the follow started).

        Returns
        -------
        ndarray of int, shape (nhinges,)

        Raises
        ------
        StateError
            No follow with contact events has tracked them.
        """
        n = int(lib.kin_nhinges(self._h))
        out = np.zeros(max(n, 1), dtype=np.int32)
        self._check(lib.kin_hinge_sides(self._h, write_ptr(out, "int *")), "hinge sides")
        return out[:n]
