"""Numbers from the paper through the Python API."""
import numpy as np
import pytest

import libkin


def test_threebar_rc_eq27():
    a = libkin.Assembly.threebar("RC")
    an = a.analyse()
    assert (an.rank, an.m, an.s, an.m_internal, an.m_rigid) == (2, 2, 1, 2, 0)
    np.testing.assert_allclose(an.singular_values[:2], [np.sqrt(3), 1.0], rtol=1e-15)
    H = a.equilibrium_matrix()
    assert H.shape == (4, 3)
    # invariants: H^T U_m = 0, H W_s = 0, orthonormal columns
    assert np.abs(H.T @ an.internal_mechanisms).max() < 1e-15
    assert np.abs(H @ an.self_stresses).max() < 1e-15
    np.testing.assert_allclose(an.internal_mechanisms.T @ an.internal_mechanisms, np.eye(2), atol=1e-15)
    np.testing.assert_allclose(np.abs(an.self_stresses[:, 0]), np.full(3, 1 / np.sqrt(3)), rtol=1e-15)


def test_sails():
    sq = libkin.Assembly.sail(4, 1).analyse()
    assert (sq.rank, sq.m, sq.m_rigid, sq.m_internal, sq.s) == (12, 6, 1, 5, 4)
    hx = libkin.Assembly.sail(6, 2)
    assert (hx.nfree, hx.nbars) == (46, 45)
    an = hx.analyse()
    assert (an.m, an.s) == (16, 15)
    assert an.internal_mechanisms.shape == (46, 16) and an.self_stresses.shape == (45, 15)


def test_follow_parallelogram():
    a = libkin.Assembly.threebar("RC")
    xyz = a.coords
    xyz[:2] = [[0.6, 0.8], [1.6, 0.8]]
    a.coords = xyz
    infos = list(a.follow(steps=10, delta=0.05))
    assert len(infos) == 10 and all(i.m_internal == 1 for i in infos)
    c = a.coords
    np.testing.assert_allclose(c[1] - c[0], [1.0, 0.0], atol=1e-12)
    assert a.max_strain <= 1e-12
    assert abs(a.path_length - infos[-1].l) == 0
    t = a.tangent()
    assert abs(np.linalg.norm(t) - 1) < 1e-14
    b = a.clone()
    assert np.array_equal(b.coords, a.coords)
    assert len(list(a.follow(length=0.2, delta=0.05))) >= 4


def test_leave_bifurcation_along_chosen_direction():
    a = libkin.Assembly.threebar("RC")
    a.set_direction([0, 1.0, 0, 1.0])
    a.step(1e-3)
    for _ in range(5):
        a.step(0.05)
    c = a.coords
    np.testing.assert_allclose(c[1] - c[0], [1.0, 0.0], atol=1e-12)


@pytest.mark.parametrize("solver", ["homotopy", "scan"])
def test_branches_square_sail(solver):
    a = libkin.Assembly.sail(4, 1)
    br = a.branches(solver=solver, starts=512, length=1.75)
    if solver == "homotopy":
        assert br.accounting["paths"] == 16 and br.accounting["real_distinct"] == 16
    assert br.betas.shape == (16, 5)
    assert len(br.paths) == 32 and br.distinct == 32
    assert all(p.exists and p.tangent_ok for p in br.paths)
    Q = a.second_order()
    for b in br.betas:
        assert np.abs(np.einsum("i,jik,k->j", b, Q, b)).max() < 1e-10


def test_branches_threebar_and_errors():
    a = libkin.Assembly.threebar("RC")
    br = a.branches(solver="scan", starts=32, length=0.5)
    assert br.betas.shape == (2, 2) and br.distinct == 4
    xyz = a.coords
    xyz[:2] = [[0.6, 0.8], [1.6, 0.8]]
    a.coords = xyz
    with pytest.raises(libkin.errors.StateError):
        a.branches()


@pytest.mark.parametrize("method", ["fast", "paper", "illinois"])
def test_locate_rc_from_p1(method):
    a = libkin.Assembly.threebar("RC")
    xyz = a.coords
    xyz[:2] = [[0.6, 0.8], [1.6, 0.8]]
    a.coords = xyz
    assert a.test_function() != 0
    info = a.locate(method=method, delta=0.1)
    assert info.located and info.path_kept and info.v_r_rel <= 1e-10 and (info.m_internal, info.s) == (2, 1)
    np.testing.assert_allclose(a.coords[:2], [[1, 0], [2, 0]], atol=1e-9)
    with pytest.raises(libkin.errors.AtBifurcationError):
        a.locate()


def test_current_analysis_is_the_last_one_while_it_holds():
    """Assembly.current_analysis(): the last analysis while the configuration
    and options are unchanged (no SVD made), None once either changes; after
    following to a bifurcation, the follower's analysis of the end, the same
    to the bit as analysing again (what atlas tasks read)."""
    a = libkin.Assembly.threebar("RC")
    assert a.current_analysis() is None  # nothing analysed yet
    an = a.analyse()
    cur = a.current_analysis()
    assert cur is not None and (cur.rank, cur.m_internal, cur.s, cur.v_r, cur.v_max) == (
        an.rank, an.m_internal, an.s, an.v_r, an.v_max)
    np.testing.assert_array_equal(cur.singular_values, an.singular_values)
    np.testing.assert_array_equal(cur.internal_mechanisms, an.internal_mechanisms)
    xyz = a.coords
    xyz[:2] = [[0.6, 0.8], [1.6, 0.8]]
    a.coords = xyz
    assert a.current_analysis() is None  # the configuration changed
    a.analyse()
    o = a.options
    o.rank_tol = 1e-7
    a.options = o
    assert a.current_analysis() is None  # the options changed
    b = libkin.Assembly.threebar("RC")
    betas, _ = libkin.solve_quadrics(b.second_order())
    ev = b.follow_event(b.analyse().internal_mechanisms @ betas[0])
    assert ev.event == "bifurcation"
    cur = b.current_analysis()
    assert cur is not None
    again = b.analyse()
    assert (cur.m_internal, cur.m_rigid, cur.s, cur.v_r, cur.v_max) == (
        again.m_internal, again.m_rigid, again.s, again.v_r, again.v_max)
