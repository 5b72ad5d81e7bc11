"""The solar-sail folding studies of the paper's Section 6, run end to end.

hexagonal_study(): from the flat state R^A along the folding path into R^B,
on to the next bifurcation R^C, and back to R^A, recording what Figures 13
and 14 show plus the strain, the hub's planarity and the closure error.
The path map of every symmetric path is the explorer's atlas
(libkin.explore, read through sailmap.py), and each leg of the run is
followed to its next event by the explorer's follower (kin_follow_event);
what the study adds is
sail-specific: which of the flat state's paths is the folding branch, which
of R^B's continues the fold, and the paper's questions.
square_study() (squarestudy.py): every path out of the square sail's flat
state (Figure 11).

Both return a plain dict of results (JSON-serialisable) and, given an output
folder, write report.md, summary.json and the figures there
(studyreport.py, studyfigures.py). The helpers both studies share are in
common.py; like every module of libkin.studies, this one uses only the
public API of libkin.
"""
import json
import pathlib
import time

import numpy as np

from libkin.assembly import Assembly
from libkin.atomic import replacing, staged_folder, write_text
from libkin.symmetry import mechanism_group, sail_rotation

# (PAPER_VR_TOL, SAIL_VR_TOL, SAME_CONFIG_TOL, paper_locate and record are
# imported for the names this module has always had)
from . import margin
from .contactstudy import member_study
from .common import (PAPER_VR_TOL, SAIL_VR_TOL, SAME_CONFIG_TOL, accounting_words, branch_words, follow_to_bifurcation,
                     jsonable, leave, paper_locate, record, say)
from .flatcache import flat_solve
from .contactmap import contact_map
from .sailmap import MAP_DEPTH, SailMap, explore_symmetric
from .readings import MAIN_READING, reading_record
from .sailmeasure import measures
from .sequential import WRAP_TOL
from .squarestudy import square_study as square_study

# number of lowest singular values recorded (Figure 14)
N_SV = 15
# how far along each symmetric path out of R^A the report draws it
SNAP_LENGTH = 1.0


def _free_vec(a, xyz):
    return xyz[a.free_map() >= 0]


class _Track:
    """What is recorded along the run."""

    def __init__(self, hub_joints):
        self.hub = hub_joints
        self.l, self.sv, self.strain, self.hub_z, self.factorizations = [], [], [], [], []
        self.coords = []  # for the drawings and the animation (not stored)
        self.offset = 0.0
        self.base = 0.0

    def begin(self, a):
        """A new segment starts at a (a bifurcation): lengths continue from here."""
        self.offset = self.l[-1] if self.l else 0.0
        self.base = a.path_length

    def add(self, a, sv=None):
        if sv is None:
            sv = a.analyse().singular_values
        self.l.append(self.offset + abs(a.path_length - self.base))
        self.sv.append(np.sort(sv)[:N_SV])
        self.strain.append(a.max_strain)
        z = a.coords[self.hub, 2]  # V0, V2, ... are fixed at z = 0
        self.hub_z.append(float(np.abs(z).max()))
        self.coords.append(a.coords)

    def pop(self):
        for v in (self.l, self.sv, self.strain, self.hub_z, self.coords):
            v.pop()


def _chord(a_from, a_to):
    d = _free_vec(a_to, a_to.coords) - _free_vec(a_from, a_from.coords)
    return d / np.linalg.norm(d)


def _hub_joints(a):
    """The hub's vertices (the centre node C is a device of the model, not
    part of the hub)."""
    return [i for i, lab in enumerate(a.labels) if lab.startswith("V")]


def _loop_nodes(labels, n, loop):
    off = 1 if labels[0] == "C" else 0
    return list(range(off + loop * n, off + (loop + 1) * n))


def _wraps_loop1(x, labels, n):
    """Loop-1 nodes directly above or below their hub vertices, alternating
    (configuration x of a sail with joint labels `labels`)."""
    V, A = _loop_nodes(labels, n, 0), _loop_nodes(labels, n, 1)
    xy = np.abs(x[A, :2] - x[V, :2]).max()
    z = x[A, 2] - x[V, 2]
    alternating = all(z[k] * z[(k + 1) % n] < 0 for k in range(n))
    return xy, alternating


def _branch_report(a, threads, length, max_s=12):
    """Complete solver + finite paths at a located bifurcation."""
    an = a.analyse()
    if an.s - an.s_trivial > max_s:  # the equations: bars between fixed joints give none
        return None, {"m": an.m_internal, "s": an.s, "skipped": f"s = {an.s - an.s_trivial} > {max_s}"}
    t0 = time.perf_counter()
    br = a.branches(solver="homotopy", length=length, threads=threads)
    ok = sum(p.exists and p.tangent_ok for p in br.paths)
    return br, {"m": an.m_internal, "s": an.s, "accounting": br.accounting, "real_solutions": len(br.betas),
                "directed_paths_ok": ok, "distinct_paths": br.distinct,
                "seconds": round(time.perf_counter() - t0, 2)}


def hexagonal_study(n_sides=6, n_loops=2, complete=True, threads=2, progress=True, out=None, executor=None,
                    map_depth=MAP_DEPTH, interference=True, contact=None):
    """The folding and deployment study of Section 6.2 on a CENTRE-supported
    family member (the paper's: n_sides=6, n_loops=2). interference: also
    the first contact of the membrane along the member's radially
    sequential fold at each thickness (contactstudy.member_study).
    complete=False skips
    the 2^s homotopy at the flat state (the symmetric sub-problem is solved
    either way). The path map is the explorer's symmetric atlas to
    map_depth levels (sailmap.py), its branches followed on `executor`
    (None: in this process; a concurrent.futures.Executor or a
    dask.distributed.Client). contact: a membrane thickness t/a (0 for the
    bare membrane) to explore the map again with contact as an event
    (contactmap.py: which mapped paths reach their next event free of
    contact); None (the default) skips it."""
    t_start = time.perf_counter()
    res = {"model": f"sail {n_sides}-gon hub, {n_loops} loops", "n_sides": n_sides, "n_loops": n_loops,
           "events": {}}
    a = Assembly.sail(n_sides, n_loops)
    flat = a.coords
    hub = _hub_joints(a)
    an = a.analyse()
    res["flat"] = {"nfree": a.nfree, "nbars": a.nbars, "m": an.m_internal, "s": an.s,
                   "measures": measures(flat, a.labels, n_sides, n_loops)}
    # per bifurcation, the configuration a short way along each path leaving
    # it (the report's small multiples)
    snaps = {}
    say(progress, f"[R^A] flat state: H is {a.nfree} x {a.nbars}, m = {an.m_internal}, s = {an.s}")
    if complete and an.s <= 16:
        say(progress, f"[R^A] complete solver: 2^{an.s} = {2 ** an.s} homotopy paths on {threads} threads, "
             "one per orbit of the sail's rotations ...")
        # the sail's symmetry group acting on beta (found from C): the solver
        # tracks one path per orbit of start roots and certifies all 2^s;
        # kept next to out for the next run with the same model (flatcache.py)
        group = mechanism_group(a, method="c")
        _, acc, cached = flat_solve(a, group, threads, progress, out)
        res["flat"]["complete"] = acc
        say(progress, f"[R^A]   the complete solver accounts for all {accounting_words(acc)} ({acc['seconds']} s"
            + (", solved by an earlier run: taken from its cache)" if cached else ")"))
    # the path map: the explorer's atlas of every symmetric path out of the
    # flat state and out of the bifurcations they reach (sailmap.py); the
    # folding branch is among the flat state's paths whose first bifurcation
    # has loop 1 wrapped (A_k over V_k, alternating): the shortest such path
    say(progress, f"[map] exploring the symmetric paths (depth {map_depth}) ...")
    smap = SailMap(explore_symmetric(a, map_depth, executor=executor, threads=threads, progress=progress))
    res["flat"]["symmetric"] = _symmetric_record(smap.branches_record(0))
    if contact is not None:
        cm = contact_map(a, smap, map_depth, contact, executor=executor, threads=threads, progress=progress)
        smap.contact_atlas = cm.pop("atlas")
        res["contact_map"] = cm
    sym = res["flat"]["symmetric"]
    say(progress, f"[R^A] {n_sides // 2}-fold symmetric motions: {sym['k']} mechanisms, {sym['s']} equations, "
         f"{sym['accounting']['real_distinct']} real solutions of {sym['accounting']['paths']}")
    followed = []  # (solution, sign, direction, target node or None)
    cands = []
    for e, t in smap.paths_from(0):
        d = np.asarray(e.direction)
        tn = smap.nodes[t] if t is not None and e.event == "bifurcation" else None
        followed.append((e.solution, e.sign, d, t))
        if tn is None or tn.kind != "bifurcation":
            cands.append({"beta": e.solution, "sign": e.sign, "reached": None, "event": e.event})
            continue
        xy, alt = _wraps_loop1(tn.coords, a.labels, n_sides)
        # the wrap test with its margin at the node's located accuracy
        # (margin.py): "undecided" candidates are listed, not counted
        u = margin.position_uncertainty(tn.located_tol)
        cands.append({"beta": e.solution, "sign": e.sign, "reached": e.length, "m": tn.m, "s": tn.s,
                      "loop1_xy": float(xy), "alternating": alt, "centre_dz": float(d[0]),
                      "located_tol": float(tn.located_tol), "loop1_xy_uncertainty": u,
                      "wrap": margin.below(xy, WRAP_TOL, u) if alt else margin.NO})
    wraps = [c for c in cands if c["reached"] and c["wrap"] == margin.YES]
    res["flat"]["candidates_wrap_undecided"] = [
        {k: c[k] for k in ("beta", "sign", "reached", "loop1_xy", "loop1_xy_uncertainty", "located_tol")}
        for c in cands if c["reached"] and c.get("wrap") == margin.UNDECIDED]
    res["flat"]["candidates"] = len(cands)
    res["flat"]["candidates_reaching_bifurcation"] = sum(1 for c in cands if c["reached"])
    res["flat"]["candidates_wrapping_loop1"] = len(wraps)
    if not wraps:
        res["failed"] = "no symmetric path out of the flat state wraps loop 1"
        return _finish_hex(res, None, out, t_start, progress, smap=smap)
    wraps.sort(key=lambda c: (round(c["reached"], 6), c["centre_dz"] > 0))
    pick = wraps[0]
    res["flat"]["chosen"] = pick
    say(progress, f"[R^A] {len(wraps)} of {len(cands)} symmetric directed paths wrap loop 1; chosen: "
         f"solution {pick['beta']}, sign {pick['sign']:+d}, R^B at l = {pick['reached']:.4f}")
    d_A = next(d for i, sg, d, _ in followed if i == pick["beta"] and sg == pick["sign"])
    snaps["R^A"] = {"length": SNAP_LENGTH, "base": a.coords, "paths": [
        {"beta": i, "sign": sg, "coords": _coords_at(None, a, d, SNAP_LENGTH), "symmetric": True,
         "tag": "chosen" if (i, sg) == (pick["beta"], pick["sign"]) else "", "to": t}
        for i, sg, d, t in followed]}

    track = _Track(hub)
    track.add(a)
    stages = [("(a) flat, R^A", a.coords)]
    # ---- R^A -> R^B
    track.begin(a)
    rb, ev, steps = follow_to_bifurcation(a, d_A, track, compare=True)
    if rb is None:
        res["failed"] = "R^B not reached"
        return _finish_hex(res, track, out, t_start, progress, stages, smap)
    _event(ev, steps, a, rb, hub, res)
    res["events"]["RB_fold"] = ev
    stages.append(("(b) R^A to R^B", _coords_at(track, a, d_A, 0.5 * ev["l"])))
    stages.append(("(c) R^B", rb.coords))
    say(progress, f"[R^B] located after {steps} steps at l = {ev['l']:.4f}: m = {ev['m']}, s = {ev['s']}, "
         f"{ev['factorizations']} factorizations ({ev['method']}), v_r = {ev['v_r_rel']:.1e}")
    chord_AB = _chord(_last_before(a, d_A, ev["l"]), rb)
    br, rep = _branch_report(rb, threads, 0.5)
    res["RB"] = rep
    say(progress, f"[R^B] {branch_words(rep)}")
    smap.mark(rb.coords, "R^B")
    # onward: a symmetric candidate that is not the arrival path and folds
    # the sail (smallest xy extent after 0.5)
    P_rb = sail_rotation(rb, n_sides, 2)
    best = None
    for p in br.paths:
        d = br.directions[p.beta] * p.sign
        if not (p.exists and p.tangent_ok):
            continue
        sym = np.linalg.norm(P_rb @ d - d) < 1e-6 * np.linalg.norm(d)
        cos_in = float(d @ chord_AB / np.linalg.norm(d))
        if not sym or abs(cos_in) > 0.99:
            continue
        extent = float(np.hypot(p.final_coords[:, 0], p.final_coords[:, 1]).max())
        if best is None or extent < best[0] - 1e-9:
            best = (extent, d, p, cos_in)
    if best is None:
        res["failed"] = "no symmetric folding path out of R^B"
        return _finish_hex(res, track, out, t_start, progress, stages, smap)
    d_B = best[1]
    res["RB"]["chosen"] = {"beta": best[2].beta, "sign": best[2].sign, "xy_extent_at_0.5": best[0],
                           "cos_with_arrival": best[3], "centre_dz": float(d_B[0])}
    snaps["R^B"] = {"length": 0.5, "base": rb.coords,
                    "paths": _branch_snaps(br, P_rb, chord_AB, (best[2].beta, best[2].sign), "back to R^A")}
    # ---- R^B -> R^C
    track.begin(rb)
    rc, ev, steps = follow_to_bifurcation(rb, d_B, track, compare=True)
    if rc is None:
        res["failed"] = "R^C not reached"
        return _finish_hex(res, track, out, t_start, progress, stages, smap)
    _event(ev, steps, rb, rc, hub, res)
    res["events"]["RC_fold"] = ev
    stages.append(("(d) R^B to R^C", _coords_at(track, rb, d_B, 0.5 * ev["l"])))
    stages.append(("(e) R^C", rc.coords))
    say(progress, f"[R^C] located after {steps} steps at l = {ev['l']:.4f} beyond R^B: m = {ev['m']}, "
         f"s = {ev['s']}, {ev['factorizations']} factorizations ({ev['method']}), v_r = {ev['v_r_rel']:.1e}")
    chord_BC = _chord(_last_before(rb, d_B, ev["l"]), rc)
    br_c, rep = _branch_report(rc, threads, 0.3)
    res["RC"] = rep
    say(progress, f"[R^C] {branch_words(rep)}")
    # onward from R^C: every symmetric path out of it in the atlas
    ib, _ = smap.mark(rb.coords, "R^B")
    ic, ic_is_rc = smap.mark(rc.coords, "R^C")
    for key, i in (("RB", ib), ("RC", ic)):
        rec = smap.branches_record(i) if i is not None else None
        if rec is not None and "k" in rec:
            res[key]["symmetric"] = _symmetric_record(rec)
        else:
            res[key]["map"] = ("not reached in the atlas" if i is None else
                               f"not expanded in the atlas of depth {map_depth}: its paths are not mapped")
    if ic is not None and ic_is_rc and smap.branches_record(ic) is not None:
        names = smap.names()
        ext_c = smap.measures(smap.nodes[ic])["xy_extent"]
        onward = [(e, t) for e, t in smap.paths_from(ic)]
        res["RC"]["onward"] = [{"to": names[t] if t is not None else None, "event": e.event, "l": e.length,
                                "xy_extent": smap.measures(smap.nodes[t])["xy_extent"] if t is not None else None}
                               for e, t in onward]
        # a local end of the fold: every symmetric path onward ends less compact
        res["RC"]["onward_less_compact"] = all(o["xy_extent"] is not None and o["xy_extent"] > ext_c + 1e-9
                                               for o in res["RC"]["onward"])
        # the most compact symmetric state only if no mapped node is more compact
        more = smap.more_compact(ic)
        res["RC"]["more_compact"] = [{"name": nm, "xy_extent": e} for nm, e in more]
        res["RC"]["most_compact"] = not more
        res["RC"]["xy_extent"] = ext_c
        say(progress, f"[R^C] symmetric paths onward lead to {', '.join(str(o['to']) for o in res['RC']['onward'])}, "
             + ("each less compact than R^C" if res["RC"]["onward_less_compact"] else "not all less compact")
             + f" (x-y extent {ext_c:.3f} a); "
             + (f"{len(more)} mapped symmetric states are more compact, the most {more[0][0]} ({more[0][1]:.3f} a)"
                if more else "no mapped symmetric state is more compact"))
    else:
        say(progress, f"[R^C] {res['RC'].get('map', 'an image of a node in the atlas')}")
    # ---- back: R^C -> R^B along the same path
    if br_c is not None:
        dirs = [br_c.directions[p.beta] * p.sign for p in br_c.paths if p.exists and p.tangent_ok]
        d_back = min(dirs, key=lambda d: d @ chord_BC / np.linalg.norm(d))
    else:
        d_back = -chord_BC
    res["RC"]["return_cos"] = float(d_back @ chord_BC / np.linalg.norm(d_back))
    if br_c is not None:
        back = [p for p in br_c.paths if p.exists and p.tangent_ok and
                np.array_equal(br_c.directions[p.beta] * p.sign, d_back)]
        snaps["R^C"] = {"length": 0.3, "base": rc.coords,
                        "paths": _branch_snaps(br_c, sail_rotation(rc, n_sides, 2), chord_BC,
                                               (back[0].beta, back[0].sign) if back else None, "back to R^B")}
    track.begin(rc)
    rb2, ev, steps = follow_to_bifurcation(rc, d_back, track, compare=True)
    if rb2 is None:
        res["failed"] = "R^B not reached on the way back"
        return _finish_hex(res, track, out, t_start, progress, stages, smap)
    _event(ev, steps, rc, rb2, hub, res)
    ev["distance_to_RB"] = float(np.abs(rb2.coords - rb.coords).max())
    res["events"]["RB_deploy"] = ev
    say(progress, f"[R^B] back after {steps} steps: m = {ev['m']}, s = {ev['s']}, {ev['factorizations']} "
         f"factorizations ({ev['method']}), {ev['distance_to_RB']:.1e} from the first R^B")
    an2 = rb2.analyse()
    d_flat = -chord_AB
    d_flat = an2.internal_mechanisms @ (an2.internal_mechanisms.T @ d_flat)
    track.begin(rb2)
    ra, ev, steps = follow_to_bifurcation(rb2, d_flat, track, compare=True)
    if ra is None:
        res["failed"] = "R^A not reached on the way back"
        return _finish_hex(res, track, out, t_start, progress, stages, smap)
    _event(ev, steps, rb2, ra, hub, res)
    res["events"]["RA_deploy"] = ev
    res["closure"] = float(np.abs(ra.coords - flat).max())
    say(progress, f"[R^A] back after {steps} steps: m = {ev['m']}, s = {ev['s']}, {ev['factorizations']} "
         f"factorizations ({ev['method']}), closure error {res['closure']:.2e}")
    if (n_sides, n_loops) == (6, 2):
        # which of the paper's statements this model reproduces (readings.py)
        say(progress, "[reading] the paper's statements on this model ...")
        res["reading"] = reading_record(MAIN_READING, threads)
        say(progress, f"[reading] {MAIN_READING}: {res['reading']['score']} of {res['reading']['of']} statements; "
            f"misses: {'; '.join(res['reading']['missed']) or 'none'}")
    if interference:
        # the paper's open question on this member: the first contact of its
        # membrane along the radially sequential fold (contactstudy.py)
        say(progress, "[interference] the membrane's first contact along the sequential fold ...")
        res["interference"] = member_study(n_sides, n_loops, threads=threads, progress=progress)
    return _finish_hex(res, track, out, t_start, progress, stages, smap, snaps)


def _event(ev, steps, start, at, hub, res):
    ev["steps"] = steps  # kin_follow_event's, the step that left the previous bifurcation included
    ev["l"] = abs(at.path_length - start.path_length)
    ev["hub_out_of_plane"] = float(np.abs(at.coords[hub, 2]).max())
    ev["measures"] = measures(at.coords, at.labels, res["n_sides"], res["n_loops"])


def _branch_snaps(br, P, chord_in, chosen, back_name):
    """The end of every directed path of br (exists, right tangent): its
    configuration, whether it keeps the symmetry P, and a tag: 'chosen',
    the arrival path continued ('straight on', cos with the arrival chord
    > 0.99) or retraced (back_name, cos < -0.99)."""
    out = []
    for p in br.paths:
        if not (p.exists and p.tangent_ok):
            continue
        d = br.directions[p.beta] * p.sign
        cos = float(d @ chord_in / np.linalg.norm(d))
        tag = ("chosen" if (p.beta, p.sign) == chosen else back_name if cos < -0.99 else
               "straight on" if cos > 0.99 else "")
        out.append({"beta": int(p.beta), "sign": int(p.sign), "coords": p.final_coords, "l": float(p.length),
                    "symmetric": bool(np.linalg.norm(P @ d - d) < 1e-6 * np.linalg.norm(d)), "tag": tag})
    return out


def _last_before(start, direction, l_target, back=0.05):
    """The point of the path out of `start` along `direction` at l_target - back."""
    l0 = start.path_length
    c = leave(start, direction)
    while True:
        rem = l_target - back - abs(c.path_length - l0)
        if rem <= 1e-12:
            return c
        dmax = c.options.step_fraction * np.sqrt(np.mean(c.rest_lengths ** 2))
        c.step(min(rem, dmax))


def _coords_at(track, start, direction, l_target):
    return _last_before(start, direction, l_target, back=0.0).coords


def _symmetric_record(rec):
    """The symmetric sub-problem at a node, from the atlas's record of how
    its branches were enumerated: k symmetric mechanisms, s equations."""
    return {"k": rec.get("k"), "s": rec.get("s_restricted", 0), "solutions": rec.get("solutions", 0),
            "accounting": rec.get("accounting", {"paths": 0, "real": rec.get("solutions", 0),
                                                 "real_distinct": rec.get("solutions", 0), "nonreal": 0,
                                                 "singular": 0, "failed": 0})}


def _finish_hex(res, track, out, t_start, progress, stages=(), smap=None, snaps=None):
    if smap is not None:
        res["map"] = smap.summary(Assembly.sail(res["n_sides"], res["n_loops"]))
        names = smap.names()
        for sn in (snaps or {}).values():
            for p in sn["paths"]:
                if "to" in p and p["to"] is not None:
                    # a path's end that is not a bifurcation says what it is
                    t = smap.nodes[p["to"]]
                    p["to"] = names[t.id] + ("" if t.kind == "bifurcation" else f" ({t.kind.replace('_', '-')})")
    if track is not None and track.l:
        res["max_strain"] = float(max(track.strain))
        res["max_hub_out_of_plane"] = float(max(track.hub_z))
        res["path_length_total"] = float(track.l[-1])
        res["steps_total"] = len(track.l) - 1
        ext = [float(np.hypot(x[:, 0], x[:, 1]).max()) for x in track.coords]
        k = int(np.argmin(ext))
        res["most_compact_on_run"] = {"xy_extent": ext[k], "l_total": float(track.l[k]),
                                      "height": float(np.ptp(track.coords[k][:, 2]))}
    res["seconds"] = round(time.perf_counter() - t_start, 1)
    if out is not None:
        out = pathlib.Path(out)
        # written aside and committed whole (libkin.atomic.staged_folder): a
        # failure leaves the folder of the last good run as it was
        with staged_folder(out) as stage:
            try:
                if smap is not None:
                    say(progress, f"[write] atlas.json: {len(smap.atlas.nodes):,} nodes, "
                                  f"{len(smap.atlas.edges):,} paths ...")
                    smap.atlas.to_json(stage / "atlas.json")
                    say(progress, "[write] atlas.html: the path map to walk in a browser ...")
                    res["map_html"] = smap.write_html(stage / "atlas.html", f"Path map of the {res['model']}",
                                                      progress=bool(progress))
                    if not res["map_html"]:
                        say(progress, "atlas.html not written: it needs plotly (pip install plotly)")
                if track is not None and track.l:
                    with replacing(stage / "track.npz") as tmp, open(tmp, "wb") as f:
                        np.savez(f, l=np.array(track.l), sv=np.array(track.sv),
                                 strain=np.array(track.strain), hub_z=np.array(track.hub_z))
                    from . import studyreport
                    studyreport.hexagonal(res, track, stages, stage, smap, snaps or {}, progress=progress)
            finally:  # with the figures' time when they were drawn
                write_text(stage / "summary.json", json.dumps(res, indent=1, default=jsonable) + "\n")
        say(progress, f"wrote {out / 'report.md'}")
    return res

