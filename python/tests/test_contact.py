"""The C clearance (kin_clearance) against an independent reference in numpy.

The reference shares nothing with the C code: every pair of parts that share
no joint is bounded (bounding spheres below, closest corners above; no tree),
and the pairs that could hold the minimum are solved exactly as the convex
quadratic program they are: the closest points of two simplices (a segment
or a triangle) lie in the relative interior of some pair of their faces,
where they are the unconstrained least-squares solution in the two faces'
affine hulls; every face pair is solved (pseudo-inverse) and the feasible
solutions kept. python-fcl's GJK distance is good to about 1e-6 only, so it
cannot check 1e-9; this reference can (docs/contact.md).

LIBKIN_TEST_SLOW=1 runs 10,100 configurations (sails with their bar triangles
as panels, perturbed, along straight paths between foldings, and random
frameworks; about 6 minutes on the shared 2-core machine); the normal suite
runs a fifth of them.
"""
from __future__ import annotations

import itertools
import os

import numpy as np
import pytest

import libkin
from libkin.io.fold.writer import graph_triangles

SLOW = os.environ.get("LIBKIN_TEST_SLOW") == "1"
REL = 1e-9

# the faces of a simplex with k vertices (as index tuples)
_FACES = {k: [c for r in range(1, k + 1) for c in itertools.combinations(range(k), r)] for k in (2, 3)}


def _simplex_distance(P: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """Distances of simplices P[n, kp, 3] and Q[n, kq, 3] (batched)."""
    n = P.shape[0]
    best = np.full(n, np.inf)
    for fp in _FACES[P.shape[1]]:
        for fq in _FACES[Q.shape[1]]:
            p0, q0 = P[:, fp[0]], Q[:, fq[0]]
            cols = [P[:, i] - p0 for i in fp[1:]] + [-(Q[:, j] - q0) for j in fq[1:]]
            r = p0 - q0
            if cols:
                M = np.stack(cols, axis=2)                     # n x 3 x k
                w = -np.einsum("nij,nj->ni", np.linalg.pinv(M), r)
                a = w[:, :len(fp) - 1]
                b = w[:, len(fp) - 1:]
                wa = np.concatenate([1 - a.sum(1, keepdims=True), a], 1)
                wb = np.concatenate([1 - b.sum(1, keepdims=True), b], 1)
                ok = (wa >= -1e-12).all(1) & (wb >= -1e-12).all(1)
                wa = np.clip(wa, 0, None)
                wa /= wa.sum(1, keepdims=True)
                wb = np.clip(wb, 0, None)
                wb /= wb.sum(1, keepdims=True)
                x = np.einsum("nk,nkd->nd", wa, P[:, list(fp)])
                y = np.einsum("nk,nkd->nd", wb, Q[:, list(fq)])
                d = np.where(ok, np.linalg.norm(x - y, axis=1), np.inf)
            else:
                d = np.linalg.norm(r, axis=1)
            best = np.minimum(best, d)
    return best


class Reference:
    """All pairs of non-adjacent parts of one model, bounded in numpy."""

    def __init__(self, bars: np.ndarray, panels: list, radii: np.ndarray, thick: np.ndarray) -> None:
        nb = len(bars)
        # primitives: bars and fan triangles, with part ids and radii
        segs = [list(b) for b in bars]
        tris, tpart = [], []
        for i, f in enumerate(panels):
            for q in range(1, len(f) - 1):
                tris.append([f[0], f[q], f[q + 1]])
                tpart.append(nb + i)
        self.segs = np.array(segs, dtype=int).reshape(-1, 2)
        self.tris = np.array(tris, dtype=int).reshape(-1, 3)
        joints = [set(b) for b in segs] + [set(f) for f in panels]
        sr = np.asarray(radii, float)
        tr = np.array([0.5 * thick[p - nb] for p in tpart])
        prims = [(2, k, k, sr[k]) for k in range(nb)] + [(3, t, tpart[t], tr[t]) for t in range(len(tris))]
        self.pairs = {}
        for x in range(len(prims)):
            for y in range(x + 1, len(prims)):
                kx, ix, px, rx = prims[x]
                ky, iy, py, ry = prims[y]
                if px == py or joints[px] & joints[py]:
                    continue
                key = (kx, ky) if kx <= ky else (ky, kx)
                first, second = ((ix, iy) if kx <= ky else (iy, ix))
                self.pairs.setdefault(key, []).append((first, second, rx + ry))
        self.pairs = {k: np.array(v) for k, v in self.pairs.items()}

    def clearance(self, x: np.ndarray) -> float:
        if x.shape[1] == 2:
            x = np.hstack([x, np.zeros((len(x), 1))])
        groups = []
        for (ka, kb), arr in self.pairs.items():
            A = x[(self.segs if ka == 2 else self.tris)[arr[:, 0].astype(int)]]
            B = x[(self.segs if kb == 2 else self.tris)[arr[:, 1].astype(int)]]
            groups.append((A, B, arr[:, 2]))
        if not groups:
            return np.inf
        # bounds: corners above, spheres below
        ub = min((np.linalg.norm(A[:, :, None] - B[:, None], axis=3).min((1, 2)) - r).min() for A, B, r in groups)
        best = np.inf
        for A, B, r in groups:
            ca, cb = A.mean(1), B.mean(1)
            ra = np.linalg.norm(A - ca[:, None], axis=2).max(1)
            rb = np.linalg.norm(B - cb[:, None], axis=2).max(1)
            lb = np.linalg.norm(ca - cb, axis=1) - ra - rb - r
            sel = lb <= ub + 1e-12 * (1 + abs(ub))
            if sel.any():
                best = min(best, float((_simplex_distance(A[sel], B[sel]) - r[sel]).min()))
        return best


def _agree(c: float, ref: float, scale: float) -> bool:
    """1e-9 relative to the clearance, or to the model's size near zero."""
    return abs(c - ref) <= REL * max(abs(ref), scale)


def _sail(n: int, k: int, t: float):
    a = libkin.Assembly.sail(n, k)
    a.panels = graph_triangles(a.bars)
    a.thickness = t
    # the references here know parts, not hinges nor devices (test_hinges.py)
    a.hinge_contact = False
    a.device_bars = []
    return a


@pytest.mark.parametrize("n,k,count", [(4, 1, 1500), (6, 1, 2000), (4, 2, 1500), (6, 2, 1500)])
def test_sails_random_and_paths(n, k, count):
    count = count if SLOW else count // 5
    rng = np.random.default_rng(100 * n + k)
    a = _sail(n, k, 0.0)
    x0 = a.coords
    scale = float(np.sqrt(np.mean(a.rest_lengths ** 2)))
    missed = contacts = 0
    worst = 0.0
    for trial in range(count):
        if trial % 4 == 0:
            t = float(rng.choice([0.0, 0.001, 0.01, 0.03])) * scale
            a.thickness = t
            ref_model = Reference(a.bars, a.panels, a.bar_radii, a.panel_thicknesses)
        kind = trial % 3
        if kind == 0:      # perturbed flat state (coplanar panels, near-touching)
            x = x0 + rng.normal(scale=float(rng.choice([1e-3, 0.05, 0.3])) * scale, size=x0.shape)
        elif kind == 1:    # crumpled: large random displacements (many crossings)
            x = x0 + rng.normal(scale=scale, size=x0.shape)
        else:              # a point on a straight path between two foldings, stepped
            if trial % 30 == 2:
                ya = x0 + rng.normal(scale=0.5 * scale, size=x0.shape)
                yb = x0 * np.array([1, 1, 0]) + rng.normal(scale=0.5 * scale, size=x0.shape)
            s = (trial % 30) / 30.0
            x = (1 - s) * ya + s * yb
        c = a.clearance(x).value
        ref = ref_model.clearance(x)
        missed += (ref <= 0.0) != (c <= 0.0) and abs(ref) > REL * scale
        contacts += ref <= 0.0
        worst = max(worst, abs(c - ref) / max(abs(ref), scale))
        assert _agree(c, ref, scale), (trial, c, ref)
    print(f"sail:{n}:{k}: {count} configurations, {contacts} contacts, {missed} missed, "
          f"worst |c - ref| / max(|ref|, rms bar) {worst:.2e}")
    assert missed == 0
    assert worst <= REL


@pytest.mark.parametrize("dim", [2, 3])
def test_random_frameworks(dim):
    rng = np.random.default_rng(dim)
    count = 1800 if SLOW else 360
    worst, contacts, done = 0.0, 0, 0
    for trial in range(count):
        nj = int(rng.integers(6, 14))
        x = rng.uniform(0, 1, size=(nj, dim))
        tri = [sorted(rng.choice(nj, 3, replace=False).tolist()) for _ in range(int(rng.integers(1, 4)))]
        if trial % 7 == 0:       # a degenerate (zero-area) panel: its third joint on the line of the others
            p, q, r = tri[0]
            x[r] = x[p] + rng.uniform(0.2, 0.8) * (x[q] - x[p])
        if trial % 11 == 0:      # a coplanar pair, and an exact touch of a corner on a side
            x[:, -1] = np.round(x[:, -1], 1) if dim == 3 else x[:, -1]
        edges = set()
        for f in tri:
            edges |= {tuple(sorted(e)) for e in ((f[0], f[1]), (f[1], f[2]), (f[0], f[2]))}
        while len(edges) < nj:
            e = tuple(sorted(rng.choice(nj, 2, replace=False).tolist()))
            edges.add(e)
        bars = np.array(sorted(edges))
        try:
            a = libkin.Assembly(x, bars, panels=tri, thickness=float(rng.choice([0.0, 0.02])))
        except libkin.KinError:
            continue
        a.hinge_contact = False  # the reference knows parts, not hinges (test_hinges.py)
        ref = Reference(a.bars, a.panels, a.bar_radii, a.panel_thicknesses).clearance(x)
        c = a.clearance().value
        if np.isinf(ref):
            assert np.isinf(c)
            continue
        assert _agree(c, ref, 1.0), (trial, c, ref)
        worst = max(worst, abs(c - ref) / max(abs(ref), 1.0))
        contacts += ref <= 0.0
        done += 1
    print(f"frameworks {dim}D: {done} configurations, {contacts} contacts, worst {worst:.2e}")


def test_special_cases():
    # parallel overlapping bars, exactly touching end to end, coplanar triangles, a zero-area panel
    x = np.array([[0, 0, 0], [2, 0, 0], [1, 0.5, 0], [3, 0.5, 0]], float)
    a = libkin.Assembly(x, [[0, 1], [2, 3]])
    assert a.clearance().value == pytest.approx(0.5, rel=1e-15)
    x2 = np.array([[0, 0, 0], [1, 0, 0], [1, 0, 0], [2, 0, 0]], float)
    assert a.clearance(x2).value == 0.0
    t = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.25, 0.25, 0], [2, 0.25, 0], [0.25, 2, 0]], float)
    b = libkin.Assembly(t, [[0, 1], [1, 2], [2, 0], [3, 4], [4, 5], [5, 3]], panels=[[0, 1, 2], [3, 4, 5]])
    c = b.clearance()
    assert c.value == 0.0 and c.contact
    d = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [1, -1, 0.5], [1, 1, 0.5]], float)
    e = libkin.Assembly(d, [[0, 1], [1, 2], [3, 4]], panels=[[0, 1, 2]])
    assert e.clearance().value == pytest.approx(0.5, rel=1e-15)
    assert e.clearance().parts[0][0] in ("bar", "panel")


def test_model_round_trip_and_errors(tmp_path):
    a = _sail(6, 1, 0.01)
    a.set_thickness(0.01, bar_radii=np.where(np.arange(a.nbars) == 3, 0.002, -1.0))
    doc = a.to_json()
    b = libkin.Assembly.from_json(doc)
    assert b.panels == a.panels and b.thickness == a.thickness
    assert np.array_equal(b.bar_radii, a.bar_radii)
    assert b.clearance().value == a.clearance().value
    p = tmp_path / "m.json"
    a.to_json(p)
    c = libkin.load_model(str(p)) if hasattr(libkin, "load_model") else libkin.Assembly.from_json(str(p))
    assert c.panels == a.panels
    assert a.clone().clearance().value == a.clearance().value
    with pytest.raises(libkin.KinError):
        a.panels = [[0, 1]]
    with pytest.raises(libkin.KinError):
        a.thickness = -1.0
    with pytest.raises(libkin.KinError):
        libkin.Assembly.from_json(dict(doc, panels=[{"joints": [0, 1, 1]}]))
    with pytest.raises(libkin.KinError):
        libkin.Assembly.from_json(dict(doc, thickness=-0.5))


def test_triangles_against_fcl():
    """python-fcl's mesh distance (its exact triangle-triangle routine, not
    GJK: measured 6e-16 relative against the reference above) on random pairs
    of triangles, apart, touching and crossing; each triangle a panel with its
    sides as bars (which lie on the panels, so the smallest clearance is the
    triangles' distance)."""
    fcl = pytest.importorskip("fcl")
    rng = np.random.default_rng(5)
    bars = [[0, 1], [1, 2], [2, 0], [3, 4], [4, 5], [5, 3]]
    for trial in range(600):
        A = rng.uniform(0, 1, (3, 3))
        B = rng.uniform(0, 1, (3, 3)) + [0, 0, rng.choice([-0.5, 0.0, 0.5, 1.5])]
        ma, mb = fcl.BVHModel(), fcl.BVHModel()
        for m, T in ((ma, A), (mb, B)):
            m.beginModel(3, 1)
            m.addSubModel(T, np.array([[0, 1, 2]]))
            m.endModel()
        req, res = fcl.DistanceRequest(enable_nearest_points=True), fcl.DistanceResult()
        d = fcl.distance(fcl.CollisionObject(ma), fcl.CollisionObject(mb), req, res)
        hit = fcl.collide(fcl.CollisionObject(ma), fcl.CollisionObject(mb), fcl.CollisionRequest(), fcl.CollisionResult())
        try:
            a = libkin.Assembly(np.vstack([A, B]), bars, panels=[[0, 1, 2], [3, 4, 5]])
        except libkin.KinError:
            continue
        c = a.clearance().value
        if hit:  # fcl reports a collision: no contact missed
            assert c == 0.0 or c <= REL
        else:
            assert abs(c - max(d, 0.0)) <= REL * max(d, 1.0), (trial, c, d)


def test_fold_round_trip(tmp_path):
    """A model's panels are written as FOLD faces and read back as panels."""
    from libkin.io.fold import read_fold
    from libkin.io.fold.writer import write_fold
    a = _sail(6, 1, 0.0)
    p = tmp_path / "s.fold"
    write_fold(str(p), a)
    b = read_fold(str(p))
    assert sorted(map(sorted, b.panels)) == sorted(map(sorted, a.panels))
    assert b.clearance().value == pytest.approx(a.clearance().value, rel=1e-12)
    with pytest.raises(libkin.KinError):
        a.panels = [[0, 1, "x"]]
    with pytest.raises(libkin.KinError):
        a.set_thickness(0.1, bar_radii=[0.1])
    with pytest.raises(libkin.KinError):
        a.clearance(np.zeros((2, 3)))


def test_follow_stops_at_contact():
    """A parallelogram swings into a fixed bar: with contact events the
    follow stops where joint 1 reaches x = -0.5 (30 degrees), the two bars named;
    without, it runs on to its flat bifurcation."""
    x = np.array([[0, 0], [0, 1], [1, 1], [1, 0], [-0.5, 0.5], [-0.5, 2]], float)
    fixed = np.array([[1, 1], [0, 0], [0, 0], [1, 1], [1, 1], [1, 1]], bool)
    bars = [[0, 1], [1, 2], [2, 3], [4, 5]]
    a = libkin.Assembly(x, bars, fixed=fixed)
    b = a.clone()
    a.set_contact_events(True, 1e-9)
    ev = a.follow_event(direction=[-1, 0, -1, 0])
    assert ev.event == "contact"
    hit = a.last_contact()
    assert ("bar", 3) in hit.parts and hit.value <= 64 * np.finfo(float).eps * 1.2
    assert a.coords[1] == pytest.approx([-0.5, np.sqrt(0.75)], abs=1e-8)
    assert b.follow_event(direction=[-1, 0, -1, 0]).event == "bifurcation"
    with pytest.raises(libkin.KinError):
        b.last_contact()
    with pytest.raises(libkin.KinError):
        a.set_contact_events(True, 0.0)


def test_explore_marks_contact():
    """explore(contact=True): the branch that swings into the fixed bar ends
    in 'contact' (its message names the parts), the other one runs on to its
    bifurcation: the atlas counts the contact-free branches."""
    x = np.array([[0, 0], [0, 1], [1, 1], [1, 0], [-0.5, 0.5], [-0.5, 2]], float)
    fixed = np.array([[1, 1], [0, 0], [0, 0], [1, 1], [1, 1], [1, 1]], bool)
    a = libkin.Assembly(x, [[0, 1], [1, 2], [2, 3], [4, 5]], fixed=fixed)
    at = libkin.explore(a, depth=1, contact=True)
    events = sorted(e.event for e in at.edges)
    assert events == ["bifurcation", "contact"]
    hit = next(e for e in at.edges if e.event == "contact")
    assert "bar 3" in hit.message
    assert at.summary()["edge_events"].get("contact") == 1
    plain = libkin.explore(a, depth=1)
    assert "contact" not in {e.event for e in plain.edges}
