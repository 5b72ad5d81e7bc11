"""The paper's open question (Section 7), answered with numbers.

"It is likely that there would be interference if one considered a larger
solar sail, whose folding pattern consists of several loops of triangles.
Of course, the effect of modelling the thickness of the membrane will also
need to be considered." For each sail family member (hub of n_sides, n_loops
loops) this module folds the sail along its radially sequential path
(sequential.py), gives the model its panels (the bar triangles and the hub
polygon: the membrane) and finds, for zero thickness and for each panel
thickness t (bars of radius t/2), the first contact along the fold: where on
the path, which two parts, and how much of the fold was done before it.

Why one clearance curve serves every thickness: with every bar of radius
t/2 and every panel of thickness t, the clearance of any two parts is their
centre geometries' distance minus t (kin_contact.h), so the clearance at
thickness t is c0(l) - t, c0 the zero-thickness clearance (tested).

The first contact is found by a certified search, not by sampling alone:
c0 changes no faster than the closest points move: each is an average of
its part's joints, the two parts share no joint, and the joints' speeds
squared sum to at most 1 along the path (the path length is the free
coordinates' arc length), so |dc0/dl| <= sqrt(2) and between two path
points l_a < l_b, c0 >= (c0(l_a) + c0(l_b) - sqrt(2) (l_b - l_a)) / 2.
An interval whose bound is above t cannot hold a contact; any other is split
by stepping the path to its middle, down to S_TOL. The path length of the
recorded steps is a sum of chords, a little shorter than the arc; ARC_MARGIN
covers that.
"""
import time
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

from libkin.errors import KinError

from .common import say
from .sailmeasure import TOUCH, part_name, sail_panels  # the membrane: sailmeasure.py
from .sequential import sequential_fold

# the panel thicknesses of the study, in hub sides a (0: bare intersection)
THICKNESSES = (0.0, 0.001, 0.003, 0.01, 0.03)
# a first contact is located along the path to this (hub sides)
S_TOL = 1e-7
# the sum of chords between two recorded points, times this, bounds the arc
ARC_MARGIN = 1.01
# how fast the clearance can change per unit path length: the closest
# points of two parts that share no joint move with distinct joints, whose
# speeds squared sum to at most 1 (a unit tangent), so |dc/dl| <= sqrt(2)
LIPSCHITZ = 2.0 ** 0.5 * ARC_MARGIN
# the members of the study
MEMBERS = tuple((n, k) for n in (6, 8) for k in (1, 2, 3, 4))


class _Search:
    """The certified first-contact search along one fold's samples."""

    def __init__(self, model: Any, samples: Any) -> None:
        self.model = model
        self.s = samples
        self.c0 = [model.clearance(x).value for x in samples.coords]
        self.evaluations = 0

    def _step_to(self, k: int, h: float) -> Tuple[float, Any]:
        """Step the path from sample k's state by about h (steps of at most
        the largest the path allows): (the length reached beyond sample k,
        the configuration there)."""
        c = self.s.states[k].clone()
        if k in self.s.leave_dir:
            c.set_direction(self.s.leave_dir[k])
        l0 = c.path_length
        dmax = c.options.step_fraction * float(np.sqrt(np.mean(c.rest_lengths ** 2)))
        while True:
            rem = h - abs(c.path_length - l0)
            if rem <= 1e-3 * S_TOL:
                break
            c.step(min(rem, dmax))
            self.evaluations += 1
        return abs(c.path_length - l0), c.coords

    def _point(self, k: int, h: float) -> Tuple[float, Any]:
        """The path point h beyond sample k: its length from the flat state
        and its configuration. A step's chord differs from the amplitude
        asked for by up to about 1e-3 of it, so the request is corrected by
        what it missed, a few times, until it lands within S_TOL / 8."""
        req = h
        for _ in range(4):
            got, x = self._step_to(k, req)
            if abs(got - h) <= S_TOL / 8:
                break
            req -= got - h
        return self.s.l[k] + got, x

    def first(self, t: float) -> Optional[Dict[str, Any]]:
        """The first point of the fold with clearance <= t (t = 0: <= TOUCH):
        {"l", "coords", "clearance"}, or None."""
        lim = max(t, TOUCH)
        if self.c0[0] <= lim:
            return {"l": 0.0, "coords": self.s.coords[0]}
        for k in range(1, len(self.c0)):
            hit = self._interval(k - 1, 0.0, self.c0[k - 1], self.s.l[k] - self.s.l[k - 1], self.c0[k],
                                 self.s.coords[k], lim)
            if hit is not None:
                return hit
        return None

    def _interval(self, k: int, ha: float, ca: float, hb: float, cb: float, xb: Any,
                  lim: float) -> Optional[Dict[str, Any]]:
        # the points ha < hb beyond sample k; ca > lim is known
        if (ca + cb - LIPSCHITZ * (hb - ha)) / 2.0 > lim:
            return None
        if hb - ha <= S_TOL:
            return {"l": self.s.l[k] + hb, "coords": xb} if cb <= lim else None
        hm = 0.5 * (ha + hb)
        try:
            lm, xm = self._point(k, hm)
        except KinError:  # cannot step there: judge the interval by its ends
            return {"l": self.s.l[k] + hb, "coords": xb} if cb <= lim else None
        hm = lm - self.s.l[k]
        if not ha < hm < hb:  # the step did not land inside: judge the interval by its ends
            return {"l": self.s.l[k] + hb, "coords": xb} if cb <= lim else None
        cm = self.model.clearance(xm).value
        if cm <= lim:
            left = self._interval(k, ha, ca, hm, cm, xm, lim)
            return left if left is not None else {"l": self.s.l[k] + hm, "coords": xm}
        left = self._interval(k, ha, ca, hm, cm, xm, lim)
        return left if left is not None else self._interval(k, hm, cm, hb, cb, xb, lim)


def _leg_at(legs: List[Dict[str, Any]], l: float) -> Tuple[int, float]:
    """(leg number, fraction of that leg done) at path length l."""
    for leg in legs:
        if l <= leg["l_end"] + 1e-12:
            span = max(leg["l_end"] - leg["l_start"], 1e-300)
            return leg["leg"], min(1.0, max(0.0, (l - leg["l_start"]) / span))
    return legs[-1]["leg"] if legs else 0, 1.0


def member_study(n_sides: int, n_loops: int, thicknesses: Sequence[float] = THICKNESSES, threads: int = 1,
                 progress: bool = False, executor: Any = None) -> Dict[str, Any]:
    """Fold one member and find its first contact at each thickness.
    Returns a JSON-serialisable dict (the fold's legs, the paper's claim
    checked on it, and per thickness the first contact or none)."""
    t0 = time.perf_counter()
    fold = sequential_fold(n_sides, n_loops, threads=threads, progress=progress, executor=executor,
                           keep_states=True)
    a = fold["assembly"]
    model = a.clone()
    panels = sail_panels(a)
    model.panels = panels
    model.set_thickness(0.0)
    search = _Search(model, fold["samples"])
    total = fold["path_length"]
    res: Dict[str, Any] = {k: v for k, v in fold.items() if k not in ("samples", "assembly")}
    # the share of the fold (by path length) between recorded points that
    # both intersect at zero thickness: parts passing through each other
    L, c0 = np.asarray(fold["samples"].l), np.asarray(search.c0)
    both = (c0[1:] <= TOUCH) & (c0[:-1] <= TOUCH)
    res["intersecting_share"] = float(np.sum(np.diff(L)[both]) / total) if total else 0.0
    res.update({"panels": len(panels), "bars": a.nbars, "samples": len(search.c0),
                "min_clearance_sampled": float(min(search.c0[1:])) if len(search.c0) > 1 else None,
                "contacts": []})
    for t in thicknesses:
        hit = search.first(t)
        row: Dict[str, Any] = {"t": t}
        if hit is None:
            row.update({"contact": False, "fold_fraction": 1.0})
        else:
            c = model.clearance(hit["coords"])
            leg, frac = _leg_at(fold["legs"], hit["l"])
            row.update({"contact": True, "l": hit["l"], "fold_fraction": hit["l"] / total if total else 0.0,
                        "leg": leg, "leg_fraction": frac, "clearance0": c.value,
                        "parts": [part_name(a, panels, kd, i) for kd, i in c.parts],
                        "part_ids": [[kd, int(i)] for kd, i in c.parts],
                        "coords": np.asarray(hit["coords"]).tolist(),
                        "points": np.asarray(c.points).tolist()})
        res["contacts"].append(row)
        say(progress, f"[contact {n_sides}/{n_loops}] t = {t:g}: " + (
            "no contact along the fold" if not row["contact"] else
            f"first contact at l = {row['l']:.4f} ({100 * row['fold_fraction']:.1f} % of the fold, leg {leg}): "
            + " / ".join(row["parts"])))
    res["refinement_steps"] = search.evaluations
    res["seconds"] = round(time.perf_counter() - t0, 1)
    return res


def interference_study(members: Sequence[Tuple[int, int]] = MEMBERS, thicknesses: Sequence[float] = THICKNESSES,
                       threads: int = 1, progress: bool = False, executor: Any = None) -> Dict[str, Any]:
    """member_study over the members; {"members": [...], "thicknesses"}."""
    return {"thicknesses": list(thicknesses),
            "members": [member_study(n, k, thicknesses, threads, progress, executor) for n, k in members]}
