"""Hinges: two panels on one fold line (kin_contact.h HINGES, docs/contact.md
"Hinges"), checked against an independent NumPy computation.

- The study's leg 2 (the hexagonal two-loop sail, R^B onward along the
  chosen branch) carries the loop-1 trapezia through themselves at R^B:
  their hinges arrive folded flat on one side and leave on the other. The
  contact event must stop there and name the two panels of such a hinge
  (before hinges, it named a bar touching a panel a step later).
- The fold angles, the pass-throughs and the events along the folds, against
  signed volumes and dihedral angles computed here in NumPy from the panels
  alone (hinges found here too), on configurations stepped densely along the
  sails' radially sequential folds (at least 10^4 with LIBKIN_TEST_SLOW=1).
- Devices and the model file.
"""
from __future__ import annotations

import itertools
import os
from typing import Dict, List, Tuple

import numpy as np
import pytest

import libkin
from libkin.errors import InvalidArgumentError
from libkin.studies.sailmeasure import sail_panels
from libkin.studies.sequential import sequential_fold

SLOW = os.environ.get("LIBKIN_TEST_SLOW") == "1"


# ---- the independent computation -----------------------------------------

def np_hinges(panels: List[List[int]]) -> Dict[Tuple[int, int, int, int], Tuple[int, int]]:
    """Every two panels on one edge: {(i, j, a, b): (pa, pb)}, i < j the
    edge, a and b the third corners of the panels' fan triangles that hold
    it (the fan from each panel's first joint)."""
    by_edge: Dict[Tuple[int, int], List[Tuple[int, int]]] = {}
    for p, f in enumerate(panels):
        fan = [(f[0], f[q], f[q + 1]) for q in range(1, len(f) - 1)]
        for q in range(len(f)):
            e = (f[q], f[(q + 1) % len(f)])
            tri = next(t for t in fan if set(e) <= set(t))
            far = (set(tri) - set(e)).pop()
            by_edge.setdefault((min(e), max(e)), []).append((p, far))
    out = {}
    for (i, j), lst in by_edge.items():
        for (pa, a), (pb, b) in itertools.combinations(sorted(lst), 2):
            out[(i, j, a, b)] = (pa, pb)
    return out


def np_volume_and_dihedral(X: np.ndarray, H: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """For configurations X (n, nj, 3) and hinges H (nh, 4): the signed
    volume det[x_j - x_i, x_a - x_i, x_b - x_i] and the dihedral angle
    between the two panels' normals (0 folded flat, pi flat open), (n, nh)."""
    xi, xj, xa, xb = (X[:, H[:, q], :] for q in range(4))
    e, va, vb = xj - xi, xa - xi, xb - xi
    vol = np.linalg.det(np.stack([e, va, vb], axis=-1))
    na, nb = np.cross(e, va), np.cross(e, vb)   # normals, each turned to its own far corner
    dih = np.arctan2(np.linalg.norm(np.cross(na, nb), axis=-1), np.einsum("...k,...k", na, nb))
    return vol, dih


def np_events(vol: np.ndarray, dih: np.ndarray, side0: np.ndarray) -> np.ndarray:
    """The first configuration index at which each hinge is closed or through
    flat-folded along the sequence (n + 1 where none), tracking the fold side
    (the sign of the volume while the dihedral is below 90 degrees; side0 at
    the start, 0 = unknown)."""
    n, nh = vol.shape
    first = np.full(nh, n + 1)
    for h in range(nh):
        s = side0[h]
        for k in range(1, n):
            d, v = dih[k, h], vol[k, h]
            if d < np.pi / 2 and s != 0 and (np.sign(v) != s or d < 1e-12):
                first[h] = k
                break
            if d >= np.pi / 2:
                s = 0
            elif s == 0 and d > 1e-6:
                s = np.sign(v)
    return first


# ---- the folds ------------------------------------------------------------

def dense_fold(n: int, loops: int, per: int, max_legs: int = 2):
    """The member's radially sequential fold, stepped `per` times between
    each two of its samples: (the fold's result, the legs as lists of
    (configuration, length from the fold's start))."""
    res = sequential_fold(n, loops, keep_states=True, max_legs=max_legs)
    S = res["samples"]
    starts = sorted(S.leave_dir)
    legs = []
    for li, q0 in enumerate(starts):
        q1 = starts[li + 1] if li + 1 < len(starts) else len(S.l) - 1
        pts = []
        for q in range(q0, q1):
            dl = S.l[q + 1] - S.l[q]
            b = S.states[q].clone()
            if q in S.leave_dir:
                b.set_direction(S.leave_dir[q])
            pts.append((b.coords, S.l[q]))
            for r in range(1, per):
                try:
                    b.step(dl / per)
                except libkin.KinError:
                    break
                pts.append((b.coords, S.l[q] + r * dl / per))
        pts.append((S.coords[q1], S.l[q1]))
        legs.append(pts)
    return res, legs


@pytest.fixture(scope="module")
def hex2():
    """The hexagonal two-loop sail's fold: legs 1 (flat to R^B) and 2 (R^B to R^C)."""
    res = sequential_fold(6, 2, keep_states=True, max_legs=2)
    S = res["samples"]
    starts = sorted(S.leave_dir)
    return res, S, starts


def _membrane(a):
    a = a.clone()
    a.panels = sail_panels(a)
    a.set_contact_events(True, 1e-9)
    return a


def test_leg2_carries_trapezia_through_themselves(hex2):
    """The study's leg 2: the hinges of the loop-1 trapezia arrive at R^B
    folded flat on one side (leg 1) and leave on the other: the contact
    event stops there and names the two panels of a hinge. (Before hinges
    it stopped a step later at bar V0-V1 on panel A0-A1-B1.)"""
    res, S, starts = hex2
    a0 = res["assembly"]
    rb, d1, d2 = S.states[starts[1]], S.leave_dir[starts[0]], S.leave_dir[starts[1]]
    # leg 1 with events: it touches where it reaches R^B; the hinges' sides
    # are tracked to there
    a = _membrane(a0)
    fe = a.follow_event(d1, max_steps=600)
    assert fe.event == "contact" and abs(fe.length - S.l[starts[1]]) < 1e-3
    sides_leg1 = a.hinge_sides()
    J, P = a.hinges()
    psi_rb = a.hinge_angles(rb.coords)
    closed = np.flatnonzero(np.pi - np.abs(psi_rb) < 1e-6)
    assert len(closed) == 6  # the six trapezia's diagonals
    assert np.all(sides_leg1[closed] != 0)
    # leg 2 from R^B
    a.coords = rb.coords
    fe2 = a.follow_event(d2, max_steps=600)
    assert fe2.event == "contact"
    c = a.last_contact()
    assert [k for k, _ in c.parts] == ["panel", "panel"]
    pair = (c.parts[0][1], c.parts[1][1])
    h = [k for k in range(len(P)) if tuple(P[k]) == pair]
    assert len(h) == 1 and h[0] in closed       # a trapezium's diagonal hinge
    assert c.value <= 0.0 and fe2.length < 1e-3
    # independently: along leg 2 that hinge's signed volume has the sign
    # opposite to leg 1's last approach, while the trapezium is folded
    b = rb.clone()
    b.set_direction(d2)
    b.step(0.05)
    Jh = J[h[0]][None, :]
    vol_in, dih_in = np_volume_and_dihedral(S.coords[starts[1] - 1][None], Jh)
    vol_out, dih_out = np_volume_and_dihedral(b.coords[None], Jh)
    assert dih_in[0, 0] < np.pi / 2 and dih_out[0, 0] < np.pi / 2
    assert np.sign(vol_in[0, 0]) == sides_leg1[h[0]] == -np.sign(vol_out[0, 0])
    # the same without hinge contact: no hinge named (today's libkin)
    a2 = _membrane(a0)
    a2.hinge_contact = False
    a2.coords = rb.coords
    fe3 = a2.follow_event(d2, max_steps=600)
    assert fe3.event != "contact" or [k for k, _ in a2.last_contact().parts] != ["panel", "panel"]


def _check_member(n: int, loops: int, per: int) -> Tuple[int, int, int]:
    """Fold angles, pass-throughs and events along member (n, loops)'s fold
    against NumPy. Returns (configurations, hinge-configurations checked,
    pass-throughs found)."""
    res, legs = dense_fold(n, loops, per)
    a = res["assembly"].clone()
    panels = sail_panels(a)
    a.panels = panels
    J, P = a.hinges()
    ref = np_hinges(panels)
    # the same hinges, the same panels
    assert sorted(ref) == sorted(map(tuple, J.tolist()))
    assert all(ref[tuple(j)] == tuple(p) for j, p in zip(J.tolist(), P.tolist()))
    X = np.array([x for leg in legs for x, _ in leg])
    vol, dih = np_volume_and_dihedral(X, J)
    psi_c = np.array([a.hinge_angles(x) for x in X])
    # the fold angle: psi = sign(volume) (pi - dihedral), up to the flat states
    psi_np = np.where(vol < 0, -1.0, 1.0) * (np.pi - dih)
    diff = np.abs(psi_c - psi_np)
    diff = np.minimum(diff, 2 * np.pi - diff)     # +-pi: closed either way
    flat = np.abs(vol) < 1e-12                    # sign by rounding
    assert np.all(diff[~flat] < 1e-10)
    assert np.all(np.minimum(np.abs(psi_c[flat]), np.pi - np.abs(psi_c[flat])) < 1e-6)
    # pass-throughs between consecutive configurations: from C's angles
    # (psi jumps between +-pi) and from NumPy's volumes (sign change while
    # folded past 90 degrees)
    through_c = (np.abs(psi_c[:-1]) > np.pi / 2) & (np.abs(psi_c[1:]) > np.pi / 2) & \
                (np.sign(psi_c[:-1]) != np.sign(psi_c[1:]))
    firm = (np.abs(vol[:-1]) > 1e-12) & (np.abs(vol[1:]) > 1e-12)
    through_np = (dih[:-1] < np.pi / 2) & (dih[1:] < np.pi / 2) & (np.sign(vol[:-1]) != np.sign(vol[1:])) & firm
    assert np.array_equal(through_c & firm, through_np)
    return len(X), vol.size, int(through_np.sum())


def test_against_numpy_along_the_folds():
    """C's hinges and fold angles against NumPy's signed volumes and
    dihedral angles on configurations along the folds; at least 10^4 of
    them with LIBKIN_TEST_SLOW=1."""
    members = [(6, 1, 6), (8, 1, 6)] if not SLOW else [(6, 1, 50), (8, 1, 50), (6, 2, 70), (8, 2, 70)]
    total = pairs = through = 0
    for n, loops, per in members:
        c, p, t = _check_member(n, loops, per)
        total += c
        pairs += p
        through += t
    print(f"{total} configurations, {pairs} hinge-configurations, {through} pass-throughs between neighbours")
    assert total >= (10_000 if SLOW else 200)


def _event_member(n: int, loops: int, per: int) -> Tuple[int, int]:
    """Each hinge of member (n, loops) alone (its two panels, every bar a
    device: nothing else can touch), each leg of the fold followed with the
    contact event from the leg's start: where C stops against where NumPy,
    tracking the fold side along the dense legs, sees the hinge close or
    pass through. Returns (hinge-legs, events)."""
    res, legs = dense_fold(n, loops, per)
    S = res["samples"]
    starts = sorted(S.leave_dir)
    a0 = res["assembly"]
    panels = sail_panels(a0)
    ref = sorted(np_hinges(panels).items())
    checked = events = 0
    for (hj, (pa, pb)) in ref:
        Jh = np.array([hj])
        side = np.zeros(1)
        for li, q0 in enumerate(starts):
            leg = legs[li]
            X = np.array([x for x, _ in leg])
            L = np.array([l for _, l in leg]) - leg[0][1]
            vol, dih = np_volume_and_dihedral(X, Jh)
            first = np_events(vol, dih, side)[0]
            b = S.states[q0].clone()
            b.panels = [panels[pa], panels[pb]]
            b.device_bars = list(range(b.nbars))
            b.set_contact_events(True, 1e-9)
            if li > 0:
                b.coords = S.states[q0].coords
            fe = b.follow_event(S.leave_dir[q0], max_steps=600, max_length=L[-1] * 1.05)
            end = L[-1]
            if first <= len(L) - 1:
                lo, hi = L[first - 1], L[first]
                if hi < end - 1e-3:   # clear of the leg's end
                    assert fe.event == "contact", (hj, li, fe.event, lo, hi)
                    assert lo - 1e-6 <= fe.length <= hi + 1e-6, (hj, li, fe.length, lo, hi)
                    events += 1
            elif fe.event == "contact":
                assert fe.length >= end - 1e-3, (hj, li, fe.length, end)
            checked += 1
            # the side NumPy tracked to the leg's end, for the next leg
            s = 0.0
            for k in range(len(L)):
                if dih[k, 0] >= np.pi / 2:
                    s = 0.0
                elif dih[k, 0] > 1e-6:
                    s = float(np.sign(vol[k, 0]))
            side = np.array([s])
            if fe.event == "contact":
                break
    return checked, events


def test_events_against_numpy():
    """The contact event on each hinge alone along the folds, against NumPy."""
    members = [(6, 2, 6)] if not SLOW else [(6, 1, 20), (6, 2, 20), (8, 1, 20), (8, 2, 20)]
    checked = events = 0
    for n, loops, per in members:
        c, e = _event_member(n, loops, per)
        checked += c
        events += e
    print(f"{checked} hinge-legs followed, {events} hinge events located inside NumPy's bracket")
    assert checked > 0 and events > 0   # not void: the two-loop fold's leg 2 has them


def test_devices_and_model_file(tmp_path):
    a = libkin.Assembly.sail(6, 2)
    bars = np.asarray(a.bars)
    centre = list(a.labels).index("C")
    assert sorted(a.device_bars) == sorted(k for k in range(a.nbars) if centre in bars[k])
    path = tmp_path / "sail.json"
    doc = a.to_json(str(path))
    assert [k for k, bar in enumerate(doc["bars"]) if bar.get("device")] == a.device_bars
    b = libkin.Assembly.from_json(str(path))
    assert b.device_bars == a.device_bars
    c = libkin.load_model(str(path)) if hasattr(libkin, "load_model") else b   # the C loader
    assert c.device_bars == a.device_bars
    b.device_bars = []
    assert b.device_bars == []
    with pytest.raises(libkin.KinError):
        b.device_bars = [a.nbars]
    with pytest.raises(InvalidArgumentError):
        b.device_bars = [True]
