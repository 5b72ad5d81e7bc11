"""The square-hub sail's study (paper Section 6.1, Figure 11): every
second-order solution at the flat state, each followed both ways; distinct
paths, their symmetry relations, and the paths to the fully folded state."""
import json
import pathlib
import time

import numpy as np

from libkin.assembly import Assembly
from libkin.atomic import staged_folder, write_text

from .common import SAME_CONFIG_TOL, accounting_words, follow_to_bifurcation, jsonable, say


def square_study(length=1.75, threads=2, progress=True, out=None):
    """Section 6.1: every second-order solution at the square sail's flat
    state, each followed both ways to `length`; distinct paths, their
    symmetry relations, and the two paths to the fully folded state."""
    t_start = time.perf_counter()
    a = Assembly.sail(4, 1)
    an = a.analyse()
    res = {"model": "sail 4-gon hub, 1 loop", "flat": {"m": an.m_internal, "m_rigid": an.m_rigid, "s": an.s}}
    say(progress, f"flat state: m = {an.m_internal} internal + {an.m_rigid} rigid, s = {an.s}")
    br = a.branches(solver="homotopy", length=length, threads=threads)
    res["accounting"] = br.accounting
    ok = [p for p in br.paths if p.exists and p.tangent_ok]
    res["real_solutions"] = len(br.betas)
    res["directed_paths_ok"] = len(ok)
    res["distinct_paths"] = br.distinct
    say(progress, f"the complete solver accounts for all {accounting_words(br.accounting)}; {len(ok)} directed "
         f"paths reach l = {length}, {br.distinct} distinct")
    lab = a.labels
    V1, V3, O0, O2 = (lab.index(n) for n in ("V1", "V3", "A0", "A2"))
    ends = [p.final_coords for p in br.paths]
    flat = a.coords
    # symmetries of the flat sail with its supports: rotation by pi about z
    # (V0 <-> V2), the mirror z -> -z, and both
    perm = np.array([2, 3, 0, 1, 6, 7, 4, 5])
    rot = np.diag([-1.0, -1.0, 1.0])
    mir = np.diag([1.0, 1.0, -1.0])
    ops = {"rot180": lambda x: (x @ rot.T)[np.argsort(perm)], "mirror": lambda x: x @ mir.T,
           "rot180+mirror": lambda x: ((x @ rot.T) @ mir.T)[np.argsort(perm)]}
    assert np.abs(ops["rot180"](flat) - flat).max() < 1e-12
    relations, folded = [], []
    for i, p in enumerate(br.paths):
        if not (p.exists and p.tangent_ok):
            continue
        x = ends[i]
        # the folding paths keep the two-fold symmetry and move the free hub
        # nodes and the outer nodes O0, O2 to opposite sides (paper 6.1);
        # each candidate is followed on to the bifurcation it reaches
        pattern = None
        if x[V1, 2] < 0 and x[V3, 2] < 0 and x[O0, 2] > 0 and x[O2, 2] > 0:
            pattern = "V1, V3 down; O0, O2 up"
        if x[V1, 2] > 0 and x[V3, 2] > 0 and x[O0, 2] < 0 and x[O2, 2] < 0:
            pattern = "V1, V3 up; O0, O2 down"
        if pattern and np.abs(ops["rot180"](x) - x).max() < SAME_CONFIG_TOL:
            at, ev, _ = follow_to_bifurcation(a, br.directions[p.beta] * p.sign, None, max_steps=400)
            f = {"path": i, "pattern": pattern}
            if at is not None:
                z = at.coords[:, 2]
                f.update({"ends_at_l": abs(at.path_length), "m": ev["m"], "s": ev["s"],
                          "end_z": [round(float(v), 6) for v in z],
                          "hub_fold_deg": round(float(np.degrees(np.arcsin(min(1.0, abs(z[V1]) / np.sqrt(0.5))))), 3)})
            folded.append(f)
        for name, op in ops.items():
            y = op(x)
            for j, q in enumerate(br.paths):
                if j > i and q.exists and q.tangent_ok and np.abs(ends[j] - y).max() < SAME_CONFIG_TOL:
                    relations.append({"path": i, "other": j, "by": name})
    res["symmetry_relations"] = relations
    res["fully_folded_paths"] = folded
    res["seconds"] = round(time.perf_counter() - t_start, 1)
    say(progress, f"{len(folded)} fully folded candidate{'' if len(folded) == 1 else 's'}"
         + (":" if folded else ""))
    for f in folded:
        say(progress, f"  path {f['path']}: {f['pattern']}; " + (
            f"reaches a bifurcation at l = {f['ends_at_l']:.4f} (m = {f['m']}, s = {f['s']}), the hub folded "
            f"{f['hub_fold_deg']:.1f} deg" if "m" in f else "reaches no bifurcation"))
    if out is not None:
        out = pathlib.Path(out)
        from . import studyreport
        with staged_folder(out) as stage:  # committed whole (libkin.atomic.staged_folder)
            write_text(stage / "summary.json", json.dumps(res, indent=1, default=jsonable) + "\n")
            studyreport.square(res, a, br, stage)
        say(progress, f"wrote {out / 'report.md'}")
    return res
