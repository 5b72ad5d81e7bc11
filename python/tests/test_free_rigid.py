"""The test function on free structures (issue 36 item 1).

A free two-triangle crease has six rigid-body mechanisms; the SVD's basis of
their span turns freely from one point to the next, and the test function's
sign must not turn with it: no sign change of tau along the fold, and
``locate`` and ``explore`` report no bifurcation and no near miss.
"""
import numpy as np
import pytest

import libkin
from libkin.errors import KinError
from libkin.io.fold.reader import read_fold

CREASE = {"vertices_coords": [[0, 0], [1, 0], [1, 1], [0, 1]],
          "edges_vertices": [[0, 1], [1, 2], [2, 3], [3, 0], [3, 1]],
          "edges_assignment": ["B", "B", "B", "B", "V"],
          "faces_vertices": [[0, 1, 3], [1, 2, 3]]}


def test_free_crease_tau_keeps_its_sign():
    a = read_fold(CREASE)
    an = a.analyse()
    assert (an.m_rigid, an.m_internal) == (6, 1)
    signs = [np.sign(a.test_function())]
    for _ in range(80):
        a.step(0.05)
        signs.append(np.sign(a.test_function()))
    assert len(set(signs)) == 1, signs


def test_free_crease_locate_finds_nothing():
    a = read_fold(CREASE)
    with pytest.raises(KinError) as err:
        a.locate(max_steps=200)
    assert "near" not in str(err.value) and "changed sign" not in str(err.value)


def test_free_crease_explore_no_near_miss():
    atlas = libkin.explore(read_fold(CREASE))
    events = {e.event for e in atlas.edges}
    assert events and events <= {"loop", "step_limit", "length_limit"}, events
    assert not any(n.kind != "regular" for n in atlas.nodes)
