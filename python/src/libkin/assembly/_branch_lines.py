"""A bifurcation's branch lines, checked once, for many follows out of it.

`Assembly.follow_event(branches=...)` with an array passes the lines to C,
which checks every number and searches them for the direction's own line in
each call: at the hexagonal sail's flat state (29,828 lines x 46 numbers)
that is several milliseconds a call. A `BranchLines` is checked once (finite,
2-D) and gives the follower the nearest line at each return to the start
through kin_follow_options.return_fn (`nearest`): the same decision as C's
(the same angle formula on the candidates), at a cost paid only at returns.
"""
from __future__ import annotations

import threading
from typing import Any, Optional, Tuple

import numpy as np
import numpy.typing as npt

from .._native._lib import ffi
from ..errors import InvalidArgumentError

# candidates for the two nearest lines: those whose |cos| to t is within this
# (relative) of the second largest; their angles are then computed as C does
# (the ranking by |cos| and by angle differ only by rounding, ~1e-16)
CANDIDATE_SLACK = 1e-9
# |cos| of t to the lines, this many lines at a time: one product of all
# 29,828 x 46 (the hexagonal flat state) is threaded by numpy's OpenBLAS,
# whose spinning threads cost 2-8x the CPU of these single-threaded ones
# (0.24 ms) on a machine whose cores are taken by the workers
ROWS = 1024


class BranchLines:
    """Branch lines (nbranch, nfree), any sign and scale, read-only; for
    `Assembly.follow_event(branches=lines, own_branch=k)`.

    Raises InvalidArgumentError if lines is not a 2-D array of finite numbers
    with at least one line.
    """

    def __init__(self, lines: npt.ArrayLike) -> None:
        raw = np.asarray(lines, dtype=np.float64)
        if raw.ndim != 2 or raw.shape[0] < 1 or raw.shape[1] < 1:
            raise InvalidArgumentError(f"branch lines must have shape (nbranch, nfree), not {raw.shape}")
        if not np.isfinite(raw).all():
            raise InvalidArgumentError("branch lines are not all finite")
        self.raw = raw
        norm = np.linalg.norm(raw, axis=1)
        self.vv = np.einsum("ij,ij->i", raw, raw)
        with np.errstate(divide="ignore", invalid="ignore"):
            self.unit = np.where(norm[:, None] > 0.0, raw / np.where(norm > 0.0, norm, 1.0)[:, None], 0.0)
        self._local = threading.local()  # the exception a return_fn call raised, per thread
        self.c_fn = ffi.callback("kin_follow_return_fn", self._call, error=-1, onerror=self._onerror)

    @property
    def shape(self) -> Tuple[int, int]:
        return (int(self.raw.shape[0]), int(self.raw.shape[1]))

    def angle(self, t: npt.ArrayLike, k: Any) -> Any:
        """Angles (radians, [0, pi/2]) between the line of t and lines k,
        by the follower's formula (atan2 of sine and |cosine|)."""
        t = np.asarray(t, dtype=np.float64)
        v = self.raw[k]
        uu, vv, uv = float(t @ t), self.vv[k], v @ t
        if not uu > 0.0:
            return np.full(np.shape(vv), np.pi / 2)
        with np.errstate(divide="ignore", invalid="ignore"):
            kk = np.where(vv > 0.0, uv / np.where(vv > 0.0, vv, 1.0), 0.0)
            r = t - kk[..., None] * v if v.ndim == 2 else t - kk * v
            s2 = np.einsum("...i,...i->...", r, r)
            out = np.arctan2(np.sqrt(s2 / uu), np.abs(uv) / np.sqrt(uu * vv))
        return np.where(vv > 0.0, out, np.pi / 2)

    def nearest(self, t: npt.ArrayLike) -> Tuple[int, float, float]:
        """(index, angle, gap): the line nearest the line of t, the angle to
        it and how much farther the next nearest is (inf with one line);
        ties go to the lowest index, as in C."""
        t = np.asarray(t, dtype=np.float64)
        n = self.raw.shape[0]
        nt = float(np.linalg.norm(t))
        c = np.zeros(n)
        if nt > 0.0:
            tn = t / nt
            for k in range(0, n, ROWS):  # BLAS products below OpenBLAS's threading size (see ROWS)
                np.dot(self.unit[k:k + ROWS], tn, out=c[k:k + ROWS])
            np.abs(c, out=c)
        if n > 2:
            j = int(np.argmax(c))
            top, c[j] = c[j], -1.0
            c2 = float(c.max())  # the second largest
            c[j] = top
            cand = np.flatnonzero(c >= c2 * (1.0 - CANDIDATE_SLACK) - CANDIDATE_SLACK)
        else:
            cand = np.arange(n)
        ang = np.atleast_1d(self.angle(t, cand))
        order = np.lexsort((cand, ang))
        j, a1 = int(cand[order[0]]), float(ang[order[0]])
        gap = float(ang[order[1]]) - a1 if len(order) > 1 else float("inf")
        return j, a1, gap

    def _call(self, user: Any, t: Any, nf: int, angle: Any, gap: Any) -> int:
        try:
            if nf != self.raw.shape[1]:
                raise InvalidArgumentError(f"branch lines have {self.raw.shape[1]} entries, the follower {nf}")
            tv = np.frombuffer(ffi.buffer(t, 8 * nf), dtype=np.float64)
            j, a, g = self.nearest(tv)
            angle[0], gap[0] = a, g
            return j
        except BaseException as exc:  # noqa: BLE001 - raised again after the C call
            self._local.error = exc
            return -1

    def _onerror(self, exc_type: Any, exc_value: Optional[BaseException], tb: Any) -> None:
        self._local.error = exc_value
        return None

    def take_error(self) -> Optional[BaseException]:
        """The exception the last return_fn call in this thread raised, if any (cleared)."""
        exc = getattr(self._local, "error", None)
        self._local.error = None
        return exc
