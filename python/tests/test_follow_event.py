"""Assembly.follow_event (kin_follow_event) and the command line's --branch."""
import subprocess
import sys

import numpy as np
import pytest

import libkin
from libkin.errors import AtBifurcationError, InvalidArgumentError

RA = np.array([[-1.0, 0.0], [0.0, 0.0]])
RB = np.array([[1.0, 0.0], [0.0, 0.0]])


def test_three_bar_branches_reach_the_other_bifurcations():
    """From R^C every directed branch ends at R^A or R^B (paper Figure 1)."""
    a = libkin.Assembly.threebar("RC")
    betas, _ = libkin.solve_quadrics(a.second_order())
    U = a.analyse().internal_mechanisms
    ends = []
    for k in range(2 * len(betas)):
        b = libkin.Assembly.threebar("RC")
        ev = b.follow_event((1 if k % 2 == 0 else -1) * (U @ betas[k // 2]))
        assert isinstance(ev, libkin.FollowEvent)
        assert ev.event == "bifurcation" and ev.status == "KIN_OK" and ev.m_internal == 2 and ev.s == 1
        assert ev.v_r_rel <= ev.vr_tol_used <= 1e-6 and ev.length > 0
        j = b.coords[:2]
        ends.append("RA" if np.allclose(j, RA, atol=1e-6) else "RB" if np.allclose(j, RB, atol=1e-6) else "?")
    assert sorted(ends) == ["RA", "RA", "RB", "RB"]


def test_failures_and_refusals():
    a = libkin.Assembly.threebar("RC")
    with pytest.raises(AtBifurcationError):
        a.follow_event()
    with pytest.raises(InvalidArgumentError):
        a.follow_event(np.zeros(3))
    with pytest.raises(InvalidArgumentError):
        a.follow_event(np.array([0.0, 1.0, 0.0, 1.0]), vr_floor=1e-12)
    # a first-order mechanism that is not a branch: a classified failure
    ev = a.follow_event(np.array([0.0, 1.0, 0.0, 0.0]))
    assert ev.event == "failed" and ev.status == "KIN_EPATHJUMP" and ev.message
    ev = libkin.Assembly.threebar("RC").follow_event(np.array([0.0, 1.0, 0.0, 1.0]), max_steps=2)
    assert ev.event == "step-limit" and ev.steps == 2


def run_cli(*args):
    return subprocess.run([sys.executable, "-m", "libkin", *args], capture_output=True, text=True, timeout=120)


def test_cli_branch():
    r = run_cli("locate", "threebar:RC", "--branch", "3")
    assert r.returncode == 0, r.stderr
    assert "bifurcation after" in r.stdout and "m = 2, s = 1" in r.stdout
    r = run_cli("follow", "threebar:RC", "--branch", "0", "--steps", "3", "--quiet")
    assert r.returncode == 0, r.stderr
    assert "3 steps" in r.stdout
    r = run_cli("locate", "threebar:RC", "--branch", "4")
    assert r.returncode != 0 and "--branch 4" in r.stderr


def test_cli_locate_falls_back_to_the_reachable_accuracy():
    """The lifted hexagonal sail's flat state: 1e-10 is out of reach; the
    fast locator's refusal is followed by kin_follow_event, which locates it
    to the accuracy reachable there (m = 16, s = 15)."""
    r = run_cli("locate", "sail:6:2", "--perturb", "0.3")
    assert r.returncode == 0, r.stderr
    assert "bifurcation after" in r.stdout and "m = 16, s = 15" in r.stdout
