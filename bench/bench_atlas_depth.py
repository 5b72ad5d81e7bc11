"""Benchmark: the hexagonal sail's atlas past depth one, on a Dask LocalCluster.

  python bench/bench_atlas_depth.py run [--model sail:6:2] --depth 2 [--workers 2] --out DIR
         [--time-limit S] [--resume] [--summary bench/atlas_depth_summary.json]
      libkin.explore(MODEL, depth=D, samples=0, executor=Client(LocalCluster(W)),
      store=DIR/explore.sqlite) with the defaults otherwise (symmetry: the
      stabiliser's group in the solve, one branch per orbit followed where its
      image is certain); writes DIR/atlas.json (large: not for the repository)
      and DIR/summary.json (small: the per-level rows of stats["levels"], the
      per-depth table, the stats), copied to --summary if given. The store
      keeps every solve and branch as it completes: a run stopped by
      --time-limit, a signal or a kill is completed by the same command with
      --resume, and a deeper run (--depth D+1 --resume) reuses a shallower
      one's store (its first D levels are read back, not recomputed);
  python bench/bench_atlas_depth.py scaling --atlas DIR/atlas.json --nodes K [--workers 1,2,1,2]
      the speed-up of the parallel part: every directed branch out of the
      first K depth-1 bifurcation orbits of a finished atlas (K orbit
      representatives located to the strict tolerance, in id order),
      enumerated once in this process (the node's analysis and complete
      solve, as the explorer does at level 2) and then followed as one batch
      of tasks, as the explorer ships a level (through a run store: streamed
      on Dask, each result recorded as it completes), on
      a fresh LocalCluster of each size, alternating; prints wall, speed-up
      and efficiency, and with --summary adds them to the summary;
  python bench/bench_atlas_depth.py table SUMMARY_OR_DIR [--project 8,64]
      the per-depth table, the ratios against depth 1 of the flat-state
      benchmark (bench/atlas_flat_symmetry_summary_lu_follower.json) and the
      projection to N workers.

Not a test: prints tables. The load average is printed at the start and the
end: the machine is shared, so compare the CPU of the followers as well as
the wall time.
"""
from __future__ import annotations

import argparse
import collections
import json
import os
import shutil
import sys
import tempfile
import time
from typing import Any, Dict, List, Optional

import numpy as np

import libkin
from bench_atlas_flat import load, progress_printer

HERE = os.path.dirname(os.path.abspath(__file__))
DEPTH1 = os.path.join(HERE, "atlas_flat_symmetry_summary_lu_follower.json")


def cluster(workers: int) -> Any:
    from dask.distributed import Client, LocalCluster
    lc = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0")
    client = Client(lc)
    client.run(lambda: 0)  # the workers are up
    return lc, client


def run(args: argparse.Namespace) -> None:
    from libkin.atlas import levels
    os.makedirs(args.out, exist_ok=True)
    store = args.store or os.path.join(args.out, "explore.sqlite")
    print(f"load average at start: {load()}  ({os.cpu_count()} CPUs); store {store}"
          f"{' (resumed)' if args.resume else ''}", flush=True)
    t0 = time.perf_counter()
    progress = progress_printer(t0)
    lc, client = cluster(args.workers)
    try:
        atlas = libkin.explore(args.model, depth=args.depth, samples=0, executor=client, threads=1,
                               max_nodes=args.max_nodes, store=store, resume=args.resume,
                               time_limit=args.time_limit, progress=progress)
    finally:
        client.close()
        lc.close()
    wall = time.perf_counter() - t0
    d = atlas.to_dict()
    d["settings"]["model_name"] = args.model
    with open(os.path.join(args.out, "atlas.json"), "w") as f:
        json.dump(d, f)
    stats = dict(d["stats"])
    s = {"model": args.model, "depth": args.depth, "workers": args.workers, "wall_seconds": round(wall, 1),
         "resumed": bool(args.resume), "load_end": load(), "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
         "levels": stats.pop("levels", []), "by_depth": levels.by_depth(d),
         "symmetries": len(d["symmetries"]), "stats": stats}
    old = os.path.join(args.out, "summary.json")
    if os.path.exists(old):  # keep what the scaling subcommand added, and earlier runs' rows
        with open(old) as f:
            prev = json.load(f)
        s["scaling"], s["scaling_runs"] = prev.get("scaling"), prev.get("scaling_runs", [])
        s["runs"] = prev.get("runs", []) + [{k: prev.get(k) for k in ("depth", "wall_seconds", "resumed", "date")}]
    write_summary(s, os.path.join(args.out, "summary.json"), args.summary)
    table_of(s)


def write_summary(s: Dict[str, Any], path: str, copy: Optional[str]) -> None:
    with open(path, "w") as f:
        json.dump(s, f, indent=1)
    if copy:
        shutil.copyfile(path, copy)
        print(f"wrote {copy}")


def _representatives(d: Dict[str, Any], k: int) -> List[Dict[str, Any]]:
    out = [n for n in d["nodes"] if n["depth"] == 1 and n["kind"] == "bifurcation" and n["orbit"] == n["id"]
           and n["located_tol"] <= 1e-10]
    return out[:k]


def _cpu() -> float:
    """CPU seconds of this process (run in each Dask worker)."""
    import resource
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def scaling(args: argparse.Namespace) -> None:
    from libkin.atlas import directions, explorer, tasks
    from libkin.atlas.model import Node
    from libkin.atlas.store import Store
    from libkin.parallel import run_tasks
    from libkin.atlas import store as atlas_store
    if args.chunk is not None:
        atlas_store.DASK_CHUNK = args.chunk
    with open(args.atlas) as f:
        d = json.load(f)
    a = libkin.Assembly.from_json(json.dumps(d["model"])) if hasattr(libkin.Assembly, "from_json") else None
    if a is None:
        from libkin.io.model_json import load_json
        a = load_json(json.dumps(d["model"]))
    ex = explorer._Explorer(a, False, None, None, float(d["settings"]["max_length"]), 1, 1, None,
                            int(d["settings"]["max_steps"]), 0, None, True, False)
    t = time.perf_counter()
    work = []
    for n in _representatives(d, args.nodes):
        node = Node(n["id"], n["kind"], np.asarray(n["coords"]), n["m"], n["m_rigid"], n["s"], n["v_r_rel"],
                    n["depth"], n["located_v_r"], n["located_tol"])
        ex.nodes.append(node)
        br, _ = ex.branches(node)
        work += [(len(ex.nodes) - 1, i, sg, b, dd) for i, sg, b, dd in br]
    enum = time.perf_counter() - t
    lines, _ = directions.node_lines(work)  # each node's branch lines go whole with its tasks (few at depth 1)
    items = [{"model": ex.text, "coords": ex.nodes[nid].coords.tolist(), "rank_tol": ex._rank_tol(ex.nodes[nid]),
              "direction": dd.tolist(), "max_length": ex.max_length, "max_steps": ex.max_steps, "samples": 0,
              "branches": np.array(lines[nid], dtype=float) if nid in lines else None, "contact": False} for nid, _, _, _, dd in work]
    print(f"load average at start: {load()}; {args.nodes} depth-1 orbits, {len(items)} directed branches "
          f"(enumerated here in {enum:.1f} s)", flush=True)
    rows = []
    for w in [int(x) for x in args.workers.split(",")]:
        lc, client = cluster(w)
        try:
            run_tasks(tasks.follow_branch, items[:2 * w], client)  # warm: imports in each worker
            with tempfile.TemporaryDirectory() as tmp, Store(os.path.join(tmp, "s.sqlite"), "scaling") as st:
                w0 = sum(client.run(_cpu).values())
                t, c0 = time.perf_counter(), time.process_time()  # as explore() ships a level: streamed
                res = st.run_tasks(tasks.follow_branch, items, client, None, "branches", None)
                wall, client_cpu = time.perf_counter() - t, time.process_time() - c0
                worker_cpu = sum(client.run(_cpu).values()) - w0
        finally:
            client.close()
            lc.close()
        cpu = sum(float(r.get("cpu_seconds", 0.0)) for r in res)
        ev = collections.Counter(r["event"] for r in res)
        rows.append({"workers": w, "branches": len(items), "wall_seconds": round(wall, 2),
                     "follower_cpu_seconds": round(cpu, 2), "worker_cpu_seconds": round(worker_cpu, 2),
                     "client_cpu_seconds": round(client_cpu, 2), "events": dict(ev), "load": load()})
        print(f"  {w} worker(s): {wall:.1f} s wall; CPU: followers {cpu:.1f} s, worker processes {worker_cpu:.1f} s, "
              f"client {client_cpu:.1f} s; {dict(ev)}; load {load()}", flush=True)
    one = [r["wall_seconds"] for r in rows if r["workers"] == 1]
    two = [r["wall_seconds"] for r in rows if r["workers"] == 2]
    out = {"nodes": args.nodes, "branches": len(items), "enumerate_seconds": round(enum, 2),
           "chunk": atlas_store.DASK_CHUNK, "rows": rows}
    n = len(items)
    out["per_branch_ms"] = {k: round(1e3 * min(r[k] for r in rows) / n, 2) for k in
                            ("follower_cpu_seconds", "worker_cpu_seconds", "client_cpu_seconds")}
    print("per branch (least over the runs): " + ", ".join(f"{k} {v} ms" for k, v in out["per_branch_ms"].items()))
    if one and two:
        out["speedup_1_to_2"] = round(min(one) / min(two), 3)
        out["efficiency_2"] = round(out["speedup_1_to_2"] / 2, 3)
        out["follow_seconds_per_branch_1_worker"] = round(min(one) / len(items), 4)
        print(f"speed-up 1 -> 2 workers (best of each): {out['speedup_1_to_2']:.2f}, "
              f"efficiency {out['efficiency_2']:.2f}")
    if args.summary:
        with open(args.summary) as f:
            s = json.load(f)
        s.setdefault("scaling_runs", []).append(out)
        s["scaling"] = out
        write_summary(s, args.summary, None)
        print(f"added to {args.summary}")


def table_of(s: Dict[str, Any], project: Optional[List[int]] = None) -> None:
    with open(DEPTH1) as f:
        d1 = json.load(f)
    rows = {r["depth"]: r for r in s.get("levels", [])}
    runs = s.get("runs") if isinstance(s.get("runs"), list) and len(s.get("runs") or []) > 1 else None
    print(f"\n{s['model']}, depth {s['depth']}, {s['workers']} Dask workers; wall {s['wall_seconds']} s "
          f"({f'{len(runs)} runs' if runs else 'this run'}{', resumed' if s.get('resumed') else ''}); "
          f"stopped by {s['stats'].get('stopped_by')}")
    print("| depth | nodes expanded | directed branches | followed / mapped | bifurcation | near miss | loop | "
          "budget | failure | new nodes | new orbits (bifurcation) | enumerate / follow / merge s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in s["by_depth"]:
        lv = rows.get(r["depth"], {})
        ev = r["events"]
        print(f"| {r['depth']} | {r['sources_expanded']:,} | {r['directed_branches']:,} | "
              f"{lv.get('followed', 0):,} / {lv.get('mapped', 0):,} | {ev.get('bifurcation', 0):,} | "
              f"{ev.get('near_miss', 0):,} | {ev.get('loop', 0):,} | {ev.get('budget', 0):,} | "
              f"{ev.get('failure', 0):,} | {r['new_nodes']:,} | {r['new_orbits']:,} ({r['new_bifurcation_orbits']:,}) | "
              f"{lv.get('enumerate_seconds', 0):.0f} / {lv.get('follow_seconds', 0):.0f} / "
              f"{lv.get('merge_seconds', 0):.0f} |")
    ref = {"directed_branches": d1["directed_branches"], "new_nodes": d1["distinct_end_nodes"],
           "new_orbits": d1["orbits"], "new_bifurcation_orbits": d1["orbits_by_kind"].get("bifurcation", 0)}
    print(f"\nagainst depth 1 of {os.path.basename(DEPTH1)} ({ref['directed_branches']:,} branches, "
          f"{ref['new_nodes']:,} nodes, {ref['new_orbits']:,} orbits, {ref['new_bifurcation_orbits']:,} "
          "bifurcation orbits):")
    for r in s["by_depth"]:
        print(f"  depth {r['depth']}: " + ", ".join(f"{k} {r[k] / ref[k]:.3f}x" for k in ref if ref[k]))
    sc = s.get("scaling")
    if sc and "efficiency_2" in sc:
        print(f"\nscaling slice: {sc['branches']:,} branches of {sc['nodes']} depth-1 orbits, {sc.get('chunk', 1)} a "
              "Dask task: " + ", ".join(f"{r['workers']} w {r['wall_seconds']} s" for r in sc["rows"])
              + f"; speed-up {sc['speedup_1_to_2']}, efficiency {sc['efficiency_2']}")
        project_levels(s, sc, project or [2, 8, 64])


def project_levels(s: Dict[str, Any], sc: Dict[str, Any], workers: List[int]) -> None:
    """The model: per level, the serial part measured in the run (enumerate
    + merge, in the client) plus the following: the workers' CPU per branch
    (scaling slice) over N x the measured efficiency, but never less than
    the client's own CPU per branch (it submits, receives and records every
    branch: the serial floor of the following)."""
    e = sc["efficiency_2"]
    w, c = sc["per_branch_ms"]["worker_cpu_seconds"] / 1e3, sc["per_branch_ms"]["client_cpu_seconds"] / 1e3
    print(f"projection: per level enumerate + merge (measured) + max(followed x {c * 1e3:.2f} ms (client), "
          f"followed x {w * 1e3:.1f} ms / (N x {e}))")
    total = {n: 0.0 for n in workers}
    for lv in s.get("levels", []):
        serial = lv.get("enumerate_seconds", 0) + lv.get("merge_seconds", 0)
        f = lv.get("followed", 0)
        est = {n: serial + max(f * c, f * w / (n * e)) for n in workers}
        for n in workers:
            total[n] += est[n]
        print(f"  depth {lv['depth']}: serial {serial:.0f} s, {f:,} followed: "
              + ", ".join(f"{n} workers {est[n]:.0f} s" for n in workers))
    print("  all levels: " + ", ".join(f"{n} workers {total[n]:.0f} s ({total[n] / 60:.1f} min)" for n in workers))


def table(args: argparse.Namespace) -> None:
    path = args.path if args.path.endswith(".json") else os.path.join(args.path, "summary.json")
    with open(path) as f:
        s = json.load(f)
    table_of(s, [int(x) for x in args.project.split(",")])


def main(argv: Optional[List[str]] = None) -> None:
    from libkin.version import blas_line
    print(blas_line(), flush=True)  # the kernel the figures below ran on
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = p.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run")
    r.add_argument("--model", default="sail:6:2")
    r.add_argument("--depth", type=int, default=2)
    r.add_argument("--workers", type=int, default=2)
    r.add_argument("--out", required=True)
    r.add_argument("--store", default=None)
    r.add_argument("--resume", action="store_true")
    r.add_argument("--time-limit", type=float, default=None)
    r.add_argument("--max-nodes", type=int, default=10 ** 7)
    r.add_argument("--summary", default=None, help="copy DIR/summary.json here (bench/atlas_depth_summary.json)")
    c = sub.add_parser("scaling")
    c.add_argument("--atlas", required=True)
    c.add_argument("--nodes", type=int, default=60)
    c.add_argument("--workers", default="1,2")
    c.add_argument("--summary", default=None)
    c.add_argument("--chunk", type=int, default=None,
                   help="branches per Dask task (atlas.store.DASK_CHUNK, default 16; 1: one task a branch)")
    t = sub.add_parser("table")
    t.add_argument("path")
    t.add_argument("--project", default="2,8,64")
    args = p.parse_args(argv)
    {"run": run, "scaling": scaling, "table": table}[args.cmd](args)


if __name__ == "__main__":
    main()
