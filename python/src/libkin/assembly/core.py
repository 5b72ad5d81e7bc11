"""The Assembly class: a pin-jointed bar assembly owned by a libkin handle.

`Assembly` is put together from one class per concept, each in its own
module: the handle, model and first-order analysis (`_base.AssemblyBase`),
path following (`_path.PathMixin`), the paths out of a bifurcation
(`_branching.BranchingMixin`) and locating bifurcations
(`_locating.LocatingMixin`). This module adds the constructors, and the
JSON form (`_json.py`) through `from_json` and `to_json`.

Units: coordinates and lengths are in the caller's length unit; singular
values and mechanisms are dimensionless (H holds direction cosines);
mechanism vectors have one entry per free coordinate, ordered joint by joint
and x, y, z within a joint (see `Assembly.free_index`).
"""
from __future__ import annotations

import os
from typing import Any, Dict, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

from .._native._arrays import as_c_array, read_ptr
from ._base import Analysis, AssemblyBase
from ._contact import Clearance, ContactMixin
from ._branching import BranchPath, Branches, BranchingMixin, solve_quadrics
from ._json import apply_contact, read_json, to_json
from .._native._lib import c_string, default_struct, ffi, lib, new_struct
from ._locating import FollowEvent, LocateInfo, LocatingMixin
from ._path import Options, PathMixin, StepInfo
from ..errors import DimensionError, InvalidArgumentError, check, error_class

__all__ = ["Assembly", "Clearance", "Analysis", "StepInfo", "Options", "BranchPath", "Branches", "LocateInfo", "FollowEvent",
           "solve_quadrics"]

_THREEBAR_STATES = {"RA": "KIN_THREEBAR_RA", "RB": "KIN_THREEBAR_RB", "RC": "KIN_THREEBAR_RC"}
_SAIL_SUPPORTS = {"auto": "KIN_SAIL_SUPPORT_AUTO", "opposite": "KIN_SAIL_SUPPORT_OPPOSITE",
                  "centre": "KIN_SAIL_SUPPORT_CENTRE"}
_SAIL_DIAGONALS = {"forward": "KIN_SAIL_DIAG_FORWARD", "backward": "KIN_SAIL_DIAG_BACKWARD"}


class Assembly(ContactMixin, PathMixin, BranchingMixin, LocatingMixin, AssemblyBase):
    """A pin-jointed bar assembly in 2D or 3D.

    Parameters
    ----------
    coords : array_like, shape (njoints, dim)
        Joint coordinates, dim 2 or 3.
    bars : array_like of int, shape (nbars, 2)
        The two joints (0-based) of each bar.
    fixed : array_like of bool, shape (njoints, dim), optional
        True where a coordinate is a support; None = every coordinate free.
    lengths : array_like, shape (nbars,), optional
        Rest lengths the bars keep; None = their initial lengths.
    labels : sequence of str, optional
        Joint names (kept for plots and JSON output).
    name : str, optional
        The model's name.
    panels : sequence of sequences of int, optional
        Panels (faces): loops of 3 or more joints (docs/contact.md).
    thickness : float, optional
        The model-wide thickness (bars: radius thickness/2; panels: slabs);
        default 0.

    Raises
    ------
    InvalidArgumentError
        A wrong shape (a ValueError); `DimensionError` if dim is not 2 or 3.
    ArgumentTypeError
        Non-numeric or ragged arrays, non-integer bar indices (a TypeError).
    JointIndexError, SelfBarError, DuplicateBarError, GeometryError, NoFreeCoordinatesError
        The C library rejected the model (the message says which bar or joint).

    Notes
    -----
    Use as a context manager or call `close`; the handle is also freed when
    the object is garbage-collected. The arrays passed are copied; the
    caller's arrays are never changed.
    """

    def __init__(self, coords: npt.ArrayLike, bars: npt.ArrayLike, fixed: Optional[npt.ArrayLike] = None,
                 lengths: Optional[npt.ArrayLike] = None, *, labels: Optional[Sequence[str]] = None,
                 name: Optional[str] = None, panels: Optional[Sequence[Sequence[int]]] = None,
                 thickness: float = 0.0) -> None:
        coords_a = as_c_array(coords, np.float64, (None, None), "coords")
        if coords_a.shape[1] not in (2, 3):
            raise DimensionError(f"coords: expected shape (njoints, 2 or 3), got {coords_a.shape}")
        nj, dim = coords_a.shape
        bars_a = as_c_array(bars, np.int32, (None, 2), "bars")
        fixed_a = None if fixed is None else as_c_array(fixed, np.uint8, (nj, dim), "fixed")
        len_a = None if lengths is None else as_c_array(lengths, np.float64, (bars_a.shape[0],), "lengths")
        out = ffi.new("kin_assembly **")
        err = ffi.new("char[512]")
        rc = lib.kin_assembly_create(
            dim, nj, read_ptr(coords_a, "double *"),
            ffi.NULL if fixed_a is None else read_ptr(fixed_a, "unsigned char *"),
            bars_a.shape[0], read_ptr(bars_a, "int *"),
            ffi.NULL if len_a is None else read_ptr(len_a, "double *"), out, err, 512)
        if rc:
            raise error_class(rc)(c_string(err), rc)
        self._adopt(out[0])
        self.labels = list(labels) if labels is not None else None
        self.name = name
        if panels:
            self.panels = panels
        if thickness:
            self.thickness = thickness

    # ---- built-in models -------------------------------------------------
    @classmethod
    def threebar(cls, state: str = "RC") -> "Assembly":
        """The paper's three-bar linkage (Figure 1, Section 5).

        Parameters
        ----------
        state : {'RA', 'RB', 'RC'}, optional
            Which of its three bifurcation configurations.

        Returns
        -------
        Assembly
            Joints J1, J2 (free) and S1, S2 (supports); 3 bars of length 1.

        Raises
        ------
        InvalidArgumentError
            Unknown `state` (a ValueError).
        """
        if state not in _THREEBAR_STATES:
            raise InvalidArgumentError(f"state: expected one of {sorted(_THREEBAR_STATES)}, got {state!r}")
        out = ffi.new("kin_assembly **")
        check(lib.kin_model_threebar(getattr(lib, _THREEBAR_STATES[state]), out), what="threebar")
        return cls._from_handle(out[0], ["J1", "J2", "S1", "S2"], f"threebar_{state}")

    @classmethod
    def sail(cls, n_sides: int = 6, n_loops: int = 2, side: float = 1.0,
             widths: Optional[npt.ArrayLike] = None, support: str = "auto",
             diagonal: str = "forward") -> "Assembly":
        """A member of the wrapping-fold solar-sail family (kin_model_sail), flat.

        Parameters
        ----------
        n_sides : int, optional
            Sides of the hub polygon: 4 is the paper's square sail, 6 the hexagonal one.
        n_loops : int, optional
            Loops of triangles around the hub.
        side : float, optional
            Hub side length.
        widths : array_like, shape (n_loops,), optional
            Loop widths; None = side * tan(pi / n_sides) each.
        support : {'auto', 'opposite', 'centre'}, optional
            'opposite': two opposite hub vertices fixed; 'centre': every other
            hub vertex fixed and a centre node moving in z; 'auto': 'opposite'
            for n_sides = 4, else 'centre' (the paper's choices).
        diagonal : {'forward', 'backward'}, optional
            Which way the triangles' diagonals run.

        Returns
        -------
        Assembly
            Labels C (if there is a centre node), V0.. (hub), A0.., B0.., ... (loops).

        Raises
        ------
        InvalidArgumentError
            Unknown `support` or `diagonal`, a wrong `widths` shape, or
            parameters the C library rejects.
        """
        if support not in _SAIL_SUPPORTS:
            raise InvalidArgumentError(f"support: expected one of {sorted(_SAIL_SUPPORTS)}, got {support!r}")
        if diagonal not in _SAIL_DIAGONALS:
            raise InvalidArgumentError(f"diagonal: expected one of {sorted(_SAIL_DIAGONALS)}, got {diagonal!r}")
        p = default_struct("kin_sail_params", int(n_sides), int(n_loops))
        p.side = float(side)
        p.support = getattr(lib, _SAIL_SUPPORTS[support])
        p.diagonal = getattr(lib, _SAIL_DIAGONALS[diagonal])
        keep = None
        if widths is not None:
            keep = as_c_array(widths, np.float64, (int(n_loops),), "widths")
            p.widths = read_ptr(keep, "double *")
        out = ffi.new("kin_assembly **")
        err = ffi.new("char[512]")
        rc = lib.kin_model_sail(p, out, err, 512)
        if rc:
            raise error_class(rc)(c_string(err), rc)
        centre = support == "centre" or (support == "auto" and n_sides != 4)
        labels = (["C"] if centre else []) + [f"V{k}" for k in range(n_sides)]
        for q in range(1, n_loops + 1):
            labels += [f"{chr(ord('A') + q - 1) if q <= 26 else 'L' + str(q)}{k}" for k in range(n_sides)]
        return cls._from_handle(out[0], labels, f"sail_{n_sides}x{n_loops}")

    @classmethod
    def from_json(cls, source: Union[str, "os.PathLike[str]", Dict[str, Any]],
                  max_bytes: Optional[int] = None) -> "Assembly":
        """Build an assembly from a JSON model (schema in ``python/README.md``).

        Parameters
        ----------
        source : str, path-like or dict
            A file path, a JSON text (starting with ``{``), or the parsed dict.
        max_bytes : int, optional
            Largest file read (default 64 MiB, as the C loader's
            KIN_LOAD_MAX_BYTES).

        Returns
        -------
        Assembly
            The model, with its labels and name.

        Raises
        ------
        ModelFormatError
            Malformed JSON or model; the message names the field and position
            (a ValueError).
        LimitError
            The file is larger than max_bytes (a ValueError).
        FileAccessError
            The file is a FIFO or a device, not read (an OSError).
        OSError
            The file cannot be read.
        """
        parsed = read_json(source, max_bytes)
        name, coords, bars, fixed, lengths, labels = parsed
        a = Assembly(coords, bars, fixed=fixed, lengths=lengths, labels=labels, name=name)
        apply_contact(a, getattr(parsed, "contact", None))
        return a

    def to_json(self, path: Union[str, "os.PathLike[str]", None] = None) -> Dict[str, Any]:
        """The assembly's current state as a JSON model.

        Parameters
        ----------
        path : str or path-like, optional
            Also write it to this file.

        Returns
        -------
        dict
            The model (schema in ``python/README.md``), with the rest lengths.
        """
        return to_json(self, path)

    def clone(self) -> "Assembly":
        """A deep copy: model, configuration, options and path state.

        Returns
        -------
        Assembly
            An independent handle.
        """
        out = ffi.new("kin_assembly **")
        self._check(lib.kin_assembly_clone(self._h, out), "clone")
        return Assembly._from_handle(out[0], self.labels, self.name)
