"""The frames the viewer draws between a path's stored configurations, and
which recorded configurations to store so that those frames are true.

atlas.html animates a path through its keyframes (the source node, the
stored samples, the target node) with a uniform Catmull-Rom spline
(viewer.js catmull()). Between two keyframes that are far apart on the
path, that curve is not a configuration of the structure: bars stretch or
shrink. `strain()` measures it exactly as the viewer draws it (the same
spline, at STRAIN_POINTS points of every segment); `choose()` picks, from
the configurations the follower recorded along the path, the fewest that
keep every interpolated frame's bar strain within VIEW_STRAIN.
"""
from __future__ import annotations

from typing import List, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

# the largest relative change of a bar's length in a frame the viewer draws
# between two stored configurations
VIEW_STRAIN = 0.01
# interpolated frames checked per segment (the curve's strain is smooth in t:
# a bump narrower than 1/STRAIN_POINTS of a segment would need a segment of
# several turns, which the first check already splits)
STRAIN_POINTS = 16


def catmull(frames: NDArray[np.float64], k: int, t: NDArray[np.float64]) -> NDArray[np.float64]:
    """The viewer's curve (viewer.js catmull()) in segment k (between
    frames[k] and frames[k+1]) at the local parameters t in [0, 1]:
    shape (len(t),) + frames.shape[1:]."""
    K = len(frames) - 1
    p0, p1, p2, p3 = frames[max(k - 1, 0)], frames[k], frames[k + 1], frames[min(k + 2, K)]
    t = np.asarray(t, dtype=float).reshape((-1,) + (1,) * (frames.ndim - 1))
    t2, t3 = t * t, t * t * t
    return 0.5 * (2 * p1 + (-p0 + p2) * t + (2 * p0 - 5 * p1 + 4 * p2 - p3) * t2
                  + (-p0 + 3 * p1 - 3 * p2 + p3) * t3)


def _bar_lengths(x: NDArray[np.float64], bars: NDArray[np.int64]) -> NDArray[np.float64]:
    out: NDArray[np.float64] = np.linalg.norm(x[..., bars[:, 0], :] - x[..., bars[:, 1], :], axis=-1)
    return out


def segment_strain(frames: ArrayLike, bars: ArrayLike, rest: ArrayLike) -> NDArray[np.float64]:
    """For each segment of the keyframes (njoints x dim configurations, in
    order), the largest |l - rest| / rest of any bar in the frames the
    viewer draws inside it (STRAIN_POINTS of them, the ends excluded)."""
    f = np.asarray(frames, dtype=float)
    b = np.asarray(bars, dtype=np.int64).reshape(-1, 2)
    r = np.asarray(rest, dtype=float)
    use = r > 0
    if len(f) < 2 or not use.any():
        return np.zeros(max(len(f) - 1, 0))
    K = len(f) - 1
    k = np.arange(K)
    p0, p1, p2, p3 = f[np.maximum(k - 1, 0)], f[k], f[k + 1], f[np.minimum(k + 2, K)]
    # the bars' end points only: (segments, bars in use, 2 ends, dim) per control point
    ub = b[use]
    p0, p1, p2, p3 = p0[:, ub], p1[:, ub], p2[:, ub], p3[:, ub]
    t = ((np.arange(STRAIN_POINTS) + 0.5) / STRAIN_POINTS)[:, None, None, None, None]
    x = 0.5 * (2 * p1 + (-p0 + p2) * t + (2 * p0 - 5 * p1 + 4 * p2 - p3) * t * t
               + (-p0 + 3 * p1 - 3 * p2 + p3) * t * t * t)  # (points, segments, bars, 2, dim)
    ls = np.linalg.norm(x[..., 0, :] - x[..., 1, :], axis=-1)
    out: NDArray[np.float64] = (np.abs(ls - r[use]) / r[use]).max(axis=(0, 2))
    return out


def strain(frames: ArrayLike, bars: ArrayLike, rest: ArrayLike) -> float:
    """The largest bar strain of any frame the viewer draws along the keyframes."""
    s = segment_strain(frames, bars, rest)
    return float(s.max()) if len(s) else 0.0


def choose(start: ArrayLike, recorded: ArrayLike, end: ArrayLike, first: Sequence[int], bars: ArrayLike,
           rest: ArrayLike, limit: float = VIEW_STRAIN) -> List[int]:
    """Indices (increasing) into recorded, the configurations recorded along
    a path from start to end in order: first (the evenly spread samples
    asked for) and, while segments of the viewer's curve through start,
    the chosen ones and end strain a bar by more than limit, the recorded
    configuration half way (by index) between each such segment's ends. A
    segment with no recorded configuration inside stays as it is (the
    record is as fine as the follower's steps)."""
    rec = np.asarray(recorded, dtype=float)
    n = len(rec)
    chosen = sorted(set(int(i) for i in first if 0 <= int(i) < n))
    if n == 0:
        return chosen
    s0, s1 = np.asarray(start, dtype=float), np.asarray(end, dtype=float)
    while True:
        keys = [-1] + chosen + [n]
        frames = np.stack([s0] + [rec[i] for i in chosen] + [s1])
        seg = segment_strain(frames, bars, rest)
        # every segment over the limit that has a recorded point inside, split at once
        split = [(keys[k] + keys[k + 1]) // 2 for k in np.flatnonzero(seg > limit) if keys[k + 1] - keys[k] >= 2]
        if not split:
            return chosen
        chosen = sorted(set(chosen) | set(split))
