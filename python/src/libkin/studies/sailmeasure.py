"""What a designer measures on a sail configuration: how far it has folded
(x-y extent, height), the angle of each fold line to the hub plane, the
hub's flatness; and what each bar of the model is (hub edge, spoke, fold,
ring, diagonal), read from the joint labels Assembly.sail gives
(C, V0.., A0.., B0..); and its membrane (sail_panels: the panels of the
contact studies, part_name: a part by its joints' labels).

Lengths are in the model's unit, the hub side a (Assembly.sail(side=1)).
The hub plane is z = 0: the plane of the fixed hub vertices V0, V2, ...
"""
from __future__ import annotations

import re
from typing import Any, Dict, List, Optional, Sequence, Set, Tuple

import numpy as np
import numpy.typing as npt

BAR_KINDS = ("hub edge", "spoke", "fold", "ring", "diagonal")
# zero thickness: parts this close count as touching (hub sides)
TOUCH = 1e-9
_LABEL = re.compile(r"^([A-Z]+)(\d*)$")


def _parse(label: str) -> Tuple[Optional[str], Optional[int]]:
    m = _LABEL.match(label)
    if not m:
        return None, None
    return m.group(1), (int(m.group(2)) if m.group(2) else None)


def loop_of(label: str) -> Optional[int]:
    """0 for the hub (V), q for loop q (A = 1, B = 2, C = 3, ...: with an
    index), -1 for the centre node C (no index)."""
    letter, index = _parse(label)
    if letter == "C" and index is None:
        return -1
    if letter == "V":
        return 0
    return ord(letter[0]) - ord("A") + 1 if letter else None


def bar_kinds(labels: Sequence[str], bars: Any) -> List[str]:
    """One of BAR_KINDS per bar: spokes C-V; hub edges V-V; fold segments
    join the same index k on neighbouring loops (V_k-A_k, A_k-B_k); rings
    join neighbours on one loop; diagonals the rest (inner_k-outer_(k+1))."""
    out: List[str] = []
    for p, q in np.asarray(bars).tolist():
        lp, lq = loop_of(labels[p]), loop_of(labels[q])
        kp, kq = _parse(labels[p])[1], _parse(labels[q])[1]
        if -1 in (lp, lq):
            out.append("spoke")
        elif lp == 0 and lq == 0:
            out.append("hub edge")
        elif lp == lq:
            out.append("ring")
        elif kp == kq:
            out.append("fold")
        else:
            out.append("diagonal")
    return out


def fold_segments(labels: Sequence[str], n_sides: int, n_loops: int) -> List[List[Tuple[int, int]]]:
    """(inner joint, outer joint) of every fold segment, as
    [loop][k] -> (i, j): loop 1 is V_k-A_k, loop 2 A_k-B_k, ..."""
    index = {lab: i for i, lab in enumerate(labels)}
    letters = ["V"] + [chr(ord("A") + q) for q in range(n_loops)]
    return [[(index[f"{letters[q]}{k}"], index[f"{letters[q + 1]}{k}"]) for k in range(n_sides)]
            for q in range(n_loops)]


def fold_angles(x: npt.NDArray[np.float64], segments: List[List[Tuple[int, int]]]) -> List[List[float]]:
    """Angle of each fold segment to the hub plane, degrees (positive =
    rising away from the hub towards +z), as [loop][k]."""
    out: List[List[float]] = []
    for loop in segments:
        row: List[float] = []
        for i, j in loop:
            d = x[j] - x[i]
            row.append(float(np.degrees(np.arcsin(np.clip(d[2] / np.linalg.norm(d), -1.0, 1.0)))))
        out.append(row)
    return out


def measures(x: npt.NDArray[np.float64], labels: Sequence[str], n_sides: int, n_loops: int) -> Dict[str, Any]:
    """A dict of physical measures of configuration x (njoints, 3)."""
    hub = [i for i, lab in enumerate(labels) if loop_of(lab) == 0]
    ang = fold_angles(x, fold_segments(labels, n_sides, n_loops))
    return {
        "xy_extent": float(np.hypot(x[:, 0], x[:, 1]).max()),
        "z_extent": float(x[:, 2].max() - x[:, 2].min()),
        "z_min": float(x[:, 2].min()),
        "z_max": float(x[:, 2].max()),
        "hub_out_of_plane": float(np.abs(x[hub, 2]).max()),
        # the sail keeps its rotational symmetry: folds k even are alike,
        # as are folds k odd
        "fold_angle_even": [a[0] for a in ang],
        "fold_angle_odd": [a[1] for a in ang],
    }


def sail_panels(a: Any) -> List[List[int]]:
    """The membrane of a sail built by Assembly.sail: every triangle of its
    bar graph (the centre node C, a device of the model, excluded) and the
    hub polygon V0, V1, ..."""
    labels = list(a.labels)
    centre = [i for i, lab in enumerate(labels) if lab == "C"]
    adj: Dict[int, Set[int]] = {i: set() for i in range(a.njoints)}
    for i, j in np.asarray(a.bars):
        adj[int(i)].add(int(j))
        adj[int(j)].add(int(i))
    tris = []
    for i in range(a.njoints):
        for j in adj[i]:
            if j <= i:
                continue
            for k in adj[i] & adj[j]:
                if k > j and not {i, j, k} & set(centre):
                    tris.append([i, j, k])
    hub = [i for i, lab in enumerate(labels) if lab.startswith("V")]
    return tris + [hub]


def part_name(a: Any, panels: Sequence[Sequence[int]], kind: str, index: int) -> str:
    """A part by its joints' labels: bar 'A0-A1', panel 'A0-A1-V0'."""
    labels = list(a.labels)
    joints = list(np.asarray(a.bars)[index]) if kind == "bar" else panels[index]
    return f"{kind} " + "-".join(labels[int(j)] for j in joints)
