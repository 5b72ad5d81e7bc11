"""The radially sequential fold of a sail family member (studies/sequential.py)
and the paper's claim of one bifurcation per loop checked on it."""
import numpy as np

from libkin import Assembly
from libkin.studies.sailmeasure import bar_kinds, loop_of
from libkin.studies.sequential import claim_check, hub_circumradius, loop_radii, sequential_fold, wraps_loop1


def test_loop_of_tells_loop_3_from_the_centre_node():
    # a 3-loop sail's third loop is labelled C0, C1, ...: not the centre C
    assert loop_of("C") == -1
    assert loop_of("V2") == 0
    assert [loop_of(x) for x in ("A0", "B5", "C0", "C5", "D1")] == [1, 2, 3, 3, 4]
    a = Assembly.sail(6, 3)
    kinds = bar_kinds(a.labels, a.bars)
    labels = a.labels
    for (i, j), kind in zip(a.bars, kinds):
        if "C" in (labels[i], labels[j]):
            assert kind == "spoke"
        else:  # no bar of loop 3 is taken for a spoke
            assert kind != "spoke", (labels[i], labels[j])


def test_loop_radii_of_the_flat_sail_grow_outwards():
    a = Assembly.sail(8, 3)
    r = loop_radii(a.coords, list(a.labels), 3, hub_circumradius(a.coords, list(a.labels)))
    assert all(1.0 < x < y for x, y in zip(r, r[1:]))
    assert not wraps_loop1(a.coords, list(a.labels), 8)


def test_one_loop_folds_in_one_leg_to_a_bifurcation_with_loop_1_wrapped():
    r = sequential_fold(6, 1, keep_states=True)
    legs = r["legs"]
    assert len(legs) == 1 and legs[0]["event"] == "bifurcation"
    assert (legs[0]["m"], legs[0]["s"]) == (4, 3)
    assert abs(legs[0]["loop_radii"][0] - 1.0) < 1e-6  # loop 1 over the hub's outline
    assert r["stop"].startswith("fold complete")
    c = claim_check(r)
    assert c["count_holds"] and c["all_sequential"]
    s = r["samples"]
    # the samples run along the path: lengths increase, and the last is the bifurcation
    assert np.all(np.diff(s.l) > 0)
    assert abs(s.l[-1] - legs[0]["l_end"]) < 1e-12
    assert len(s.states) == len(s.coords) == len(s.l)
    assert wraps_loop1(s.coords[-1], list(r["assembly"].labels), 6)
