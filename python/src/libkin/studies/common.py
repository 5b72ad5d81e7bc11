"""What both sail studies use: progress messages, JSON values, and following
a branch out of a bifurcation to the next one with the library's follower
(follow_to_bifurcation), recording the path on the way."""
import sys

import numpy as np

from libkin.errors import KinError

# Bifurcations are located to v_r / v_max <= 1e-10 by the follower
# (kin_follow_event: the fast method, relaxed towards 1e-6 only where 1e-10 is
# out of reach, e.g. at a tangency) and m, s counted as the follower saw them.
SAIL_VR_TOL = 1e-10
# The paper's method is also run from the same point, at the paper's own
# tolerance, to compare its cost with the paper's step counts.
PAPER_VR_TOL = 1e-6
# two paths coincide when their end configurations agree to this (length unit)
SAME_CONFIG_TOL = 1e-6


def say(progress, msg):
    if progress:
        print(msg, file=sys.stderr, flush=True)


def accounting_words(a):
    """The complete solver's accounting (Branches.accounting) as words."""
    words = (f"{a['paths']} homotopy paths: {a['real']} real ({a['real_distinct']} distinct), {a['nonreal']} complex, "
             f"{a['singular']} singular, {a['failed']} failed")
    if "proven_real" in a:  # the interval certificates (absent from results of older runs)
        words += (f"; proven (interval certificates): {a['proven_real']} real, {a['proven_nonreal']} non-real, "
                  f"{a['unproven']} unproven")
    return words


def branch_words(rep):
    """A bifurcation's branch report (m, s, the solver's accounting, the
    directed paths) as one sentence."""
    if "accounting" not in rep:
        return f"m = {rep['m']}, s = {rep['s']} ({rep.get('skipped', 'not solved')})"
    return (f"m = {rep['m']}, s = {rep['s']}; the complete solver accounts for all {accounting_words(rep['accounting'])}; "
            f"{rep['directed_paths_ok']} directed paths exist with the right tangent, {rep['distinct_paths']} distinct"
            + (f" ({rep['seconds']} s)" if "seconds" in rep else ""))


def paper_locate(prev, at):
    """The paper's locator (tolerance PAPER_VR_TOL) from the regular point
    `prev` before the bifurcation `at`: its cost, for the report's question
    of how it compares with the follower's locator."""
    p = prev.clone()
    try:
        lp = p.locate(method="paper", vr_tol=PAPER_VR_TOL, max_steps=30)
    except KinError as exc:
        return {"gave_up": str(exc)}
    return {"factorizations": lp.factorizations, "forward": lp.forward, "v_r_rel": lp.v_r_rel,
            "distance_to_point": float(np.abs(p.coords - at.coords).max())}


def follow_to_bifurcation(start, direction, track=None, max_steps=600, vr_tol=SAIL_VR_TOL, compare=False):
    """Follow the branch `direction` out of the bifurcation `start` to its
    next event with the library's follower (kin_follow_event, the one the
    explorer uses), which locates a bifurcation to vr_tol (or to the best
    accuracy reachable, down to 1e-6) and classifies anything else.

    With a track, the path is then stepped again up to about one step
    before the event (the path is deterministic) to record the singular
    values, strains and configurations along it for the figures; compare=True
    also runs the paper's locator from the last point recorded.

    Returns (assembly at the bifurcation, event dict, steps), or (None,
    {"stopped": why}, steps) when the next event is not a bifurcation."""
    at = start.clone()
    fe = at.follow_event(direction, vr_tol=vr_tol, max_steps=max_steps)
    if fe.event != "bifurcation":
        return None, {"stopped": f"{fe.event} after l = {fe.length:.4f}" + (f": {fe.message}" if fe.message
                                                                              else "")}, fe.steps
    an = at.analyse()
    sv = np.sort(an.singular_values)
    ev = {"method": "fast", "follower": "kin_follow_event", "vr_tol": fe.vr_tol_used, "factorizations": fe.factorizations,
          "forward": fe.forward, "attempts": fe.attempts, "v_r_rel": fe.v_r_rel, "path_kept": fe.path_kept,
          "m": an.m_internal, "s": an.s, "zero_order": fe.zero_order, "tangent_cos": fe.tangent_cos,
          "lowest_sv_rel": [float(v / an.v_max) for v in sv[: an.s + 2]], "detected_after_steps": fe.steps}
    if track is not None or compare:
        prev = record(start, direction, fe.length, track)
        if compare:
            ev["paper_method"] = paper_locate(prev, at)
        if track is not None:
            track.add(at, an.singular_values)
            ev["l_total"] = track.l[-1]
    return at, ev, fe.steps


def record(start, direction, length, track):
    """Step from the bifurcation `start` along `direction` until within about
    two full steps of path length `length` (where the follower found the
    next event), recording each point in track; returns the last point."""
    l0 = start.path_length
    c = leave(start, direction)
    dmax = c.options.step_fraction * np.sqrt(np.mean(c.rest_lengths ** 2))
    if track is not None:
        track.add(c)
    while length - abs(c.path_length - l0) > 2.0 * dmax:
        prev = c.clone()
        try:
            c.step(0.0)
        except KinError:
            return prev
        if abs(c.path_length - l0) > length:  # an automatic step went past the event
            return prev
        if track is not None:
            track.add(c)
    return c


def leave(a, d):
    c = a.clone()
    c.set_direction(d)
    c.step(0.0)
    return c


def jsonable(v):
    if isinstance(v, (np.integer,)):
        return int(v)
    if isinstance(v, (np.floating,)):
        return float(v)
    if isinstance(v, np.bool_):
        return bool(v)
    return str(v)
