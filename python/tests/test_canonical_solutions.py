"""Same answer whatever basis the SVD returns (issue 35): the mechanism
basis U of kin_analyse, the self-stress basis (the mixing of the Q_j) and
the symmetric subspace's basis are arbitrary choices that another OpenBLAS
kernel or thread count makes differently. Here every one of them is turned
by a fixed random orthogonal matrix (monkeypatched on the Python side, the
C calls given back their own basis): the second-order solutions, as
physical directions U beta, come back in the same order with the same
signs (assembly/_canonical.py), and the atlas and the study's summary are
the same."""
import dataclasses
import json
import pathlib

import numpy as np
import pytest

import libkin
from libkin.assembly import _base, _branching
from libkin.symmetry import automorphisms, cyclic

EXPECTED = pathlib.Path(__file__).resolve().parents[2] / "examples" / "sail_study"


def _orthogonal(n, seed):
    q, r = np.linalg.qr(np.random.default_rng(seed).standard_normal((n, n)))
    return q * np.sign(np.diag(r))  # a random rotation or reflection, not near the identity


@pytest.fixture
def rotated(monkeypatch):
    """Turn U by R_m, mix the Q_j by O_s and turn the symmetric subspace by
    S_k (fixed matrices per size, so repeated analyses agree); the C calls
    that take betas get them back in C's basis."""
    R = lambda m: _orthogonal(m, 100 + m)  # noqa: E731
    O = lambda s: _orthogonal(s, 200 + s)  # noqa: E731
    S = lambda k: _orthogonal(k, 300 + k)  # noqa: E731
    raw = {"on": False}
    analyse, second_order = _base.AssemblyBase.analyse, _branching.BranchingMixin.second_order
    follow_branches, solver_group = _branching.BranchingMixin.follow_branches, _branching.BranchingMixin.solver_group
    invariant, symmetric = automorphisms.invariant_subspace, cyclic.symmetric_subspace

    def turned_analyse(self, *a, **k):
        an = analyse(self, *a, **k)
        if raw["on"]:
            return an
        U = an.internal_mechanisms
        return dataclasses.replace(an, internal_mechanisms=np.asfortranarray(U @ R(U.shape[1])))

    def turned_second_order(self, *a, **k):
        Q = second_order(self, *a, **k)
        s, m = Q.shape[0], Q.shape[1]
        return np.einsum("jk,xa,kxy,yb->jab", O(s), R(m), Q, R(m))

    def c_basis(Q):  # the inverse of turned_second_order
        s, m = Q.shape[0], Q.shape[1]
        return np.einsum("kj,ax,kxy,by->jab", O(s), R(m), Q, R(m))

    def raw_follow_branches(self, betas, *a, **k):
        b = np.atleast_2d(np.asarray(betas, dtype=float))
        raw["on"] = True
        try:
            return follow_branches(self, b @ R(b.shape[1]).T, *a, **k)
        finally:
            raw["on"] = False

    def turned_solver_group(self, Q, seed=1):
        raw["on"] = True
        try:
            G = solver_group(self, c_basis(Q), seed)
        finally:
            raw["on"] = False
        m = Q.shape[1]
        return None if G is None else np.einsum("xa,gxy,yb->gab", R(m), G, R(m))

    monkeypatch.setattr(_base.AssemblyBase, "analyse", turned_analyse)
    monkeypatch.setattr(_branching.BranchingMixin, "second_order", turned_second_order)
    monkeypatch.setattr(_branching.BranchingMixin, "follow_branches", raw_follow_branches)
    monkeypatch.setattr(_branching.BranchingMixin, "solver_group", turned_solver_group)
    monkeypatch.setattr(automorphisms, "invariant_subspace", lambda U, P: (lambda G: G @ S(G.shape[1]))(invariant(U, P)))
    monkeypatch.setattr(cyclic, "symmetric_subspace", lambda U, P: (lambda G: G @ S(G.shape[1]))(symmetric(U, P)))
    return R


def _solve(a):
    br = a.branches(solver="homotopy", length=0.05)
    return br, [(p.beta, p.sign, p.exists, round(p.length, 9)) for p in br.paths]


@pytest.mark.parametrize("spec", [(4, 1), (6, 1)])
def test_branches_are_the_same_directions_in_any_basis(spec, request):
    """Assembly.branches: the same directions U beta, row for row (order and
    sign), and the same paths, with the basis turned."""
    a = libkin.Assembly.sail(*spec)
    ref, ref_paths = _solve(a)
    U0 = a.analyse().internal_mechanisms
    request.getfixturevalue("rotated")
    U1 = a.analyse().internal_mechanisms
    assert np.abs(U1 - U0).max() > 0.1  # turned
    got, got_paths = _solve(a)
    assert len(got.directions) == len(ref.directions) >= 4
    assert np.abs(got.directions - ref.directions).max() < 1e-8
    assert got_paths == ref_paths


def test_solve_quadrics_orders_by_the_basis_given():
    """solve_quadrics(Q', basis=U') for a turned U' = U R, Q' = R^T Q R (and
    mixed equations): the same directions row for row."""
    a = libkin.Assembly.sail(6, 1)
    U, Q = a.analyse().internal_mechanisms, a.second_order()
    s, m = Q.shape[0], Q.shape[1]
    R, O = _orthogonal(m, 7), _orthogonal(s, 8)
    Q2 = np.einsum("jk,xa,kxy,yb->jab", O, R, Q, R)
    b1, _ = libkin.solve_quadrics(Q, basis=U)
    b2, _ = libkin.solve_quadrics(Q2, basis=U @ R)
    assert len(b1) >= 4 and np.abs(b1 @ U.T - b2 @ (U @ R).T).max() < 1e-8


def test_canonical_key():
    """The key: w_0 . d > 0, then increasing w_1 . d, for fixed unit vectors
    of generic entries (the same in every run and on every machine: integer
    arithmetic); any order and signs in, the same out; a tie on w_1 is
    ordered by w_2."""
    from libkin.assembly import canonical_order
    from libkin.assembly._canonical import generic_vectors
    W = generic_vectors(5)
    assert W.shape == (4, 5) and np.allclose(np.linalg.norm(W, axis=1), 1.0)
    assert np.array_equal(W, generic_vectors.__wrapped__(5))
    assert np.round(W[0], 12).tolist() == np.round(generic_vectors.__wrapped__(9)[0, :5] /
                                                   np.linalg.norm(generic_vectors.__wrapped__(9)[0, :5]), 12).tolist()
    rng = np.random.default_rng(3)
    b = rng.standard_normal((9, 5))
    c, perm, sign = canonical_order(b)
    assert sorted(perm) == list(range(9)) and np.allclose(c, b[perm] * sign[:, None])
    unit = c / np.linalg.norm(c, axis=1)[:, None]
    assert (unit @ W[0] > 0).all() and (np.diff(unit @ W[1]) > 0).all()
    c2, _, _ = canonical_order(b[rng.permutation(9)] * rng.choice([-1.0, 1.0], 9)[:, None])
    assert np.array_equal(c2, c)
    # two unit directions with the same w_1 key to 1e-12: ordered by w_2, whichever comes first
    d0 = unit[0]
    for v in rng.standard_normal((20, 5)):  # d1: d0 reflected in a hyperplane that holds w_1
        v -= (v @ W[1]) * W[1]
        v /= np.linalg.norm(v)
        d1 = d0 - 2.0 * (v @ d0) * v
        if d1 @ W[0] > 0.1 and abs((d1 - d0) @ W[2]) > 0.1:
            break
    assert abs((d1 - d0) @ W[1]) < 1e-12 and d1 @ W[0] > 0.1
    first = min((d0, d1), key=lambda d: d @ W[2])
    for pair in ([d0, d1], [d1, d0]):
        out, _, _ = canonical_order(np.array(pair))
        assert np.array_equal(out[0], first)


def test_atlas_is_the_same_in_any_basis(request):
    """explore(): the same atlas (nodes; edges with their solution numbers
    and signs) with every basis turned, plain and symmetric."""
    # (not sail:6:1's plain atlas: of its 940 branches some end in a follower failure whose point
    # moves by 1e-5 with the direction's last digits, and is then taken for another such end or not)
    runs = (("sail:4:1", {"depth": 1}), ("sail:4:1", {"depth": 2, "symmetric": True}),
            ("sail:6:1", {"depth": 2, "symmetric": True}))
    ref = [libkin.explore(model, **kw) for model, kw in runs]
    request.getfixturevalue("rotated")
    for (model, kw), r in zip(runs, ref):
        got = libkin.explore(model, **kw)
        assert len(got.edges) >= 10
        _same_atlas(got, r)


def _same_atlas(a, b, tol=1e-7):
    """Atlas.same_as, except that a point is compared to what it was located
    to (a bifurcation located only to v_r / v_max <= 1e-6 moves by 1e-6 with
    the direction's last digits: the explorer's own identification tolerance,
    LOCATION_FACTOR sqrt(located_tol)), as are the lengths of the edges to
    it; and where the follower failed (such an end moves by up to 1e-5) the
    point and length are not compared."""
    from libkin.atlas.model import LOCATION_FACTOR
    assert len(a.nodes) == len(b.nodes) and len(a.edges) == len(b.edges)
    near = {}
    for x, y in zip(a.nodes, b.nodes):
        assert (x.kind, x.m, x.s, x.orbit, x.expanded) == (y.kind, y.m, y.s, y.orbit, y.expanded), x.id
        near[x.id] = max(tol, LOCATION_FACTOR * np.sqrt(max(x.located_tol, y.located_tol, 0.0)))
        scale = max(1.0, np.abs(x.coords).max())
        assert x.kind == "failure" or np.abs(x.coords - y.coords).max() <= near[x.id] * scale, x.id
    for e, f in zip(a.edges, b.edges):
        assert (e.source, e.target, e.solution, e.sign, e.event) == (f.source, f.target, f.solution, f.sign, f.event), e.id
        assert e.event == "failure" or abs(e.length - f.length) <= near[e.target] * max(1.0, e.length), e.id
        # the stored first direction is physical (sign U beta), so a turned basis leaves it
        # alone up to the solver's last digits (it was beta, in the turned basis's coordinates)
        assert len(e.direction) == len(f.direction) > 0, e.id
        assert np.abs(np.asarray(e.direction) - np.asarray(f.direction)).max() <= 1e-8, e.id
        assert abs(np.linalg.norm(e.direction) - 1.0) <= 64 * np.finfo(float).eps, e.id


def test_study_summary_is_the_same_in_any_basis(rotated, tmp_path):
    """The hexagonal sail's study (--quick) with every basis turned: the
    summary of the stored run, the chosen solutions and signs included."""
    from libkin.studies import sailstudy
    from test_sail_study import _compare
    sailstudy.hexagonal_study(complete=False, progress=False, out=tmp_path)
    got = json.loads((tmp_path / "summary.json").read_text())
    exp = json.loads((EXPECTED / "hex_quick" / "summary.json").read_text())
    _compare(got, exp)
    for k in ("depth", "nodes", "edges", "node_kinds", "edge_events"):
        assert got["map"]["atlas"][k] == exp["map"]["atlas"][k], k
    assert (got["flat"]["chosen"]["beta"], got["flat"]["chosen"]["sign"]) == \
        (exp["flat"]["chosen"]["beta"], exp["flat"]["chosen"]["sign"])
