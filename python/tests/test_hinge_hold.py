"""Held hinges (follow_event(hold_hinges=True), docs/contact.md "Held
hinges"): a hinge that closes is held closed, the follow goes on with it
held where the structure still moves, and the hold is released only along
a motion that opens it.

- A square sheet folded in half, then in half again (a degree-4 vertex of
  four right triangles around C, tests/test_hinge_hold.c): folding along
  the first line closes its two hinges; held, the follow goes on along the
  second line with them closed, their far corners together to rounding and
  no hinge through flat-folded anywhere, and ends 'held-rigid' at four
  layers; back along each line reopens its hinges.
- The hexagonal one-loop sail: its fold closes the loop-1 trapezia at R^B,
  and with them held the structure has no motion ('held-rigid'); the
  two-loop sail's leg 2 out of R^B presses them through and is refused.
"""
from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import libkin
from libkin.errors import InvalidArgumentError
from libkin.studies.sailmeasure import sail_panels
from libkin.studies.sequential import sequential_fold


def vertex(rho: float) -> libkin.Assembly:
    """The vertex folded by rho along its first line (the x axis)."""
    X = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -np.cos(rho), -np.sin(rho)]], float)
    bars = [(0, 1), (0, 2), (0, 3), (0, 4), (1, 2), (2, 3), (3, 4), (4, 1)]
    fixed = np.zeros((5, 3), bool)
    fixed[0] = True
    fixed[1, 1:] = True
    fixed[2, 2] = True
    a = libkin.Assembly(X, bars, fixed=fixed)
    a.panels = [[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 1]]
    a.device_bars = [4, 5, 6, 7]  # the outer edges: stacked layers' edges touch at zero thickness
    a.set_contact_events(True, 1e-9)
    return a


def no_pass_through(a: Any, samples: np.ndarray) -> bool:
    """No hinge's fold angle jumps between +-pi while it is open."""
    psi = np.array([a.hinge_angles(x) for x in samples])
    jump = (np.abs(np.diff(psi, axis=0)) > np.pi) & (np.pi - np.abs(psi[1:]) > 1e-6)
    return not jump.any()


def test_fold_in_half_twice() -> None:
    a = vertex(np.pi / 2)
    # hinges sorted by edge: 0 = C-E1, 1 = C-E2, 2 = C-E3, 3 = C-E4
    ev = a.follow_event(hold_hinges=True, samples=60)
    assert ev.event == "hinge-closed" and ev.held == 2 and ev.held_m == 1 and ev.hinge in (0, 2)
    assert no_pass_through(a, ev.samples)
    ev = a.follow_event(hold_hinges=True, samples=60)
    assert ev.event == "held-rigid" and ev.held == 4 and ev.held_m == 0 and ev.reopened == 0
    assert len(ev.samples) > 4 and ev.length > 3.0
    S = ev.samples
    psi = np.array([a.hinge_angles(x) for x in S])
    assert (np.pi - np.abs(psi[:, [0, 2]]) <= 1e-6).all()          # held closed all the way
    assert np.linalg.norm(S[:, 2] - S[:, 4], axis=1).max() <= 64 * np.finfo(float).eps  # far corners
    assert no_pass_through(a, S)
    assert abs(a.coords[3, 0] - 1.0) <= 1e-6                         # E3 onto E1: four layers
    on, back2, back1 = np.zeros(9), np.zeros(9), np.zeros(9)
    on[5], back2[5], back1[8] = -1.0, 1.0, -1.0                      # E3's z, E4's z
    with pytest.raises(InvalidArgumentError):
        a.follow_event(on, hold_hinges=True)                          # presses the layers through
    ev = a.follow_event(back2, hold_hinges=True, samples=60)
    assert ev.reopened == 2 and ev.event == "bifurcation" and ev.held == 2 and ev.held_m == 1
    assert no_pass_through(a, ev.samples)
    ev = a.follow_event(back1, hold_hinges=True, samples=60)
    assert ev.reopened == 2 and ev.event == "bifurcation" and ev.held == 0
    assert np.abs(a.hinge_angles()).max() <= 1e-6                     # flat again


def test_without_holds_the_same_fold_stops_at_contact() -> None:
    a = vertex(np.pi / 2)
    ev = a.follow_event()
    assert ev.event == "contact" and ev.held == 0 and ev.held_m == -1


def test_sail_locked_at_rb_is_rigid() -> None:
    res = sequential_fold(6, 2, keep_states=True)
    S = res["samples"]
    a = res["assembly"].clone()
    a.panels = sail_panels(a)
    a.set_contact_events(True, 1e-9)
    ev = a.follow_event(S.leave_dir[0], max_steps=800, hold_hinges=True)
    assert ev.event in ("hinge-closed", "held-rigid") and ev.held == 6
    assert ev.length == pytest.approx(res["legs"][0]["l_end"], abs=1e-3)
    ev = a.follow_event(hold_hinges=True)
    assert ev.event == "held-rigid" and ev.held == 6 and ev.held_m == 0 and ev.length == 0.0
    starts = sorted(S.leave_dir)
    a.coords = S.states[starts[1]].coords
    with pytest.raises(InvalidArgumentError):
        a.follow_event(S.leave_dir[starts[1]], max_steps=800, hold_hinges=True)
