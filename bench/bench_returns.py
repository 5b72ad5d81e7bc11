"""Benchmark: what a branch task pays for its start's branch lines (returns decided in one follow).

A return to the start is a closed loop only if its direction is nearest the
branch's own line among ALL the start's lines (docs/follow.md "Branch
directions"). At the hexagonal flat state (sail:6:2) there are 29,828 lines
x 46 numbers. This follows the same random branches (tasks.follow_branch,
the explorer's task) with

  own    only the branch's own line (the old first pass: a return ends as a loop),
  array  all lines as an array (kin_follow_event_ex checks them all, finds
         the own line and the nearest at each return, in every call),
  shared all lines as a libkin.shared reference: checked once per process,
         the own line's index given, the nearest found by BranchLines at
         each return (kin_follow_options.return_fn),

alternating the modes task by task, and prints the CPU per task of each,
and whether array and shared give the same result on every task.

  python bench/bench_returns.py --store S [--tasks 200] [--seed 1]

S: a store of `bench_atlas_flat.py run --store S` (its complete solve of the
flat state gives the lines). Not a test: prints a table.
"""
from __future__ import annotations

import argparse
import json
import sqlite3
import time

import numpy as np

import libkin
from libkin.atlas import tasks
from libkin.io.model_json import to_json
from libkin.shared import Sharing


def main() -> None:
    from libkin.version import blas_line
    print(blas_line(), flush=True)  # the kernel the figures below ran on
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--store", required=True)
    p.add_argument("--model", default="sail:6:2")
    p.add_argument("--tasks", type=int, default=200)
    p.add_argument("--seed", type=int, default=1)
    args = p.parse_args()
    db = sqlite3.connect(f"file:{args.store}?mode=ro", uri=True)
    betas = np.array(json.loads(db.execute("SELECT value FROM results WHERE kind = 'solve'").fetchone()[0])["betas"])
    from libkin.cliargs import load_model_spec
    a = load_model_spec(args.model)
    an = a.analyse()
    U = an.internal_mechanisms
    lines = betas @ U.T  # sign +1, in solution order (directions.node_lines)
    print(f"{args.model}: m = {an.m_internal}, s = {an.s}, {lines.shape[0]} lines x {lines.shape[1]}")
    scale = max(1.0, float(np.abs(a.coords - a.coords.mean(axis=0)).max()))
    base = {"model": json.dumps(to_json(a)), "coords": a.coords.tolist(), "rank_tol": 1e-9,
            "max_length": 10.0 * scale, "max_steps": 2000, "samples": 0, "contact": False}
    rng = np.random.default_rng(args.seed)
    picks = rng.choice(lines.shape[0], size=args.tasks, replace=False)
    signs = rng.choice([-1, 1], size=args.tasks)
    cpu = {"own": [], "array": [], "shared": []}
    same, events, differ = 0, {}, []
    with Sharing(None) as sh:
        ref = sh.share(lines)
        t0 = time.process_time()
        tasks.follow_branch({**base, "direction": lines[0].tolist(), "branches": ref, "own": 0, "max_steps": 1})
        first = time.process_time() - t0
        from libkin.assembly import BranchLines
        from libkin.shared import resolve
        held = resolve(ref, BranchLines)  # the worker's checked lines: count and time the calls at returns
        calls = [0, 0.0]
        nearest = held.nearest

        def counted(t):
            c0 = time.process_time()
            out = nearest(t)
            calls[0] += 1
            calls[1] += time.process_time() - c0
            return out
        held.nearest = counted
        kind = []
        for k, (i, sg) in enumerate(zip(picks, signs)):
            d = (sg * lines[i]).tolist()
            res = {}
            order = ["own", "array", "shared"][k % 3:] + ["own", "array", "shared"][:k % 3]
            for mode in order:
                br = {"own": {"branches": [d]}, "array": {"branches": lines},
                      "shared": {"branches": ref, "own": int(i)}}[mode]
                r = tasks.follow_branch({**base, "direction": d, **br})
                cpu[mode].append(r["cpu_seconds"])
                res[mode] = r
            x, y = res["array"], res["shared"]
            ok = x["event"] == y["event"] and np.allclose(x["coords"], y["coords"], atol=0, rtol=0)
            same += ok
            if not ok:
                differ.append((int(i), int(sg), x["event"], y["event"]))
            events[(res["own"]["event"], y["event"])] = events.get((res["own"]["event"], y["event"]), 0) + 1
            kind.append(f'{res["own"]["event"]} -> {y["event"]}')
    print(f"first shared task (lines checked, unit rows made): {1e3 * first:.1f} ms")
    print("| mode | mean CPU ms / task | median | vs own |")
    print("| --- | --- | --- | --- |")
    m0 = np.mean(cpu["own"])
    for mode, v in cpu.items():
        print(f"| {mode} | {1e3 * np.mean(v):.2f} | {1e3 * np.median(v):.2f} | {np.mean(v) / m0:.3f} |")
    print(f"return_fn calls: {calls[0]} ({calls[0] / args.tasks:.2f} a task), "
          f"{1e3 * calls[1] / max(calls[0], 1):.2f} ms CPU each, {1e3 * calls[1] / args.tasks:.3f} ms a task")
    print("| own only -> all lines | tasks | own | array | shared (mean CPU ms) |")
    print("| --- | --- | --- | --- | --- |")
    for k in sorted(set(kind)):
        sel = [i for i, x in enumerate(kind) if x == k]
        print(f"| {k} | {len(sel)} | " + " | ".join(f"{1e3 * np.mean([cpu[m][i] for i in sel]):.2f}"
                                                     for m in ("own", "array", "shared")) + " |")
    print(f"array and shared: the same event and end point on {same} of {args.tasks} tasks {differ[:5]}")
    print("events (own only -> all lines):", {f"{a} -> {b}": n for (a, b), n in sorted(events.items())})


if __name__ == "__main__":
    main()
