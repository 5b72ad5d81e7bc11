"""Proofs of the exactly singular points near the hexagonal sail's located
bifurcations (issue 38 item 2; docs/locate.md "The exactly singular point
near it"): explore a path map, then kin_prove_singular at every node.

usage: python bench/bench_sing_proof.py OUT.json [DEPTH] [sym|full] [TIME_LIMIT_S] [MODEL]
(docs: 1 full 100). Prints the counts and percentiles and writes them, with
the proven nodes, to OUT.json (bench/sing_proof_sail.json); timings are the
best of five calls (one BLAS thread: set OPENBLAS_NUM_THREADS=1)."""
import collections
import json
import sys
import time

import numpy as np

import libkin


def main():
    out = sys.argv[1]
    depth = int(sys.argv[2]) if len(sys.argv) > 2 else 1
    sym = (sys.argv[3] if len(sys.argv) > 3 else "full") == "sym"
    limit = float(sys.argv[4]) if len(sys.argv) > 4 else 100.0
    model = sys.argv[5] if len(sys.argv) > 5 else "sail:6:2"
    t0 = time.time()
    atlas = libkin.explore(model, depth=depth, symmetric=sym, time_limit=limit)
    print(f"explore: {len(atlas.nodes)} nodes in {time.time() - t0:.1f} s", flush=True)
    a = libkin.load_model(atlas.model)
    rows = []
    for n in atlas.nodes:
        a.coords = n.coords
        a.analyse()
        best = np.inf
        for _ in range(5):
            t = time.perf_counter()
            p = a.prove_singular()
            best = min(best, time.perf_counter() - t)
        rows.append(dict(id=n.id, kind=n.kind, m=n.m, s=n.s, located=n.located_v_r, proven=p.proven,
                         corank=p.corank, distance=p.distance, dlength=p.dlength, unique=p.unique, seconds=best))
    counts = collections.Counter(f"{r['kind']} m={r['m']} s={r['s']} {'proven' if r['proven'] else 'not proven'}"
                                 for r in rows)
    pr = [r for r in rows if r["proven"]]
    pct = {k: {str(q): float(f"{np.percentile([r[k] for r in pr] or [np.nan], q):.3g}") for q in (0, 50, 90, 99, 100)}
           for k in ("distance", "dlength", "unique", "seconds")}
    head = {"nodes": len(rows), "counts": dict(counts), "percentiles_of_proven": pct,
            "proven_columns": ["id", "located v_r/v_max", "distance", "dlength", "seconds"]}
    with open(out, "w") as f:  # the proven nodes one a line, 4 digits
        f.write(json.dumps(head, indent=1)[:-2] + ',\n "proven": [\n'
                + ",\n".join(json.dumps([r["id"]] + [float(f"{r[k]:.4g}") for k in
                                                      ("located", "distance", "dlength", "seconds")]) for r in pr)
                + "\n ]\n}\n")
    print(dict(counts))
    for key, v in pct.items():
        print(key, v)


if __name__ == "__main__":
    main()
