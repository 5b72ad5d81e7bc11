"""Fixed thresholds that decide a reported fact, judged with a margin
(issue 35 item 4; docs/sail_study.md).

A study reports facts decided by a fixed threshold: loop 1 "wraps" when its
nodes lie within WRAP_TOL of their hub vertices in x-y. Judged at a point
whose position is known only to some accuracy, a value near the threshold
can flip with rounding, the BLAS kernel or the order branches arrived in (the
coarsely located m = 4, s = 3 nodes of issue 35 had offsets 7e-6..5e-5
against 1e-5). So a threshold here decides only with a margin: "yes" where
the value plus its uncertainty is at most threshold / MARGIN, "no" where the
value minus its uncertainty is at least threshold x MARGIN, and otherwise
"undecided", reported with the numbers, never counted either way.

The uncertainty of a position measured at a located bifurcation: a point
whose vanishing singular values are all at most tol x v_max lies within
tol x v_max / slope of the bifurcation along the path, slope the rate at
which the steepest of them grows (relative to v_max, per unit length). The
sails' bifurcations have slopes of 0.01..1 (the collapsed hub's pair 0.2);
MIN_SLOPE = 1e-3 is taken as the bound, so a node located to 1e-10 is
placed to 1e-7 and one located only to a relaxed 1e-7 to 1e-4.
"""
from __future__ import annotations

from typing import Any, Dict, Optional

MARGIN = 10.0
MIN_SLOPE = 1e-3

YES, NO, UNDECIDED = "yes", "no", "undecided"


def position_uncertainty(located_tol: float) -> float:
    """How far a point located to v_r <= located_tol v_max may lie from the
    bifurcation (length units of a unit hub side); 0 for a point that is not
    a located bifurcation (located_tol 0: a configuration taken as given)."""
    return max(0.0, float(located_tol)) / MIN_SLOPE


def below(value: float, threshold: float, uncertainty: float = 0.0, margin: float = MARGIN) -> str:
    """YES, NO or UNDECIDED: whether value < threshold, decided only with the
    margin (see the module's text)."""
    if value + uncertainty <= threshold / margin:
        return YES
    if value - uncertainty >= threshold * margin:
        return NO
    return UNDECIDED


def verdict_record(value: float, threshold: float, uncertainty: float, verdict: str) -> Dict[str, Any]:
    """The numbers a verdict was decided on, for a report."""
    return {"value": float(value), "threshold": float(threshold), "uncertainty": float(uncertainty),
            "margin": MARGIN, "verdict": verdict}


def as_bool(verdict: str) -> Optional[bool]:
    """True, False, or None for UNDECIDED."""
    return True if verdict == YES else False if verdict == NO else None
