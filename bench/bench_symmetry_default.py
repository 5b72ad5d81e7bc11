"""Benchmark: explore() with the structure's symmetries (the default) against
symmetry=False, and how long explore() runs past its time_limit.

  python bench/bench_symmetry_default.py atlas [--runs 2]
      sail:4:1 depth 1 and 2, sail:6:1 depth 1 (serial, samples 0): wall time
      with and without symmetry, alternating runs, the ratio, the branches
      followed and mapped, and the differences between the two atlases
      (orbits.differences, the start's branches that end differently, each a
      failure or near-miss in one of the two, left out as in
      python/tests/test_symmetry_default.py);
  python bench/bench_symmetry_default.py time-limit [--model sail:6:1] [--limit 2]
      explore(symmetry=False) with time_limit on each executor (serial,
      threads, process pool, Dask): the wall time, the overrun past the
      limit and the branches followed, beside the uninterrupted run.

Not a test: prints tables (ratios of alternating runs; the machine may be shared).
"""
from __future__ import annotations

import argparse
import concurrent.futures
import contextlib
import os
import sys
import time
from typing import Any, Iterator


import libkin
from libkin import parallel
from libkin.atlas.orbits import differences

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python", "tests"))
from test_symmetry_default import excluding, fragile_branches  # noqa: E402  (one comparison for both)


def load() -> str:
    return " ".join(f"{x:.1f}" for x in os.getloadavg())


def atlas(args: argparse.Namespace) -> None:
    print(f"load average at start: {load()}")
    print("| model | depth | nodes | edges | no symmetry [s] | symmetry [s] | ratio | followed / mapped | "
          "differences |")
    print("|---|---|---|---|---|---|---|---|---|")
    for spec, depth in (("sail:4:1", 1), ("sail:4:1", 2), ("sail:6:1", 1)):
        t = {True: [], False: []}
        res: dict = {}
        for _ in range(args.runs):
            for sym in (False, True):
                t0 = time.perf_counter()
                res[sym] = libkin.explore(spec, depth=depth, symmetry=sym, samples=0)
                t[sym].append(time.perf_counter() - t0)
        a, b = res[False], res[True]
        fragile = fragile_branches(a, b)
        diff = differences(a, b, exclude=excluding(fragile))
        kinds = sorted({f"{p}/{q}" for _, p, q in fragile})
        print(f"| {spec} | {depth} | {len(a.nodes)} / {len(b.nodes)} | {len(a.edges)} | "
              f"{min(t[False]):.2f} | {min(t[True]):.2f} | {min(t[False]) / min(t[True]):.2f} | "
              f"{b.stats['branches_followed']} / {b.stats['branches_mapped']} | "
              f"{len(diff)} (start's branches ending differently left out: {len(fragile)}, {kinds}) |", flush=True)
    print(f"load average at end: {load()}")


@contextlib.contextmanager
def _executor(kind: str) -> Iterator[Any]:
    if kind == "serial":
        yield None
    elif kind == "threads":
        with concurrent.futures.ThreadPoolExecutor(2) as ex:
            yield ex
    else:
        with parallel.executor("process" if kind == "process" else "dask", 2) as ex:
            yield ex


def time_limit(args: argparse.Namespace) -> None:
    print(f"load average at start: {load()}")
    t0 = time.perf_counter()
    full = libkin.explore(args.model, depth=1, symmetry=False, samples=0)
    whole = time.perf_counter() - t0
    print(f"uninterrupted, serial: {whole:.1f} s, {len(full.edges)} branches")
    print("| executor | time_limit [s] | returned after [s] | past the limit [s] | branches followed | partial |")
    print("|---|---|---|---|---|---|")
    for kind in ("serial", "threads", "process", "dask"):
        with _executor(kind) as ex:
            t0 = time.perf_counter()
            at = libkin.explore(args.model, depth=1, symmetry=False, samples=0, executor=ex, time_limit=args.limit)
            dt = time.perf_counter() - t0
        print(f"| {kind} | {args.limit:g} | {dt:.2f} | {dt - args.limit:.2f} | {len(at.edges)} of {len(full.edges)} | "
              f"{at.stats['partial']} |", flush=True)
    print(f"load average at end: {load()}")


def main(argv: list[str] | None = None) -> None:
    from libkin.version import blas_line
    print(blas_line(), flush=True)  # the kernel the figures below ran on
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = p.add_subparsers(dest="cmd", required=True)
    a = sub.add_parser("atlas")
    a.add_argument("--runs", type=int, default=2)
    t = sub.add_parser("time-limit")
    t.add_argument("--model", default="sail:6:1")
    t.add_argument("--limit", type=float, default=2.0)
    args = p.parse_args(argv)
    (atlas if args.cmd == "atlas" else time_limit)(args)


if __name__ == "__main__":
    sys.exit(main())
