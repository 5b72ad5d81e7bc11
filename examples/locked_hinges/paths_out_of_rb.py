"""Every directed path out of R^B (the first bifurcation of a sail member's
radially sequential fold, loop 1 wrapped) followed with contact events, the
hinges' fold sides tracked along leg 1 into R^B (issue 37 items 2 and 3):
how many carry a hinge through flat-folded at R^B, and where the others go.

    LIBKIN_LIBRARY=build/libkin.so PYTHONPATH=python/src \\
        python examples/locked_hinges/paths_out_of_rb.py 6:1,6:2,8:1,8:2
"""
import json
import sys
import time

import numpy as np

from libkin.studies.sailmeasure import part_name, sail_panels
from libkin.studies.sequential import sequential_fold


def extent(x):
    return float(np.hypot(x[:, 0], x[:, 1]).max())


def main(members):
    for m in members.split(","):
        n, loops = map(int, m.split(":"))
        t0 = time.time()
        res = sequential_fold(n, loops, max_legs=2, keep_states=True)
        S = res["samples"]
        ks = sorted(S.leave_dir)
        rb = S.states[ks[1]] if len(ks) > 1 else S.states[-1]
        a = res["assembly"].clone()
        panels = sail_panels(a)
        a.panels = panels
        a.set_contact_events(True, 1e-9)
        leg1 = a.follow_event(S.leave_dir[0], max_steps=800)   # tracks the sides into R^B
        br = rb.branches(solver="homotopy", length=0.5)
        out = {"through_at_RB": 0, "free": [], "other": []}
        for p in br.paths:
            if not (p.exists and p.tangent_ok):
                continue
            b = a.clone()
            b.coords = rb.coords
            f = b.follow_event(br.directions[p.beta] * p.sign, max_steps=800)
            if f.event == "contact":
                c = b.last_contact()
                if [k for k, _ in c.parts] == ["panel", "panel"] and f.length < 1e-3:
                    out["through_at_RB"] += 1
                    continue
                out["other"].append([f.event, round(f.length, 3), [part_name(b, panels, kd, i) for kd, i in c.parts]])
            else:
                out["free"].append([f.event, round(f.length, 3), round(extent(b.coords), 3)])
        print(json.dumps({"member": m, "leg1": [leg1.event, round(leg1.length, 5)],
                          "RB_extent": round(extent(rb.coords), 3), "flat_extent": round(extent(res["assembly"].coords), 3),
                          **out, "seconds": round(time.time() - t0, 1)}), flush=True)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "6:1,6:2,8:1,8:2")
