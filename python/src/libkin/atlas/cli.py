"""`libkin explore`: the command line of libkin.explore (cli.py registers it)."""
from __future__ import annotations

import argparse
import contextlib
import pathlib
from typing import TYPE_CHECKING, Any, Iterator

if TYPE_CHECKING:
    from .assembly import Assembly


def add_arguments(s: argparse.ArgumentParser) -> None:
    from .cli import _count, _positive  # the command line's checked types
    s.add_argument("model")
    s.add_argument("--depth", type=_count(0), default=1, help="levels of bifurcations to expand (default 1)")
    s.add_argument("--max-nodes", type=_count(1), default=200,
                   help="no node is expanded beyond this many (default 200)")
    s.add_argument("--max-length", type=_positive, default=None,
                   help="path-length budget of one branch (default 10 x the model size)")
    s.add_argument("--time-limit", type=_positive, default=None,
                   help="seconds; no node is expanded and no branch started after it")
    s.add_argument("--symmetric", nargs="?", const="true", default="false", choices=["true", "false", "auto"],
                   help="only the paths that keep each node's symmetry (auto: where s > 12)")
    s.add_argument("--follow-orbits", action="store_true",
                   help="follow one branch per orbit of each node's symmetries, map the others (faster)")
    s.add_argument("--executor", default="serial", choices=["serial", "process", "dask"],
                   help="where branches are followed: this process, a process pool, a local Dask cluster")
    s.add_argument("--workers", type=_count(1), default=2, help="workers of --executor process|dask (default 2)")
    s.add_argument("--out", required=True, help="output folder: atlas.json, atlas.graphml, report.md, PNGs")
    s.add_argument("--quiet", action="store_true", help="no progress messages")


@contextlib.contextmanager
def executor(kind: str, workers: int) -> Iterator[Any]:
    """The executor named on the command line (None for serial)."""
    if kind == "serial":
        yield None
    elif kind == "process":
        from concurrent.futures import ProcessPoolExecutor
        with ProcessPoolExecutor(max_workers=workers) as ex:
            yield ex
    else:
        try:
            from distributed import Client, LocalCluster
        except ImportError:
            raise ImportError("--executor dask needs dask[distributed] (pip install 'libkin[dask]')") from None
        with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                          dashboard_address=None) as cluster, Client(cluster) as client:
            yield client


def run(args: argparse.Namespace, assembly: Assembly) -> int:
    from . import atlas_report
    from .atlas import explore
    sym: bool | str = {"true": True, "false": False}.get(args.symmetric, "auto")
    with executor(args.executor, args.workers) as ex:
        at = explore(assembly, depth=args.depth, max_nodes=args.max_nodes, max_length=args.max_length,
                     time_limit=args.time_limit, symmetric=sym, executor=ex,
                     progress=None if args.quiet else True, follow_orbits=args.follow_orbits)
    rep = atlas_report.write(at, args.out)
    s = at.summary()
    kinds = ", ".join(f"{v} {k}" for k, v in sorted(s["edge_events"].items())) or "none"
    print(f"{s['nodes']} nodes, {s['edges']} directed paths ({kinds}); wrote {pathlib.Path(args.out) / 'atlas.json'}, "
          f"atlas.graphml, atlas_map.png, {rep}")
    return 0
