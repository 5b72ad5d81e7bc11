"""The units of work of libkin.explore, as plain functions of plain data.

Each runs anywhere (this process, a process pool, a Dask worker): it takes
a dict of JSON-able values and NumPy arrays (the model as JSON text, a
configuration, a direction) and returns JSON-able values, so it pickles and
ships without any handle. The explorer's arrays stay arrays: the store hashes
them by their bytes (a JSON encoding of their numbers cost 45 of the 75 us
of a branch task's key, 4.5 s of the client's CPU before the hexagonal
sail's full atlas could start) and Dask does not walk them.
A worker parses each model text once (parsing and creating the hexagonal
sail's Assembly took 5.4 ms, a third of a branch task) and keeps it as a
template: a task clones it (0.02 ms) and sets its configuration. A fresh
clone of a never-used handle is the freshly loaded handle, so the result
still depends on the task alone: the same whichever worker runs it, in
whichever order, with or without the cache (python/tests/test_atlas.py).
"""
from __future__ import annotations

import functools
import json
import math
import time
from typing import TYPE_CHECKING, Any, Dict, List, Optional

import numpy as np

if TYPE_CHECKING:
    from ..assembly import Assembly

Task = Dict[str, Any]

# model templates kept per process (rebuild): an atlas uses one model, a
# process that serves several runs a few
TEMPLATES = 4

# event kinds of a directed branch (edge of the atlas)
BIFURCATION = "bifurcation"  # a bifurcation was located at the end
NEAR_MISS = "near_miss"      # v_r dipped towards zero but the point is regular
LOOP = "loop"                # the path came back to where it started
BUDGET = "budget"            # the length (or step) budget ran out first
FAILURE = "failure"          # following failed (corrector, path jump, ...)
CONTACT = "contact"          # two parts touched first (explore(contact=True), docs/contact.md)
EVENT_KINDS = (BIFURCATION, NEAR_MISS, LOOP, BUDGET, FAILURE, CONTACT)


@functools.lru_cache(maxsize=TEMPLATES)
def _template(model: str, rank_tol: Optional[float]) -> Assembly:
    """The Assembly of a model text with its rank tolerance, parsed once per
    process (never stepped nor analysed: tasks only clone it)."""
    from ..io.model_json import load_json
    a = load_json(model)
    if rank_tol:
        o = a.options
        o.rank_tol = float(rank_tol)
        a.options = o
    return a


def rebuild(task: Task) -> Assembly:
    """The Assembly of a task at its configuration, with its rank tolerance:
    a clone of the model's template (_template), so a task never changes
    what the next one starts from."""
    rank_tol, model = task.get("rank_tol"), task["model"]
    if not isinstance(model, str):  # a model dict (the explorer sends text)
        model = json.dumps(model, sort_keys=True)
    a = _template(model, float(rank_tol) if rank_tol else None).clone()
    a.coords = np.asarray(task["coords"], dtype=float)
    return a


def _rms_rest(a: Assembly) -> float:
    return float(np.sqrt(np.mean(a.rest_lengths ** 2)))


_EVENTS = {"bifurcation": BIFURCATION, "near-miss": NEAR_MISS, "closed-loop": LOOP, "length-limit": BUDGET,
           "step-limit": BUDGET, "contact": CONTACT}


def follow_branch(task: Task) -> Dict[str, Any]:
    """Follow one directed branch to its next event (kin_follow_event).

    task: {"model": JSON text, "coords": (njoints, dim) array or list,
    "rank_tol", "direction": (nfree,) array or list (U_m beta times the
    sign), "max_length",
    "max_steps", "vr_tol", "samples": how many configurations to record along
    the way, "branches": optional, the start's branch directions, a list or
    an array (a return along another branch is located, not a loop; a subset
    of them: atlas/directions.py), or with "own" (the index of direction's
    line among them) all of them as a libkin.shared reference (read and
    checked once per process), "contact": stop at the first
    contact of two parts}. Returns {"event": one of EVENT_KINDS, "coords": end
    configuration, "length": path length travelled, "m", "m_rigid", "s",
    "v_r_rel" at the end (analysis at the rank tolerance), "accuracy" (the
    vanishing singular value / v_max where the event was located), "vr_tol"
    (the tolerance it was located to), "steps", "samples", "message",
    a near miss's "min_located" and "min_width" (its end is the minimum of
    v_r / v_max along the path, located to that path length / RMS length),
    "cpu_seconds" (this task's CPU time in its process), with "branches" and
    a loop "return_angle" (radians, its return direction to its own branch)
    and "return_tangent" (the path's direction at the end, where regular)}.
    The samples come from the same follow (kin_follow_event_ex records the
    points its steps reach, record_room(n) of them): for k = 1..n the
    recorded point whose path length is nearest k/(n+1) of the event's
    length, and more of the recorded points where the viewer's curve
    through the samples would strain a bar by more than 1 % (frames.py);
    the branch is followed once."""
    from ..parallel import one_blas_thread
    with one_blas_thread():
        return _follow_branch(task)


def _follow_branch(task: Task) -> Dict[str, Any]:
    from ..errors import KinError
    cpu0 = time.process_time()
    a = rebuild(task)
    n = int(task.get("samples", 0))
    if task.get("contact"):
        a.set_contact_events(True, 1e-9)
    d = np.asarray(task["direction"], dtype=float)
    br, own = task.get("branches"), task.get("own")
    if own is not None:  # every line of the node, shared with the workers (directions.follow)
        from ..assembly import BranchLines
        from ..shared import resolve
        br = resolve(br, BranchLines)
    lim: Dict[str, Any] = {"max_steps": int(task.get("max_steps", 1000)), "vr_tol": float(task.get("vr_tol", 1e-10))}
    samples: list[Any] = []
    out: Dict[str, Any] = {"samples": samples, "message": ""}
    try:
        view = bool(task.get("view", True))  # the viewer's extra samples (explore(view_samples))
        ev = a.follow_event(d, max_length=float(task["max_length"]), samples=record_room(n) if view else SAMPLE_ROOM * n,
                            branches=br, own_branch=own, **lim)
    except KinError as exc:
        out.update(_end_state(a, FAILURE))
        out.update({"message": f"{type(exc).__name__}: {exc}", "accuracy": float("nan"), "vr_tol": 0.0,
                    "steps": 0, "cpu_seconds": time.process_time() - cpu0})
        return out
    kind = _EVENTS.get(ev.event, FAILURE)
    if kind == FAILURE:
        out["message"] = f"{ev.status}: {ev.message}"
    if kind == CONTACT:
        out["message"] = "contact: " + " / ".join(f"{k} {i}" for k, i in a.last_contact().parts)
    rank_tol = max(float(task.get("rank_tol") or 1e-9), 10.0 * ev.vr_tol_used) if kind == BIFURCATION else None
    if kind == NEAR_MISS and ev.v_r_rel > 0:  # counted as the follower decided: v_r is not zero there
        rank_tol = min(float(task.get("rank_tol") or 1e-9), 0.1 * float(ev.v_r_rel))
    out.update(_end_state(a, kind, rank_tol))
    out.update({"accuracy": float(ev.v_r_rel), "vr_tol": float(ev.vr_tol_used) if kind == BIFURCATION else 0.0,
                "steps": int(ev.steps), "length": float(ev.length), "at_start": bool(ev.at_start)})
    if kind == NEAR_MISS:  # the end is the located minimum of v_r / v_max, to min_width (orbits.certain)
        out.update({"min_located": bool(ev.min_located), "min_width": float(ev.min_width)})
        out.update(near_verdict(float(ev.v_r_rel), float(ev.vr_tol_used), bool(ev.min_located)))
    if kind == BIFURCATION and out["m"] == 2 and out["s"] == 1:
        out.update(crossing_verdict(a, float(ev.vr_tol_used)))
    if kind == LOOP and br is not None:  # for atlas/directions.py
        out["return_angle"] = float(ev.return_angle)  # to the own branch
        an = a.analyse() if own is None else None  # decided with every line: nothing to decide again
        if an is not None and an.m_internal == 1:  # the path's direction at the end, near the start
            out["return_tangent"] = [float(v) for v in an.internal_mechanisms[:, 0]]
    samples.extend(_pick_samples(ev.samples, ev.sample_lengths, ev.length, n, start=task["coords"], end=a.coords,
                                 bars=a.bars if view else None, rest=a.rest_lengths))
    out["cpu_seconds"] = time.process_time() - cpu0
    return out


# a bifurcation's branch directions go whole with each of its branch tasks up
# to this many numbers (branches x nfree); beyond (the hexagonal sail's flat
# state: 29,828 x 46) each task gets the exact subset of directions.follow
BRANCH_DIRECTIONS_MAX = 20000


# recorded points per sample asked for: the follower keeps them evenly spread
# by steps, so the one nearest each wanted length is within about a step of it
SAMPLE_ROOM = 8
# at least this many recorded points to pick from where samples are asked
# for: where the viewer's curve through the evenly spread samples would
# stretch a bar by more than frames.VIEW_STRAIN, more are stored from these
VIEW_RECORD = 128


def record_room(n: int) -> int:
    """How many configurations the follower records along a path for n samples."""
    return max(SAMPLE_ROOM * n, VIEW_RECORD) if n > 0 else 0


def _pick_samples(recorded: Any, lengths: Any, total: float, n: int, start: Any = None, end: Any = None,
                  bars: Any = None, rest: Any = None) -> list[Any]:
    """For k = 1..n the recorded configuration nearest k/(n+1) of the path
    length (each used once; fewer when fewer were recorded) and, given the
    path's start and end and the model's bars, more of the recorded ones
    where the viewer's curve through them strains a bar by more than
    frames.VIEW_STRAIN (frames.choose); in path order."""
    if n <= 0 or recorded is None or len(recorded) == 0:
        return []
    lengths = np.asarray(lengths, dtype=float)
    used: list[int] = []
    for k in range(1, n + 1):
        order = np.argsort(np.abs(lengths - total * k / (n + 1)))
        i = next((int(j) for j in order if int(j) not in used), None)
        if i is None:
            break
        used.append(i)
    from .frames import choose
    if start is not None and end is not None and bars is not None and rest is not None:
        used = choose(start, recorded, end, used, bars, rest)
    return [recorded[i].tolist() for i in sorted(used)]


# a near miss is one where the located minimum of v_r / v_max is this many
# times above the floor a crossing would leave at the width it was located
# to (the follower's vr_tol_used for a near miss, docs/follow.md); below that
# margin it is undecided (issue 35 item 4)
NEAR_MARGIN = 10.0
UNDECIDED_WHY = ("undecided: the minimum of v_r / v_max here is neither at the strict tolerance nor "
                 f"{NEAR_MARGIN:g} x above the floor a crossing would leave at its located width")


def undecided_why(res: Dict[str, Any]) -> str:
    """An undecided end's reason, with its numbers (a node's status): a
    located minimum without the margin, or a relaxed point lower than the
    minimum found (docs/follow.md, "Tolerance out of reach")."""
    v, floor = float(res.get("accuracy", math.nan)), float(res.get("floor", math.nan))
    if res.get("event") == BIFURCATION and "crossing_ratio" in res:
        rho, tol = float(res["crossing_ratio"]), math.sqrt(float(res.get("vr_tol", 1e-10)))
        return (f"undecided: tangent branches? The second-order form's eigenvalues here have the ratio {rho:.2g} "
                f"(located to v_r / v_max = {v:.2g}); a crossing needs it below -{tol:.2g}, the square root of the "
                "tolerance located to, as second order cannot tell a crossing from a tangency within that")
    if res.get("min_located"):
        return (f"undecided: the minimum of v_r / v_max here, {v:.2g}, is neither at the strict tolerance nor "
                f"{NEAR_MARGIN:g} x above the floor a crossing would leave at its located width, {floor:.2g}")
    return (f"undecided: a relaxed location reached v_r / v_max = {v:.2g} here (accepted at {floor:.2g}), lower than "
            "the minimum of v_r found around it; Moore's extended system did not prove a singular structure within "
            "the model's rounding near it")


def near_verdict(v_rel: float, floor: float, located: bool) -> Dict[str, Any]:
    """The near miss's floor and whether it is undecided: a minimum not
    NEAR_MARGIN x above its floor, or a point not located with a floor (the
    follower's relaxed point that no minimum of v_r explained), is reported
    with its numbers rather than called a near miss or a bifurcation."""
    return {"floor": floor, "undecided": bool(floor > 0 and (not located or not v_rel > NEAR_MARGIN * floor))}


# the rules that decide a branch task's result (its kind, its verdicts): part
# of a store's identity (explorer.explore), so that a run resumed under other
# rules recomputes nothing silently from results decided the old way. 2:
# crossing_verdict below
RESULT_RULES = 2

# A corank-1 bifurcation (m = 2, s = 1) is two branches crossing where its
# second-order form Q (2 x 2) is indefinite: its eigenvalues l_small, l_large
# (by magnitude) of opposite signs, the branches at 2 atan sqrt(|l_small /
# l_large|) to each other. Where the ratio rho = l_small / l_large is not
# below -sqrt(tau) (tau the tolerance the point was located to: 1e-5 at the
# default 1e-10), second order cannot tell a crossing from a tangency there:
# at a tangency v_r grows like the square of the path length, so a point
# located to tau lies anywhere within about sqrt(tau) of the RMS length of
# the exact one, and l_small / l_large moves by as much over that stretch.
# Such an end is undecided (issue 35 item 4), with its ratio; never a
# bifurcation to expand. Measured on the depth-5 atlas of sail:6:2
# (docs/atlas.md, "Tangent branches"): the crossings have rho <= -2e-4, the
# others |rho| <= 1.3e-7: on both sides the margin is more than 10
def crossing_verdict(a: Assembly, tau: float) -> Dict[str, Any]:
    """The crossing test of a corank-1 bifurcation end, the assembly at it
    and analysed with m = 2, s = 1: {"crossing_ratio": rho} and, where rho is
    not below -sqrt(tau), "undecided": True. Nothing where second order has
    no form here (the self-stress is one of bars between fixed joints)."""
    from ..errors import StateError
    try:
        Q = a.second_order(normalise=False)
    except StateError:
        return {}
    lam = np.linalg.eigvalsh(0.5 * (Q[0] + Q[0].T))
    small, big = lam[np.argsort(np.abs(lam), kind="stable")]  # two distinct ones, even for -l, l
    rho = float(small / big) if big != 0.0 else 0.0
    out: Dict[str, Any] = {"crossing_ratio": rho}
    if not rho <= -math.sqrt(tau):
        out["undecided"] = True
    return out


def _end_state(a: Assembly, kind: str, rank_tol: Optional[float] = None) -> Dict[str, Any]:
    an = None
    if rank_tol is not None and min(0.5, rank_tol) != a.options.rank_tol:
        # a point located only to a coarser v_r is analysed as the follower saw it
        o = a.options
        o.rank_tol = min(0.5, rank_tol)
        a.options = o
    elif kind not in (FAILURE, NEAR_MISS):
        # the follower's own analysis of the end, where current (0.3 ms a task saved, 4% of
        # a branch): the same analysis to the bit where the rank tolerance is the handle's
        # (399 of 400 flat-state branches; the other a bifurcation located to 1e-8, which
        # the branch above analyses at 1e-7). Not a near miss's (or undecided) end: the
        # follower's analysis there may be a relaxed attempt's, at its coarser tolerance
        an = a.current_analysis()
    if an is None:
        an = a.analyse()
    return {"event": kind, "coords": a.coords.tolist(), "length": float(abs(a.path_length)),
            "m": int(an.m_internal), "m_rigid": int(an.m_rigid), "s": int(an.s),
            "v_r_rel": float(an.v_r / an.v_max) if an.v_max > 0 else 0.0}


def solve_task(task: Task) -> Dict[str, Any]:
    """The complete solver on one system: task {"Q": (s, m, m) list, "seed"}
    -> {"betas": (nsol, m) list, "accounting": dict}."""
    from ..assembly import solve_quadrics
    betas, acc = solve_quadrics(np.asarray(task["Q"], dtype=float), "homotopy", seed=int(task.get("seed", 1)),
                                threads=int(task.get("threads", 1)))
    return {"betas": betas.tolist(), "accounting": {k: int(v) for k, v in acc.items()}}
