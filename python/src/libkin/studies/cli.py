"""`libkin study`: the command line of the solar-sail studies (register() adds
it to the dispatcher, libkin.cli)."""
import argparse
import pathlib
import sys

from libkin.atomic import folder_lock
from libkin.cliargs import EXIT_STUDY_FAILED, EXIT_USAGE, count
from libkin.parallel import executor


def register(sub):
    """Add the `study` subcommand to the dispatcher's subparsers."""
    s = sub.add_parser("study", help="the solar-sail folding study (paper Section 6) with a report")
    s.add_argument("--hub", type=int, default=6,
                   help="hub sides: 6 (default) = the hexagonal study R^A-R^B-R^C and back; 4 = the square "
                        "sail's paths out of its flat state; other even n >= 6: that family member")
    s.add_argument("--loops", type=count(1), default=2, help="loops of triangles (default 2; 1 for --hub 4)")
    s.add_argument("--out", default="study_out", help="output folder for report.md, summary.json, PNGs")
    s.add_argument("--quick", action="store_true",
                   help="skip the 2^s homotopy at the flat state (the symmetric sub-problem is still solved)")
    s.add_argument("--threads", type=count(1), default=2, help="threads of the homotopy solver")
    s.add_argument("--map-depth", type=count(1), default=2,
                   help="levels of the path map's atlas (libkin explore's --depth; default 2)")
    s.add_argument("--executor", default="serial", choices=["serial", "process", "dask"],
                   help="where the path map's branches are followed (libkin explore's --executor)")
    s.add_argument("--workers", type=count(1), default=2, help="workers of --executor process|dask (default 2)")
    s.add_argument("--quiet", action="store_true", help="no progress messages")
    s.set_defaults(fn=cmd_study)


def cmd_study(args: argparse.Namespace) -> int:
    if args.hub == 4 and args.loops != 1:
        print("the square-hub study is the paper's one-loop sail (--loops 1)", file=sys.stderr)
        return EXIT_USAGE
    with folder_lock(args.out):  # one run per --out at a time: a second fails at once (FolderInUseError)
        return _study(args)


def _study(args: argparse.Namespace) -> int:
    from . import sailstudy, squarestudy
    if args.hub == 4:
        if args.loops != 1:
            print("the square-hub study is the paper's one-loop sail (--loops 1)", file=sys.stderr)
            return EXIT_USAGE
        res = squarestudy.square_study(threads=args.threads, progress=not args.quiet, out=args.out)
    else:
        with executor(args.executor, args.workers) as ex:
            res = sailstudy.hexagonal_study(args.hub, args.loops, complete=not args.quick, threads=args.threads,
                                            progress=not args.quiet, out=args.out, executor=ex,
                                            map_depth=args.map_depth)
    if "failed" in res:
        print(f"study stopped early: {res['failed']}", file=sys.stderr)
        return EXIT_STUDY_FAILED
    print(f"report: {pathlib.Path(args.out) / 'report.md'}")
    return 0
