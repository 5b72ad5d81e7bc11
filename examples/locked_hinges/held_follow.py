"""Locked hinges by the follower itself (issue 37 item 3): each sail member's
radially sequential fold (libkin.studies.sequential) followed from the flat
state along leg 1 with contact events and ``hold_hinges=True``: where hinges
first close the follow stops with them held ('hinge-closed' or
'held-rigid'), and the next follow goes on with them held, or ends
'held-rigid' where the held structure has no motion; then the study's
leg 2 out of R^B is asked for with those holds. The lock bars of
locked_hinges.py ask the same question of a model with a bar between each
closed hinge's far corners; this asks the follower.

    LIBKIN_LIBRARY=build/libkin.so PYTHONPATH=python/src \\
        python examples/locked_hinges/held_follow.py [--members 6:1,...] [--out DIR]

Writes DIR/held_follow.json. Seconds per member (the fold is the cost).
"""
from __future__ import annotations

import argparse
import json
import os
import re
import time
from typing import Any, Dict, List, Optional

import numpy as np

import libkin
from libkin.errors import KinError
from libkin.studies.sailmeasure import sail_panels
from libkin.studies.sequential import sequential_fold


def passes_through(a: Any, samples: np.ndarray) -> List[int]:
    """Hinges whose fold angle jumps between +pi and -pi (through
    flat-folded) between two samples while not closed."""
    psi = np.array([a.hinge_angles(x) for x in samples])
    if len(psi) < 2:
        return []
    jump = (np.abs(np.diff(psi, axis=0)) > np.pi) & (np.pi - np.abs(psi[1:]) > 1e-6)
    return sorted(set(np.flatnonzero(jump.any(axis=0)).tolist()))


def member(n: int, loops: int) -> Dict[str, Any]:
    t0 = time.perf_counter()
    res = sequential_fold(n, loops, keep_states=True)
    S = res["samples"]
    a = res["assembly"].clone()
    a.panels = sail_panels(a)
    J, _ = a.hinges()
    labels = list(a.labels)
    name = lambda h: "-".join(labels[q] for q in J[h][:2])  # noqa: E731
    a.set_contact_events(True, 1e-9)
    rec: Dict[str, Any] = {"member": f"{n}:{loops}", "fold_length": float(res["legs"][-1]["l_end"]),
                           "leg1_end": float(res["legs"][0]["l_end"]), "follows": []}
    d: Optional[np.ndarray] = S.leave_dir[0]
    for _ in range(6):
        try:
            f = a.follow_event(d, max_steps=800, hold_hinges=True, samples=400)
        except KinError as e:  # a direction refused: no onward motion asked for
            rec["follows"].append({"error": str(e)})
            break
        held = [name(h) for h in _held(a, J)]
        rec["follows"].append({"event": f.event, "length": f.length, "m_internal": f.m_internal, "s": f.s,
                               "v_r_rel": f.v_r_rel, "held": f.held, "held_m": f.held_m,
                               "reopened": f.reopened, "held_hinges": held,
                               "through": [name(h) for h in passes_through(a, f.samples)]})
        if f.event not in ("hinge-closed", "hinge-reopened"):
            break
        d = None
    # the study's leg 2 out of R^B, with the holds the follow left there
    starts = sorted(S.leave_dir)
    if len(starts) > 1:
        a.coords = S.states[starts[1]].coords
        try:
            f = a.follow_event(S.leave_dir[starts[1]], max_steps=800, hold_hinges=True)
            rec["leg2"] = {"event": f.event, "length": f.length, "held": f.held, "reopened": f.reopened}
        except KinError as e:
            hit = re.search(r"hinge (\d+)", str(e))
            rec["leg2"] = {"refused": str(e), "hinge": name(int(hit.group(1))) if hit else None}
    rec["seconds"] = round(time.perf_counter() - t0, 1)
    return rec


def _held(a: Any, J: np.ndarray) -> List[int]:
    """Hinges closed to the hold's threshold (gap <= 1e-6 x the RMS rest
    length) at the current configuration."""
    X = np.asarray(a.coords)
    rms = float(np.sqrt(np.mean(np.asarray(a.rest_lengths) ** 2)))
    out = []
    for h, (i, j, p, q) in enumerate(J):
        e = X[j] - X[i]
        ua, ub = X[p] - X[i], X[q] - X[i]
        ua = ua - ua @ e / (e @ e) * e
        ub = ub - ub @ e / (e @ e) * e
        hmin = min(np.linalg.norm(ua), np.linalg.norm(ub))
        delta = np.arctan2(np.linalg.norm(np.cross(ua, ub)), ua @ ub)
        if 2 * hmin * np.sin(delta / 2) <= 1e-6 * rms:
            out.append(h)
    return out


def main(argv: Optional[List[str]] = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--members", default="6:1,6:2,8:1,8:2,6:3,8:3,6:4,8:4")
    ap.add_argument("--out", default=os.path.join(os.path.dirname(__file__)))
    args = ap.parse_args(argv)
    recs = []
    for m in args.members.split(","):
        n, loops = (int(v) for v in m.split(":"))
        r = member(n, loops)
        print(json.dumps(r), flush=True)
        recs.append(r)
        with open(os.path.join(args.out, "held_follow.json"), "w") as f:
            json.dump({"libkin": libkin.__version__, "members": recs}, f, indent=1)


if __name__ == "__main__":
    main()
