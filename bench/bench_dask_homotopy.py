"""Benchmark: the complete solver sharded over a Dask LocalCluster.

At a sail's flat state (default sail:8:2, s = 20, 2^20 = 1,048,576 paths)
the 2^s homotopy paths are tracked as tasks (libkin.homotopy.shards:
kin_quadrics_homotopy_range per shard, one kin_quadrics_homotopy_merge).

  python bench/bench_dask_homotopy.py scaling [--paths N] [--workers 1,2]
      tracks the first N paths (default 16384) in 8*workers shards on a
      LocalCluster of each size and prints the time and the speed-up;
  python bench/bench_dask_homotopy.py full [--workers 2]
      the complete solve, merged: time and the accounting of every path;
  python bench/bench_dask_homotopy.py inprocess [--workers 2]
      the same without Dask: kin_quadrics_homotopy_ex on that many threads in
      this process (no endpoint records to move between processes).
  add --sym to `full` and `inprocess`: with the sail's symmetry group
      (mechanism_group, found from C inside the timing): one path per orbit
      of start roots (kin_quadrics_homotopy_orbit_range shards and the merge
      on the equivariant form; in process kin_quadrics_homotopy_sym).

Run it on an idle machine (uptime is printed); one worker process per core,
one thread each.
"""
from __future__ import annotations

import argparse
import json
import os
import time

import numpy as np

import libkin
from libkin.homotopy import shards as hs


def flat_state_system(hub: int, loops: int) -> np.ndarray:
    a = libkin.Assembly.sail(hub, loops)
    a.analyse()
    return a.second_order()


def load() -> str:
    return " ".join(f"{x:.2f}" for x in os.getloadavg())


def cluster(workers: int):
    from dask.distributed import Client, LocalCluster
    lc = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0")
    return lc, Client(lc)


def scaling(Q: np.ndarray, paths: int, workers_list: list[int]) -> list[dict]:
    s = Q.shape[0]
    rows = []
    for w in workers_list:
        lc, client = cluster(w)
        try:
            shards = 8 * w
            cuts = [paths * k // shards for k in range(shards + 1)]
            items = [{"Q": Q.tolist(), "seed": 1, "threads": 1, "first": cuts[k], "count": cuts[k + 1] - cuts[k]}
                     for k in range(shards)]
            client.submit(hs.range_task, dict(items[0], count=1)).result()  # warm the workers
            t0 = time.perf_counter()
            futures = client.map(hs.range_task, items, pure=False)
            done = client.gather(futures)
            dt = time.perf_counter() - t0
            assert sum(p["count"] for p in done) == paths
            rows.append({"workers": w, "paths": paths, "s": s, "seconds": dt, "us_per_path": 1e6 * dt / paths,
                         "load": load()})
            print(f"workers {w}: {paths} paths of 2^{s} in {dt:.2f} s ({1e6 * dt / paths:.0f} us/path wall), "
                  f"load {load()}", flush=True)
        finally:
            client.close()
            lc.close()
    base = rows[0]["seconds"] * rows[0]["workers"]
    for r in rows:
        r["speedup"] = rows[0]["seconds"] / r["seconds"]
        r["efficiency"] = base / (r["seconds"] * r["workers"])
    return rows


def group_of(a: libkin.Assembly | None) -> np.ndarray | None:
    from libkin.symmetry import mechanism_group
    return None if a is None else mechanism_group(a, method="c")


def full(Q: np.ndarray, workers: int, sym: libkin.Assembly | None = None) -> dict:
    lc, client = cluster(workers)
    try:
        t0 = time.perf_counter()
        betas, acc = hs.solve_sharded(Q, executor=client, shards=64 * workers, group=group_of(sym))
        dt = time.perf_counter() - t0
    finally:
        client.close()
        lc.close()
    out = {"workers": workers, "seconds": dt, "accounting": acc, "real_solutions": int(betas.shape[0]),
           "symmetry": sym is not None, "load_after": load()}
    print(json.dumps(out, indent=1), flush=True)
    return out


def inprocess(Q: np.ndarray, threads: int, sym: libkin.Assembly | None = None) -> dict:
    t0 = time.perf_counter()
    betas, acc = libkin.solve_quadrics(Q, threads=threads, group=group_of(sym))
    dt = time.perf_counter() - t0
    out = {"threads": threads, "seconds": dt, "accounting": acc, "real_solutions_returned": int(betas.shape[0]),
           "symmetry": sym is not None, "load_after": load()}
    print(json.dumps(out, indent=1), flush=True)
    return out


def main() -> None:
    from libkin.version import blas_line
    print(blas_line(), flush=True)  # the kernel the figures below ran on
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("mode", choices=["scaling", "full", "inprocess"])
    p.add_argument("--hub", type=int, default=8)
    p.add_argument("--loops", type=int, default=2)
    p.add_argument("--paths", type=int, default=16384)
    p.add_argument("--workers", default="1,2")
    p.add_argument("--json", help="write the results here")
    p.add_argument("--sym", action="store_true", help="use the sail's symmetry group (full, inprocess)")
    args = p.parse_args()
    Q = flat_state_system(args.hub, args.loops)
    print(f"sail:{args.hub}:{args.loops} flat state: s = {Q.shape[0]}, m = {Q.shape[1]}, "
          f"{1 << Q.shape[0]} paths; load {load()}", flush=True)
    workers = [int(w) for w in args.workers.split(",")]
    sym = libkin.Assembly.sail(args.hub, args.loops) if args.sym else None
    if args.mode == "scaling":
        res = scaling(Q, args.paths, workers)
    elif args.mode == "full":
        res = full(Q, workers[-1], sym)
    else:
        res = inprocess(Q, workers[-1], sym)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(res, f, indent=1)


if __name__ == "__main__":
    main()
