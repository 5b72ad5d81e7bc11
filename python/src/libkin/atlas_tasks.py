"""The units of work of libkin.explore, as plain functions of plain data.

Each runs anywhere (this process, a process pool, a Dask worker): it takes
a dict of JSON-able values (the model as JSON text, a configuration, a
direction) and returns one, so it pickles and ships without any handle.
The worker rebuilds the Assembly from the model text each time (a few
milliseconds), so nothing is cached between tasks and the result depends on
the task alone: the same whichever worker runs it, in whichever order.
"""
import math

import numpy as np

# event kinds of a directed branch (edge of the atlas)
BIFURCATION = "bifurcation"  # a bifurcation was located at the end
NEAR_MISS = "near_miss"      # v_r dipped towards zero but the point is regular
LOOP = "loop"                # the path came back to where it started
BUDGET = "budget"            # the length (or step) budget ran out first
FAILURE = "failure"          # following failed (corrector, path jump, ...)
EVENT_KINDS = (BIFURCATION, NEAR_MISS, LOOP, BUDGET, FAILURE)


def rebuild(task):
    """The Assembly of a task at its configuration, with its rank tolerance."""
    from .model_json import load_json
    a = load_json(task["model"])
    if task.get("rank_tol"):
        o = a.options
        o.rank_tol = float(task["rank_tol"])
        a.options = o
    a.coords = np.asarray(task["coords"], dtype=float)
    return a


def _rms_rest(a):
    return float(np.sqrt(np.mean(a.rest_lengths ** 2)))


def follow_branch(task):
    """Follow one directed branch to its next event.

    task: {"model": JSON text, "coords": (njoints, dim) list, "rank_tol",
    "direction": (nfree,) list (U_m beta times the sign), "max_length",
    "vr_tol"}. Returns {"event": one of EVENT_KINDS, "coords": end
    configuration, "length": path length travelled, "m", "m_rigid", "s",
    "v_r_rel" at the end, "accuracy" (distance to the event point, length
    unit; NaN if not estimated), "samples": a few configurations along the
    way, "message"}."""
    from .errors import KinError
    a = rebuild(task)
    d = np.asarray(task["direction"], dtype=float)
    samples = []
    out = {"samples": samples, "message": "", "accuracy": float("nan")}
    try:
        a.set_direction(d)
        a.step(0.0)
        samples.append(a.coords.tolist())
        return _follow_c(a, task, out)
    except KinError as exc:
        out.update(_end_state(a, FAILURE))
        out["message"] = f"{type(exc).__name__}: {exc}"
        return out


def _follow_c(a, task, out):
    """Until the C follower (kin_follow_event) is wired in: follow with
    kin_locate_next, bounded by the step count that covers max_length."""
    from .errors import KinError
    step = a.options.step_fraction * _rms_rest(a)
    max_steps = max(1, int(math.ceil(float(task["max_length"]) / step)))
    l0 = a.path_length
    try:
        li = a.locate(method="fast", vr_tol=float(task.get("vr_tol", 1e-10)), max_steps=max_steps)
    except KinError as exc:
        l = abs(a.path_length - l0)
        kind = BUDGET if l >= 0.9 * max_steps * step else NEAR_MISS
        out.update(_end_state(a, kind))
        out["message"] = str(exc)
        return out
    out.update(_end_state(a, BIFURCATION if li.m_internal >= 2 else NEAR_MISS))
    out["accuracy"] = float(li.v_r_rel)
    return out


def _end_state(a, kind):
    an = a.analyse()
    return {"event": kind, "coords": a.coords.tolist(), "length": float(abs(a.path_length)),
            "m": int(an.m_internal), "m_rigid": int(an.m_rigid), "s": int(an.s),
            "v_r_rel": float(an.v_r / an.v_max) if an.v_max > 0 else 0.0}


def solve_task(task):
    """The complete solver on one system: task {"Q": (s, m, m) list, "seed"}
    -> {"betas": (nsol, m) list, "accounting": dict}."""
    from .assembly import solve_quadrics
    betas, acc = solve_quadrics(np.asarray(task["Q"], dtype=float), "homotopy", seed=int(task.get("seed", 1)),
                                threads=int(task.get("threads", 1)))
    return {"betas": betas.tolist(), "accounting": {k: int(v) for k, v in acc.items()}}
