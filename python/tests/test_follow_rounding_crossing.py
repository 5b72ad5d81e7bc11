"""A crossing that the model's rounding broke is a bifurcation (issue 35).

The fixture is a follow task of the hexagonal sail's depth-5 atlas (model
sail:6:2 as the explorer sends it, start, direction): its path passes a
crossing at v_r / v_max ~ 1.2e-8, a minimum no location brings to the
strict tolerance, and the follower used to end it "undecided" (a relaxed
point below the minimum it found). Moore's extended system proves there an
exactly singular configuration of a structure whose bar lengths are within
~1e-14 of the given ones, so the end is that configuration: a bifurcation
with m = 2, s = 1 at the strict tolerance, whose bars keep their lengths to
the rounding of the model (docs/follow.md, "Tolerance out of reach")."""
import json
import pathlib

import numpy as np
import pytest

from libkin.io.model_json import load_json
from libkin.parallel import one_blas_thread

DATA = pathlib.Path(__file__).parent / "data" / "rounding_crossing_sail62.json"


@pytest.fixture(scope="module")
def task():
    return json.loads(DATA.read_text())


def _start(task):
    a = load_json(json.dumps(task["model"], sort_keys=True))
    o = a.options
    o.rank_tol = float(task["rank_tol"])
    a.options = o
    a.coords = np.asarray(task["coords"], dtype=float)
    return a


def test_rounding_crossing_is_a_bifurcation(task):
    a = _start(task)
    with one_blas_thread():
        ev = a.follow_event(np.asarray(task["direction"]), max_length=float(task["max_length"]),
                            max_steps=int(task["max_steps"]), samples=0)
    assert ev.event == "bifurcation"
    assert (ev.m_internal, ev.s) == (2, 1)
    assert ev.v_r_rel <= 1e-10 and ev.vr_tol_used == 1e-10
    # the end keeps the bar lengths to the rounding of the model
    rms = float(np.sqrt(np.mean(np.asarray(a.rest_lengths) ** 2)))
    assert a.max_strain <= 1e-12
    # and the proof holds there, for lengths within 1e-12 of the RMS length
    p = a.prove_singular()
    assert p.proven and p.corank == 1 and p.dlength <= 1e-12 * rms


def test_end_is_the_proofs_point(task):
    """the end is the exactly singular configuration itself, to rounding:
    proven again there, the singular point is within 1e-12 of the RMS length
    (from the undecided point it was 1.5e-7 away), and the path's lowest
    singular value there is at the rounding of the equilibrium matrix"""
    a = _start(task)
    with one_blas_thread():
        ev = a.follow_event(np.asarray(task["direction"]), max_length=float(task["max_length"]),
                            max_steps=int(task["max_steps"]), samples=0)
        p = a.prove_singular()
    rms = float(np.sqrt(np.mean(np.asarray(a.rest_lengths) ** 2)))
    assert p.proven and p.distance <= 1e-12 * rms
    assert ev.v_r_rel <= 1e3 * np.finfo(float).eps
