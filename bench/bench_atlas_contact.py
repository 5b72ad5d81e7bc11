"""Which branches out of a sail's flat state are free of contact (issue 23 item 5).

The sail's panels are its bar triangles (graph_triangles), every bar of radius
t/2 and every panel of thickness t (t in hub sides: the built-in sails have
hub side 1); libkin.explore(contact=True) follows every directed branch out
of the flat state (one per orbit of the stabilizer, the others their images:
follow_orbits=True) and stops each at its first contact. A branch whose event
is not 'contact' reaches its next event free of contact.

  python bench/bench_atlas_contact.py [--model 6:2] [--thickness 0.0] [--workers 2] [--out summary.json]

Not a test: prints one JSON line (counts by event, wall time, load average).
"""
from __future__ import annotations

import argparse
import concurrent.futures
import json
import os
import time

import libkin
from libkin.io.fold.writer import graph_triangles


def main() -> None:
    from libkin.version import blas_line
    print(blas_line(), flush=True)  # the kernel the figures below ran on
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--model", default="6:2", help="sail n_sides:n_loops (default 6:2)")
    p.add_argument("--thickness", type=float, default=0.0, help="t / hub side (default 0)")
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--out", default=None)
    args = p.parse_args()
    n, k = map(int, args.model.split(":"))
    a = libkin.Assembly.sail(n, k)
    a.panels = graph_triangles(a.bars)
    a.thickness = args.thickness
    load0, t0 = os.getloadavg()[0], time.time()
    with concurrent.futures.ProcessPoolExecutor(args.workers) as ex:
        at = libkin.explore(a, depth=1, symmetric=False, samples=0, executor=ex, follow_orbits=True, contact=True)
    s = at.summary()
    ev = s["edge_events"]
    res = {"model": f"sail:{n}:{k}", "thickness": args.thickness, "panels": a.npanels, "edges": s["edges"],
           "edge_events": ev, "contact_free": s["edges"] - ev.get("contact", 0),
           "wall_s": round(time.time() - t0, 1), "load_start": load0, "load_end": os.getloadavg()[0]}
    print(json.dumps(res))
    if args.out:
        with open(args.out, "w") as f:
            json.dump(res, f, indent=1)


if __name__ == "__main__":
    main()
