"""`libkin explore`: the command line of libkin.explore (register() adds it
to the dispatcher, libkin.cli)."""
from __future__ import annotations

import argparse
import contextlib
import pathlib
import signal
import sys
import threading
from typing import TYPE_CHECKING, Any, Iterator, List

from ..atomic import folder_lock
from ..cliargs import count, load_model_spec, positive, require_extras
from ..parallel import executor
from .limits import MAX_NODES

if TYPE_CHECKING:
    from ..assembly import Assembly

__all__ = ["register", "add_arguments", "run", "executor"]


def register(sub: Any) -> None:
    """Add the `explore` subcommand to the dispatcher's subparsers."""
    s = sub.add_parser("explore", help="the atlas: every path out of every bifurcation met (docs/atlas.md)")
    add_arguments(s)
    s.set_defaults(fn=cmd_explore)


def cmd_explore(args: argparse.Namespace) -> int:
    return run(args, load_model_spec(args.model))


def add_arguments(s: argparse.ArgumentParser) -> None:
    s.add_argument("model")
    s.add_argument("--depth", type=count(0), default=1, help="levels of bifurcations to expand (default 1)")
    s.add_argument("--max-nodes", type=count(1), default=MAX_NODES,
                   help=f"no node is expanded once the atlas has this many (default {MAX_NODES:,}: the depth "
                        "bounds the run)")
    s.add_argument("--max-length", type=positive, default=None,
                   help="path-length budget of one branch (default 10 x the model size)")
    s.add_argument("--time-limit", type=positive, default=None,
                   help="seconds; then nothing more is started, the atlas so far is written (partial) and "
                        "--resume continues it")
    s.add_argument("--symmetric", nargs="?", const="true", default="false", choices=["true", "false", "auto"],
                   help="only the paths that keep each node's symmetry (auto: where s > 12)")
    s.add_argument("--no-symmetry", action="store_true",
                   help="do not use the structure's symmetries to save work (by default the complete solve at "
                        "a node uses its stabiliser and one branch per orbit is followed where the mapped end "
                        "is certain); every branch followed, the plain solver")
    s.add_argument("--follow-orbits", action="store_true",
                   help="follow one branch per orbit of each node's symmetries, map the others (the default "
                        "unless --no-symmetry)")
    s.add_argument("--samples", type=count(0), default=2,
                   help="configurations stored along each path: this many, evenly spread, and with --html "
                        "more where the viewer's animation through them would stretch a bar by over 1 %% "
                        "(default 2; 0: none, the viewer then draws a straight move between the ends)")
    s.add_argument("--contact", action="store_true",
                   help="stop each branch at the first contact of two parts (the model's panels and thickness)")
    s.add_argument("--executor", default="serial", choices=["serial", "process", "dask"],
                   help="where branches are followed: this process, a process pool, a local Dask cluster")
    s.add_argument("--workers", type=count(1), default=2, help="workers of --executor process|dask (default 2)")
    s.add_argument("--out", required=True, help="output folder: atlas.json, atlas.graphml, report.md, PNGs")
    s.add_argument("--store", default=None,
                   help="the run's store (SQLite): each solved node and followed branch recorded as it "
                        "completes (default: .OUT.explore.sqlite next to --out)")
    s.add_argument("--resume", action="store_true",
                   help="continue the interrupted run recorded in the store (same model and options)")
    s.add_argument("--html", action="store_true",
                   help="also write atlas.html: the atlas to walk in a browser, offline (needs plotly)")
    s.add_argument("--quiet", action="store_true",
                   help="no progress messages (the lines saying which limit stopped the run are still printed)")


def needed_modules(args: argparse.Namespace) -> List[str]:
    """The optional modules this run will need: its files (report.OUTPUT_MODULES),
    plotly for --html, distributed for --executor dask."""
    from .report import OUTPUT_MODULES
    return (list(OUTPUT_MODULES) + (["plotly"] if args.html else [])
            + (["distributed"] if args.executor == "dask" else []))


def run(args: argparse.Namespace, assembly: Assembly) -> int:
    # every missing extra named at once, before any work or any file (ImportError)
    require_extras("libkin explore", needed_modules(args))
    # one run per --out at a time: a second fails at once (FolderInUseError)
    with folder_lock(args.out):
        return _run(args, assembly)


def _run(args: argparse.Namespace, assembly: Assembly) -> int:
    from . import report as atlas_report
    from .explorer import explore
    from .store import default_path, remove_store
    sym: bool | str = {"true": True, "false": False}.get(args.symmetric, "auto")
    store = args.store or default_path(args.out)
    with executor(args.executor, args.workers) as ex, _stop_on_signals() as signalled:
        at = explore(assembly, depth=args.depth, max_nodes=args.max_nodes, max_length=args.max_length,
                     time_limit=args.time_limit, symmetric=sym, executor=ex,
                     progress=None if args.quiet else True, follow_orbits=True if args.follow_orbits else None,
                     store=store, resume=args.resume, stop=lambda: bool(signalled), symmetry=not args.no_symmetry,
                     contact=args.contact, samples=args.samples, view_samples=bool(args.html))
    rep = atlas_report.write(at, args.out, html="atlas.html" if args.html else None,
                             progress=None if args.quiet else True)
    s = at.summary()
    kinds = ", ".join(f"{v} {k}" for k, v in sorted(s["edge_events"].items())) or "none"
    print(f"{s['nodes']} nodes, {s['edges']} directed paths ({kinds}); wrote {pathlib.Path(args.out) / 'atlas.json'}, "
          f"atlas.graphml, atlas_map.png, {'atlas.html, ' if args.html else ''}{rep}")
    bad = at.stats.get("store", {}).get("recomputed", 0)
    if bad:
        print(f"store: {bad} recorded result{'s' if bad > 1 else ''} failed the check (edited, damaged or "
              f"written before checksums) and {'were' if bad > 1 else 'was'} recomputed")
    if str(at.settings.get("symmetries", "")).startswith("not detected"):
        print(f"symmetries {at.settings['symmetries']}: explored as if the structure had none")
    if not signalled and not at.stats.get("partial") and args.store is None:
        remove_store(store)  # the default store of a complete run: nothing left to resume
    if not signalled:  # which limit stopped the run, and how to lift it (even with --quiet)
        for limit, text in atlas_report.limits_hit(at).items():
            print(f"libkin explore: {text}" + (f" (store {store})" if limit == "time_limit" else ""),
                  file=sys.stderr)
    if signalled:
        print(f"libkin: interrupted by signal {signalled[0]}: the atlas so far is written (partial); "
              f"continue with --resume (store {store})", file=sys.stderr)
        return 128 + signalled[0]
    return 0


@contextlib.contextmanager
def _stop_on_signals() -> Iterator[List[int]]:
    """SIGINT and SIGTERM in the block append their number to the list
    (the explorer then starts nothing more) instead of ending the process;
    a second one ends it as before."""
    got: List[int] = []
    if threading.current_thread() is not threading.main_thread():
        yield got
        return

    def handler(signum: int, frame: Any) -> None:
        if got:
            signal.signal(signum, old[signal.Signals(signum)])
            signal.raise_signal(signum)
        got.append(signum)
    old = {s: signal.signal(s, handler) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield got
    finally:
        for s, h in old.items():
            signal.signal(s, h)
