"""`libkin study`: the command line of the solar-sail studies (register() adds
it to the dispatcher, libkin.cli)."""
import argparse
from typing import List, Tuple
import pathlib
import sys

from libkin.atomic import folder_lock
from libkin.cliargs import EXIT_STUDY_FAILED, EXIT_USAGE, count, require_extras
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
    s.add_argument("--reading", default=None, metavar="NAME",
                   help="which model of the paper's hexagonal sail (Section 6.2 allows several; docs/sail_study.md "
                        "'Readings'): the main job's ('alternating', the default) runs the study; another name "
                        "measures that reading against every statement the paper makes (report.md in --out); 'all' "
                        "tabulates every reading side by side")
    s.add_argument("--contact", nargs="?", type=float, const=0.0, default=None, metavar="T",
                   help="also explore the path map with contact as an event (membrane thickness t/a = T, default "
                        "0: the bare membrane) and report which mapped paths reach their next event free of "
                        "contact")
    s.add_argument("--interference", action="store_true",
                   help="the interference study instead (paper Section 7's open question): fold each member of "
                        "--members along its radially sequential path and report the first contact of its "
                        "membrane at each --thickness (report.md, summary.json, interference.png in --out)")
    s.add_argument("--members", default=None,
                   help="with --interference: members as HUB/LOOPS, comma-separated "
                        "(default 6/1,6/2,6/3,6/4,8/1,8/2,8/3,8/4)")
    s.add_argument("--thickness", default=None,
                   help="with --interference: panel thicknesses t/a, comma-separated (default 0,0.001,0.003,0.01,0.03)")
    s.set_defaults(fn=cmd_study)


def _members(text: str) -> List[Tuple[int, int]]:
    out = []
    for item in text.split(","):
        try:
            n, k = (int(v) for v in item.strip().split("/"))
        except ValueError:
            raise argparse.ArgumentTypeError(f"--members: expected HUB/LOOPS items such as 6/2, got {item!r}")
        if n < 6 or n % 2 or k < 1:
            raise argparse.ArgumentTypeError(f"--members: {item!r}: the hub must be even and >= 6, loops >= 1")
        out.append((n, k))
    return out


def _thicknesses(text: str) -> List[float]:
    try:
        ts = [float(v) for v in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"--thickness: expected numbers separated by commas, got {text!r}")
    if not ts or any(not (0.0 <= t < 1.0) for t in ts):
        raise argparse.ArgumentTypeError("--thickness: each t/a must be in [0, 1)")
    return sorted(set(ts))


def _interference(args: argparse.Namespace) -> int:
    from .contactreport import write_interference
    from .contactstudy import MEMBERS, THICKNESSES, interference_study
    try:
        members = _members(args.members) if args.members else list(MEMBERS)
        ts = _thicknesses(args.thickness) if args.thickness else list(THICKNESSES)
    except argparse.ArgumentTypeError as exc:
        print(exc, file=sys.stderr)
        return EXIT_USAGE
    with executor(args.executor, args.workers) as ex:
        study = interference_study(members, ts, threads=args.threads, progress=not args.quiet, executor=ex)
    write_interference(study, args.out)
    print(f"report: {pathlib.Path(args.out) / 'report.md'}")
    return 0


def needed_modules(args: argparse.Namespace) -> List[str]:
    """The optional modules this study cannot run without: matplotlib for its
    figures, distributed for --executor dask. plotly is not among them: without
    it the study writes everything but the path map's atlas.html, and says so."""
    return (["matplotlib"]
            + (["distributed"] if args.executor == "dask" and (args.interference or args.hub != 4) else []))


def _reading(args: argparse.Namespace) -> int:
    from .readings import readings_table
    from .readingsreport import write_readings
    names = None if args.reading == "all" else [args.reading]
    rows = readings_table(names, threads=args.threads)
    write_readings(rows, args.out)
    print(f"report: {pathlib.Path(args.out) / 'report.md'}")
    return 0


def cmd_study(args: argparse.Namespace) -> int:
    if args.reading is not None:
        from .readings import MAIN_READING
        from .readingsreport import reading_names
        if args.reading not in reading_names():
            print(f"--reading: unknown reading {args.reading!r}; one of: {', '.join(reading_names())}",
                  file=sys.stderr)
            return EXIT_USAGE
        if args.hub != 6 or args.loops != 2 or args.interference or args.contact is not None:
            print("--reading reads the paper's hexagonal sail (--hub 6 --loops 2, without --interference or "
                  "--contact)", file=sys.stderr)
            return EXIT_USAGE
        if args.reading != MAIN_READING:
            with folder_lock(args.out):
                return _reading(args)
    if args.contact is not None:
        if not (0.0 <= args.contact < 1.0):
            print("--contact: the thickness t/a must be in [0, 1)", file=sys.stderr)
            return EXIT_USAGE
        if args.interference or args.hub == 4:
            print("--contact maps the hexagonal-type study's paths (--hub 6, 8, ...; not with --interference "
                  "or --hub 4)", file=sys.stderr)
            return EXIT_USAGE
    if args.hub == 4 and args.loops != 1 and not args.interference:
        print("the square-hub study is the paper's one-loop sail (--loops 1)", file=sys.stderr)
        return EXIT_USAGE
    # every missing extra named at once, before any work or any file (ImportError: exit 1)
    require_extras("libkin study", needed_modules(args))
    if args.interference:
        with folder_lock(args.out):
            return _interference(args)
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
                                            map_depth=args.map_depth, contact=args.contact)
    if "failed" in res:
        print(f"study stopped early: {res['failed']}", file=sys.stderr)
        return EXIT_STUDY_FAILED
    print(f"report: {pathlib.Path(args.out) / 'report.md'}")
    return 0
