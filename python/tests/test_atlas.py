"""The atlas (libkin.explore): symmetry detection, the map of the square
sail's flat state serially, on a process pool and on a Dask cluster, other
structures and starts, the outputs and the command line."""
import json
from concurrent.futures import ProcessPoolExecutor

import networkx as nx
import numpy as np
import pytest

import libkin
from libkin import atlas as atlas_mod
from libkin.homotopy import shards as homotopy_shards
from libkin.atlas.tasks import EVENT_KINDS
from libkin.symmetry.automorphisms import detect_symmetries, invariant_subspace
from libkin.cli import main
from libkin.symmetry import sail_rotation, symmetric_subspace


@pytest.fixture(scope="module")
def square():
    """The serial atlas of the square sail's flat state, depth 1."""
    return libkin.explore("sail:4:1", depth=1)


def _check_square(at):
    assert at.nodes[0].kind == atlas_mod.BIFURCATION and (at.nodes[0].m, at.nodes[0].s) == (5, 4)
    assert at.nodes[0].branches["solutions"] == 16 and at.nodes[0].branches["accounting"]["paths"] == 16
    assert len(at.edges) == 32
    assert sorted((e.solution, e.sign) for e in at.edges) == sorted((i, s) for i in range(16) for s in (1, -1))
    assert all(e.source == 0 and e.event in EVENT_KINDS for e in at.edges)


def test_symmetries_detected():
    sq = detect_symmetries(libkin.Assembly.sail(4, 1))
    # identity, the mirror z -> -z, the half-turn about z (V0 <-> V2), and both
    assert len(sq) == 4 and sum(g.proper for g in sq) == 2 and sq[0].is_identity
    half = [g for g in sq if g.proper and not g.is_identity][0]
    assert half.perm == (2, 3, 0, 1, 6, 7, 4, 5)
    assert len(detect_symmetries(libkin.Assembly.threebar("RC"))) == 2  # the mirror y -> -y
    hexa = libkin.Assembly.sail(6, 2)
    gs = detect_symmetries(hexa)
    assert len(gs) == 6 and sum(g.proper for g in gs) == 3
    # the proper rotations give the sail study's symmetric subspace (k = 6)
    U = hexa.analyse().internal_mechanisms
    P = [g.free_matrix(hexa.free_map()) for g in gs if g.proper and not g.is_identity]
    G = invariant_subspace(U, P)
    G_study = symmetric_subspace(U, sail_rotation(hexa, 6, 2))
    assert G.shape == G_study.shape == (16, 6)
    assert np.linalg.svd(G.T @ G_study, compute_uv=False).min() > 1 - 1e-9  # the same subspace


def test_square_sail_serial(square):
    _check_square(square)
    at = square
    for n in at.nodes:
        # a node says what it is: regular points are never bifurcations
        if n.kind == atlas_mod.BIFURCATION:
            assert n.m >= 2 and n.s >= 1
        elif n.kind in (atlas_mod.REGULAR, atlas_mod.NEAR_MISS):
            assert n.m == 1
    assert at.summary()["edge_events"].get("bifurcation", 0) > 0
    # end points related by the structure's symmetry share an orbit
    imgs = [n for n in at.nodes if n.image_of is not None]
    assert imgs and all(n.orbit == at.nodes[n.image_of["node"]].orbit for n in imgs)
    for n in imgs:
        g = at.symmetries[n.image_of["symmetry"]]
        assert np.abs(g.apply(at.nodes[n.image_of["node"]].coords) - n.coords).max() < 1e-5
    # deterministic
    assert libkin.explore("sail:4:1", depth=1).same_as(at, tol=0.0)


def test_square_sail_process_pool(square):
    with ProcessPoolExecutor(max_workers=2) as ex:
        at = libkin.explore("sail:4:1", depth=1, executor=ex)
        # the complete solver in shards on the same pool: the same answer
        sharded = libkin.explore("sail:4:1", depth=1, executor=ex, shards=4)
        Q = libkin.Assembly.sail(4, 1).second_order()
        betas, acc = homotopy_shards.solve_sharded(Q, ex, shards=3)
    _check_square(at)
    assert at.same_as(square)
    assert sharded.nodes[0].branches["accounting"]["shards"] == 4 and sharded.same_as(square)
    ref, ref_acc = libkin.solve_quadrics(Q, threads=1)
    assert np.array_equal(betas, ref) and all(acc[k] == ref_acc[k] for k in acc)


def test_square_sail_dask(square):
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=":0") as cluster, distributed.Client(cluster) as client:
        at = libkin.explore("sail:4:1", depth=1, executor=client)
    _check_square(at)
    assert at.same_as(square)


def test_symmetric_mode():
    at = libkin.explore("sail:4:1", depth=1, symmetric=True)
    b = at.nodes[0].branches
    # the half-turn's symmetric subspace: 3 mechanisms, 2 equations, 4 real solutions
    assert (b["mode"], b["k"], b["s_restricted"], b["solutions"]) == ("symmetric", 3, 2, 4)
    assert len(at.edges) == 8


def test_threebar_and_regular_start(tmp_path):
    at = libkin.explore("threebar:RC", depth=2)
    bif = [n for n in at.nodes if n.kind == atlas_mod.BIFURCATION]
    assert len(bif) == 3 and all((n.m, n.s) == (2, 1) for n in bif)
    assert len([e for e in at.edges if e.source == 0]) == 4
    # every branch ends at one of the three bifurcations, with at least 2 samples along the way (more where
    # the viewer's curve through 2 would stretch a bar by over 1 %: atlas/frames.py)
    assert all(e.event == "bifurcation" and len(e.samples) >= 2 for e in at.edges)
    # a regular start: a point on a path (a sample of the atlas above)
    at2 = libkin.explore("threebar:RC", start=at.edges[0].samples[0], depth=1)
    assert at2.nodes[0].kind == atlas_mod.REGULAR and at2.nodes[0].branches["mode"] == "regular"
    assert len(at2.edges) == 2 and {e.sign for e in at2.edges} == {1, -1}
    assert any(at2.nodes[e.target].kind == atlas_mod.BIFURCATION for e in at2.edges)


def test_a_bar_between_the_supports_changes_no_branch():
    """The three-bar linkage with a fourth bar between its two supports
    (docs/generality.md, "Bars between fixed joints"): s counts that bar's
    self-stress (s = 2, s_trivial = 1), and the atlas is the linkage's."""
    p = libkin.Assembly.threebar("RC")
    a = libkin.Assembly(p.coords, np.vstack([p.bars, [[2, 3]]]), fixed=p.fixed,
                        lengths=np.append(p.rest_lengths, 1.0))
    assert (a.analyse().s, a.analyse().s_trivial) == (2, 1)
    ap, aa = libkin.explore(p, depth=2), libkin.explore(a, depth=2)
    assert [(n.kind, n.m, n.s) for n in aa.nodes] == [(n.kind, n.m, n.s + 1) for n in ap.nodes]
    assert all(n.branches.get("s_trivial") == 1 and n.branches["s"] == 1 for n in aa.nodes)
    assert len(aa.edges) == len(ap.edges) == 12
    for ea, ep in zip(aa.edges, ap.edges):
        assert (ea.source, ea.target, ea.event) == (ep.source, ep.target, ep.event)
        assert abs(ea.length - ep.length) <= 1e-9


def test_json_model_and_outputs(tmp_path):
    path = tmp_path / "three.json"
    libkin.Assembly.threebar("RC").to_json(path)
    at = libkin.explore(str(path), depth=1)
    assert len(at.edges) == 4
    from libkin.atlas import report as atlas_report
    rep = atlas_report.write(at, tmp_path / "out")
    for f in ("atlas.json", "atlas.graphml", "atlas_map.png", "atlas_nodes.png", "report.md"):
        assert (tmp_path / "out" / f).stat().st_size > 0
    assert "N0" in rep.read_text()
    back = atlas_mod.Atlas.from_dict(json.loads((tmp_path / "out" / "atlas.json").read_text()))
    assert back.same_as(at, tol=0.0)
    G = nx.read_graphml(tmp_path / "out" / "atlas.graphml")
    assert G.number_of_nodes() == len(at.nodes) and G.number_of_edges() == len(at.edges)
    assert G.nodes["N0"]["kind"] == "bifurcation"


def _solve(Q):
    betas, acc = libkin.solve_quadrics(Q, threads=1)
    return {"betas": betas.tolist(), "accounting": acc}


def test_overdetermined_and_continuum_systems():
    # two equations in two unknowns: b0^2 = 0 and 2 b0 b1 = 0 share the root (0, 1)
    Q = np.array([[[1.0, 0.0], [0.0, 0.0]], [[0.0, 1.0], [1.0, 0.0]]]) / np.sqrt([[[1.0]], [[2.0]]])
    betas, rec = atlas_mod.solve_system(Q, 2, _solve)
    assert betas.shape == (1, 2) and abs(abs(betas[0, 1]) - 1.0) < 1e-9 and rec["candidates"] >= 1
    # ... b0^2 - b1^2 = 0 and 2 b0 b1 = 0 share none
    Q2 = np.array([[[1.0, 0.0], [0.0, -1.0]], [[0.0, 1.0], [1.0, 0.0]]]) / np.sqrt(2.0)
    betas, rec = atlas_mod.solve_system(Q2, 2, _solve)
    assert betas.shape == (0, 2) and rec["solutions"] == 0
    # one equation in three unknowns: a continuum, not enumerated
    Q3 = np.zeros((1, 3, 3))
    Q3[0, 0, 0], Q3[0, 1, 1] = 1.0 / np.sqrt(2.0), -1.0 / np.sqrt(2.0)
    betas, rec = atlas_mod.solve_system(Q3, 3, _solve)
    assert betas is None and rec["solutions"] == 0


def test_shard_ranges_cover_every_path():
    for s, k in ((4, 3), (4, 16), (4, 40), (10, 7)):
        r = homotopy_shards.shard_ranges(s, k)
        assert r[0][0] == 0 and sum(c for _, c in r) == 1 << s and all(c > 0 for _, c in r)
        assert all(r[i][0] + r[i][1] == r[i + 1][0] for i in range(len(r) - 1))


def test_bad_arguments():
    with pytest.raises(libkin.errors.InvalidArgumentError):
        libkin.explore("threebar:RC", symmetric="maybe")
    with pytest.raises(libkin.errors.InvalidArgumentError):
        libkin.explore("threebar:RC", depth=-1)
    with pytest.raises(libkin.errors.InvalidArgumentError):
        libkin.explore("threebar:RC", start=np.zeros((3, 2)))
    for bad in ({"max_length": -1.0}, {"max_length": float("nan")}, {"max_nodes": 0}, {"samples": -1},
                {"time_limit": -1.0}, {"shards": 0}, {"max_steps": 0}):
        with pytest.raises(libkin.errors.InvalidArgumentError):
            libkin.explore("threebar:RC", **bad)


def test_cli(tmp_path, capsys):
    out = tmp_path / "atl"
    assert main(["explore", "threebar:RC", "--depth", "1", "--out", str(out), "--quiet"]) == 0
    doc = json.loads((out / "atlas.json").read_text())
    assert len(doc["edges"]) == 4 and doc["nodes"][0]["kind"] == "bifurcation"
    assert (out / "report.md").exists() and (out / "atlas_map.png").exists()


def test_bounds():
    # the start is expanded, then the node budget stops the next level
    at = libkin.explore("threebar:RC", depth=3, max_nodes=2)
    assert at.nodes[0].expanded and not any(n.expanded for n in at.nodes[1:])
    assert at.stats["stopped_by"] == "max_nodes"
    # no time at all: nothing is expanded, and the atlas says why
    at = libkin.explore("threebar:RC", depth=3, time_limit=0.0)
    assert len(at.nodes) == 1 and not at.edges and at.stats["stopped_by"] == "time_limit"
    # a time limit that runs out while the start's branches are followed: the
    # branches not started are left out, and the start says so
    at = libkin.explore("sail:4:1", depth=1, time_limit=0.1)
    if len(at.edges) < 32:  # (a fast machine may finish in time)
        assert "time limit" in at.nodes[0].status and at.stats["stopped_by"] == "time_limit"
    # a path-length budget shorter than every path: every branch ends in `budget` at a regular point
    at = libkin.explore("threebar:RC", depth=1, max_length=0.5)
    assert len(at.edges) == 4 and all(e.event == "budget" for e in at.edges)
    assert all(at.nodes[e.target].kind == atlas_mod.REGULAR and e.length >= 0.5 for e in at.edges)


def test_square_sail_matches_stored_example(square):
    """examples/atlas/square_sail (written by `libkin explore sail:4:1 --out ...`): the same map, whatever
    the order the solver gives the roots in (the default symmetric solve orders them by orbit)."""
    import pathlib
    from libkin.atlas.orbits import differences
    stored = pathlib.Path(__file__).resolve().parents[2] / "examples" / "atlas" / "square_sail" / "atlas.json"
    ref = atlas_mod.Atlas.from_dict(json.loads(stored.read_text()))
    assert sorted((n.kind, n.m, n.s) for n in ref.nodes) == sorted((n.kind, n.m, n.s) for n in square.nodes)
    assert len(ref.edges) == len(square.edges)
    assert differences(ref, square) == []


def test_follow_orbits_gives_the_same_atlas():
    """One branch per orbit of the node's stabilizer followed, the others
    mapped by the symmetry: the same nodes and edges as following all."""
    full = libkin.explore("sail:4:1", depth=1, samples=1, follow_orbits=False)
    fast = libkin.explore("sail:4:1", depth=1, samples=1)  # follow_orbits: the default with symmetry
    # a node's point is its best-located end (docs/atlas.md "Identification"): the square sail's
    # supports leave rigid-body mechanisms, so the two may hold ends a rigid motion apart
    from libkin.symmetry.procrustes import aligned_distance
    for a, b in zip(full.nodes, fast.nodes):
        assert aligned_distance(a.coords, b.coords) <= 1e-9
        b.coords = a.coords
    assert full.same_as(fast, tol=1e-7)
    assert fast.stats["branches_followed"] < full.stats["branches_followed"] == len(full.edges)
    assert fast.stats["branches_followed"] + fast.stats["branches_mapped"] == len(fast.edges)
    for e, f in zip(full.edges, fast.edges):
        assert abs(e.accuracy - f.accuracy) <= 1e-9 or e.accuracy == f.accuracy
        assert np.abs(np.asarray(e.samples) - np.asarray(f.samples)).max() <= 1e-7
    from libkin.errors import InvalidArgumentError
    with pytest.raises(InvalidArgumentError):
        libkin.explore("sail:4:1", depth=1, follow_orbits="yes")


def test_branch_orbits_match_images():
    from libkin.atlas.orbits import branch_orbits
    rng = np.random.default_rng(5)
    # a group of order 4 acting on R^3 by signed permutations, and an orbit-closed set of directions
    P = [np.diag([1.0, 1.0, -1.0]), np.array([[0, 1, 0], [1, 0, 0], [0, 0, 1.0]]),
         np.array([[0, 1, 0], [1, 0, 0], [0, 0, -1.0]])]
    base = [rng.normal(size=3) for _ in range(5)]
    dirs = []
    for b in base:
        for M in [np.eye(3)] + P:
            dirs.append(M @ b)
    order = rng.permutation(len(dirs))
    dirs = [dirs[i] for i in order]
    orb = branch_orbits(dirs, P)
    reps = [k for k, (r, j) in enumerate(orb) if j < 0]
    assert len(reps) == 5
    for k, (r, j) in enumerate(orb):
        assert r <= k and orb[r][1] == -1
        if j >= 0:
            u = dirs[k] / np.linalg.norm(dirs[k])
            v = P[j] @ dirs[r] / np.linalg.norm(dirs[r])
            assert np.abs(u - v).max() < 1e-12


def test_a_task_gives_the_same_result_with_the_model_cached():
    # tasks clone a per-process template of the model (atlas/tasks.py): the
    # result must be the freshly loaded model's, bit for bit, and a task must
    # not change what the next one starts from
    from libkin.atlas import tasks
    a = libkin.Assembly.sail(4, 1)
    an = a.analyse()
    res = a.branches()
    text = json.dumps(a.to_json())
    outs = {}
    for cached in (False, True, True):
        rows = []
        for k, d in enumerate(res.directions[:6]):
            if not cached:
                tasks._template.cache_clear()
            task = {"model": text, "coords": a.coords.tolist(), "rank_tol": None, "direction": list(d),
                    "max_length": 10.0 * a.nfree, "samples": 2}
            r = tasks.follow_branch(task)
            rows.append((r["event"], r["length"], np.asarray(r["coords"]).tobytes(), r["steps"],
                         [np.asarray(x).tobytes() for x in r["samples"]]))
        outs.setdefault(cached, []).append(rows)
    assert an.m_internal >= 2
    assert outs[False][0] == outs[True][0] == outs[True][1]
    # what a task does to its handle stays with it
    task = {"model": text, "coords": a.coords.tolist(), "rank_tol": 1e-8}
    b = tasks.rebuild(task)
    b.coords = np.asarray(tasks.follow_branch(dict(task, direction=list(res.directions[0]),
                                                   max_length=1.0))["coords"])
    assert not np.array_equal(b.coords, a.coords)
    o = b.options
    o.rank_tol = 1e-3
    b.options = o
    c = tasks.rebuild(task)
    assert np.array_equal(c.coords, a.coords) and c.options.rank_tol == 1e-8


def test_node_kind_does_not_depend_on_arrival_order():
    """A point reached as a near miss (the minimum of v_r along one path) and
    as a located bifurcation (along another) is a bifurcation node, whichever
    branch came first; a bifurcation node stays one, and an expanded node is
    never changed."""
    from libkin.atlas.model import Node, node_kind
    near = {"m": 1, "m_rigid": 0, "s": 0, "v_r_rel": 3e-8, "accuracy": 3e-8}
    bif = {"m": 2, "m_rigid": 0, "s": 1, "v_r_rel": 0.02, "accuracy": 4e-11}

    def node(kind, res):
        return Node(7, kind, np.zeros((2, 3)), res["m"], res["m_rigid"], res["s"], res["v_r_rel"], 1,
                    located_v_r=res["accuracy"], located_tol=1e-10)

    kinds = {}
    for first, second in (("near_miss", "bifurcation"), ("bifurcation", "near_miss")):
        res = {"near_miss": near, "bifurcation": bif}
        n = node(node_kind(first, res[first]), res[first])
        assert n.arrived(node_kind(second, res[second]), res[second]) == 7
        kinds[first] = (n.kind, n.m, n.s, n.located_v_r, n.located_tol)
    assert kinds["near_miss"] == kinds["bifurcation"] == (atlas_mod.BIFURCATION, 2, 1, 4e-11, 1e-10)
    done = node(atlas_mod.NEAR_MISS, near)
    done.expanded = True
    done.arrived(atlas_mod.BIFURCATION, bif)
    assert (done.kind, done.m) == (atlas_mod.NEAR_MISS, 1)


def _orbits_by_scan(dirs, P, tol):
    """branch_orbits' rule by brute force: each representative's image under
    P[j] claims the lowest-index unclaimed direction within tol."""
    D = np.array([d / np.linalg.norm(d) for d in dirs])
    out = [None] * len(D)
    for k in range(len(D)):
        if out[k] is None:
            out[k] = (k, -1)
            for j, Pj in enumerate(P):
                img = Pj @ D[k]
                for i in range(len(D)):
                    if out[i] is None and np.abs(D[i] - img).max() <= tol:
                        out[i] = (k, j)
                        break
    return out


def test_branch_orbits_as_a_scan_with_near_duplicates():
    # directions within SAME_DIRECTION of another (the k-d tree finds two in
    # reach: every one is tried, lowest index first), just outside it, and
    # images with no match: the same claims as a scan
    from libkin.atlas.orbits import SAME_DIRECTION, branch_orbits
    rng = np.random.default_rng(11)
    P = [np.diag([1.0, 1.0, -1.0, 1.0]), np.array([[0, 1, 0, 0], [1, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])]
    dirs = []
    for _ in range(6):
        b = rng.normal(size=4)
        dirs += [b, P[0] @ b]
        u = P[1] @ b / np.linalg.norm(b)
        dirs.append(u + 0.4 * SAME_DIRECTION * np.sign(rng.normal(size=4)))  # within reach of the image
        dirs.append(u - 0.4 * SAME_DIRECTION * np.sign(rng.normal(size=4)))  # a second one within reach
        dirs.append(u + 3.0 * SAME_DIRECTION)  # just outside
    dirs = [dirs[i] for i in rng.permutation(len(dirs))]
    got = branch_orbits(dirs, P)
    assert got == _orbits_by_scan(dirs, P, SAME_DIRECTION)
    D = np.array([d / np.linalg.norm(d) for d in dirs])
    reach = [int((np.abs(D - Pj @ D[k]).max(axis=1) <= SAME_DIRECTION).sum()) for k, (r, j) in enumerate(got)
             if j < 0 for Pj in P]
    assert reach.count(2) >= 1 and reach.count(0) >= 1  # both kinds of image were met


def test_follow_level_takes_each_result_once_in_work_order():
    # results arrive in a scrambled order; take() sees every branch once, in
    # work order, as soon as all before it are known: the followed branches
    # and the certain images while the first pass runs, up to the first
    # image not certain, which waits for the second pass
    from libkin.atlas.orbits import follow_level

    class Mirror:
        def apply(self, X):
            return np.asarray(X) * np.array([-1.0, 1.0])
    X = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]])
    bars = np.array([[0, 1], [1, 2]])
    # work k: a rep (even k) and its image (k + 1); the reps' events: loops are certain, budgets not
    n = 12
    work = [("w", k) for k in range(n)]
    images = [None if k % 2 == 0 else (k - 1, 0) for k in range(n)]
    events = {k: ("loop" if k in (0, 2, 6, 8) else "budget") for k in range(0, n, 2)}
    taken, passes = [], []

    def follow(items, on_result):
        passes.append([w[1] for w in items])
        res = [{"event": events.get(w[1], "budget"), "coords": X.tolist(), "samples": [], "k": w[1]}
               for w in items]
        for j in reversed(range(len(items))):  # completes last-first
            if len(passes) == 1 and j == len(items) - 1:
                on_result(j, res[j])
                assert taken == []  # nothing before it is at hand yet
                continue
            on_result(j, res[j])
        if len(passes) == 1:
            assert taken == [0, 1, 2, 3, 4]  # up to the first image not certain (5), while this pass runs
        return res

    def take(k, res):
        taken.append(k)
        assert res is not None and (res.get("mapped") or res["k"] == k)
    results, followed, mapped = follow_level(work, images, follow, [Mirror()], bars, take)
    uncertain = [k for k in range(1, n, 2) if events[k - 1] == "budget"]
    assert passes == [list(range(0, n, 2)), uncertain]
    assert taken == list(range(n))
    assert followed == n // 2 + len(uncertain) and mapped == n // 2 - len(uncertain)
    assert all(r is not None for r in results)
