"""Command line: python -m libkin (or `libkin`) SUBCOMMAND ...

Exit status: 0 success; 1 a libkin error or a file that cannot be read or
written (one line on stderr, no traceback); 2 a usage error (argparse, or a
model that is not a valid start for the command); 3 a study that stopped
early; 4 a path that stopped before the steps asked (`follow`,
`fold-export`: what was reached is written, fewer frames than asked);
5 the run's store cannot be used (`explore`: not a store, damaged or
truncated, a failed write such as a full disk under it; one line naming the
store and what to do, atlas/store.py StoreError);
130 interrupted (Ctrl-C or SIGTERM: workers ended, one line on stderr).
"""
from __future__ import annotations

import argparse
import os
import pathlib
import sys
from typing import Any, List, NamedTuple, NoReturn, Optional, Tuple

import numpy as np

from .version import __version__
from .assembly import Analysis, Assembly, FollowEvent, solve_quadrics
from .atlas import cli as atlas_cli
from .atlas.store import StoreError
from .cliargs import (EXIT_ERROR, EXIT_INTERRUPTED, EXIT_PARTIAL, EXIT_STORE, EXIT_STUDY_FAILED, EXIT_USAGE,
                      add_input_arguments, count, finite, load_model_spec, positive)
from .errors import InvalidArgumentError, KinError, NotFoundError
from .parallel import Terminated, terminate_on_sigterm
from .studies import cli as studies_cli

__all__ = ["main", "follow_path", "FollowedPath", "EXIT_ERROR", "EXIT_USAGE", "EXIT_STUDY_FAILED", "EXIT_PARTIAL",
           "EXIT_STORE", "EXIT_INTERRUPTED"]


def _load(args: argparse.Namespace) -> Assembly:
    """args.model read as --fold-dim and --resolution say (where the command has them)."""
    return load_model_spec(args.model, fold_dim=getattr(args, "fold_dim", None),
                           resolution=getattr(args, "resolution", None))


def cmd_analyse(args: argparse.Namespace) -> int:
    a = _load(args)
    an = a.analyse()
    print(f"{a.name}: dim {a.dim}, {a.njoints} joints, {a.nbars} bars, H is {a.nfree} x {a.nbars}")
    print(f"rank r = {an.rank}; mechanisms m = {an.m} (internal {an.m_internal}, rigid {an.m_rigid}); "
          f"self-stress states s = {an.s}" + (f" ({an.s_trivial} of bars between fixed joints)" if an.s_trivial else ""))
    print(f"v_max = {an.v_max:.6g}, v_r (lowest non-zero) = {an.v_r:.6g}, max strain {a.max_strain:.3g}")
    print("state:", ("bifurcation point" if an.s > an.s_trivial else "a mechanism of several freedoms")
          if an.m_internal >= 2 else "on a single path" if an.m_internal == 1 else "rigid (no internal mechanism)")
    if args.singular_values:
        print("singular values:", " ".join(f"{v:.6g}" for v in an.singular_values))
    return 0


def _branch_direction(a: Assembly, args: argparse.Namespace) -> np.ndarray:
    """U_m beta for --branch K at a bifurcation: the real second-order
    solutions of the complete solver, K // 2 the solution, the sign by K's
    parity (even +, odd -) unless --sign gives it."""
    U = a.analyse().internal_mechanisms
    betas, _ = solve_quadrics(a.second_order(), basis=U)  # numbered and signed by the directions U beta
    if not 0 <= args.branch < 2 * len(betas):
        raise InvalidArgumentError(f"--branch {args.branch}: this bifurcation has {2 * len(betas)} directed branches "
                                   f"(0 .. {2 * len(betas) - 1}: {len(betas)} real second-order solutions, two signs)")
    sign = args.sign if args.sign is not None else (1 if args.branch % 2 == 0 else -1)
    print(f"branch {args.branch}: second-order solution {args.branch // 2} of {len(betas)}, sign {sign:+d}")
    return float(sign) * (U @ betas[args.branch // 2])


def _regular_start(args: argparse.Namespace) -> Tuple[Optional[Assembly], Optional[Analysis]]:
    """The model (perturbed and relaxed if asked) and its analysis, or None
    with a message when it is not on a single path. At a bifurcation with
    --branch the chosen branch's direction is set (args.direction)."""
    a = _load(args)
    if args.perturb:
        _generic_start(a, args)
    an = a.analyse()
    args.direction = None
    if an.m_internal >= 2 and args.branch is not None:
        args.direction = _branch_direction(a, args)
        return a, an
    if an.m_internal == 0:
        print(f"{a.name} is rigid here (no internal mechanism; {an.m_rigid} rigid-body mechanisms): "
              "there is no path to follow", file=sys.stderr)
        return None, None
    if an.m_internal != 1:
        print(f"{a.name} has {an.m_internal} internal mechanisms here: it is at a bifurcation; "
              "choose a branch (--branch K) or start from a regular configuration (--perturb)", file=sys.stderr)
        return None, None
    return a, an


def cmd_follow(args: argparse.Namespace) -> int:
    a, an = _regular_start(args)
    if a is None or an is None:
        return EXIT_USAGE
    if args.direction is not None:
        a.set_direction(args.direction)
    path = follow_path(a, an, args.steps, args.delta, not args.quiet, direction=args.direction)
    ls, svs, frames, passed = path.lengths, path.singular_values, path.frames, path.passed
    stopped = len(ls) - 1 < args.steps  # fewer frames than asked: the exit status says so
    k = int(np.argmin(path.v_r))
    # v_r as the library defines it (kin_analysis.v_r, what `libkin analyse` and
    # `libkin locate` report), printed to the last bit
    print(f"{len(ls) - 1} steps, path length {ls[-1]:.6g}, max strain {a.max_strain:.3g}, "
          f"smallest v_r {float(path.v_r[k])!r} (v_r / v_max {path.v_r[k] / path.v_max[k]:.3g}, step {k})")
    if path.detector_stop:
        print(f"bifurcations counted up to path length {path.detector_stop[0]:.6g} only: the detector stopped "
              f"there ({path.detector_stop[1]})", file=sys.stderr)
    if passed:
        print(f"passed {len(passed)} bifurcation{'s' if len(passed) > 1 else ''} (located by the library's "
              "detector, as `libkin locate` and `libkin explore` find them):")
        print(f"  {'step':>6}  {'path length from':>16}  {'to':>12}")
        for k, l0, l1 in passed:
            print(f"  {k:>6}  {l0:>16.6g}  {l1:>12.6g}")
    else:
        print("passed no bifurcation")
    if args.plot:
        from . import plot
        plot.follow.path_singular_values(ls, np.array(svs), path.v_r, path.v_max, count=args.count, passed=passed,
                                         path=args.plot, title=f"{a.name}: singular values of H along the path")
        print("wrote", args.plot)
    if args.gif:
        from . import plot
        k = max(1, len(frames) // 60)
        plot.follow.animate_path(frames[::k], a.bars, args.gif, fixed=a.fixed, lengths=ls[::k], name=a.name or "")
        print("wrote", args.gif)
    if args.out:
        a.to_json(args.out)
        print("wrote", args.out)
    return EXIT_PARTIAL if stopped else 0


class FollowedPath(NamedTuple):
    """What `follow_path` followed (start included in every list).

    Attributes
    ----------
    lengths : list of float
        Path length at each frame.
    singular_values : list of ndarray
        The singular values of H at each frame.
    frames : list of ndarray, shape (njoints, dim)
        The configurations.
    passed : list of (int, float, float)
        Each bifurcation passed, as (k, path length at frame k - 1, at frame
        k): located by the library's detector (kin_follow_event, as `libkin
        locate` and `libkin explore` locate them) between frames k - 1 and k,
        or at frame k.
    v_r, v_max : ndarray, shape (frames,)
        The library's v_r (lowest non-zero singular value, kin_analysis) and
        v_max at each frame.
    detector_stop : tuple of (float, str), or None
        Where and why the detector stopped before the last frame (a libkin
        error); bifurcations are counted up to there.
    """

    lengths: List[float]
    singular_values: List[np.ndarray]
    frames: List[np.ndarray]
    passed: List[Tuple[int, float, float]]
    v_r: np.ndarray
    v_max: np.ndarray
    detector_stop: Optional[Tuple[float, str]] = None


def follow_path(a: Assembly, an: Analysis, steps: int, delta: float = 0.0, progress: bool = False,
                direction: Optional[np.ndarray] = None) -> FollowedPath:
    """Follow up to `steps` steps from a regular point (analysis `an`), or
    out of a bifurcation along `direction` (already set on `a`), and count
    the bifurcations passed with the library's detector (`_bifurcations_passed`).
    A libkin error stops the path with a line on stderr; what was reached
    stands."""
    start = a.clone()  # the detector's handle, at the start
    ls, svs, frames = [0.0], [an.singular_values], [a.coords]
    vr, vmax = [an.v_r], [an.v_max]
    tangents: List[Optional[np.ndarray]] = [np.asarray(direction, float) if direction is not None else _tangent(a)]
    regular = [an.m_internal == 1]
    try:
        for info in a.follow(steps=steps, delta=delta, progress=progress):
            here = a.analyse()
            ls.append(info.l)
            svs.append(here.singular_values)
            frames.append(a.coords)
            vr.append(here.v_r)
            vmax.append(here.v_max)
            tangents.append(_tangent(a))
            regular.append(here.m_internal == 1)
    except KinError as exc:
        print(f"stopped after {len(ls) - 1} of {steps} steps: {exc}", file=sys.stderr)
    passed, stop = _bifurcations_passed(start, ls, frames, tangents, regular, delta)
    return FollowedPath(ls, svs, frames, passed, np.array(vr), np.array(vmax), stop)


def _tangent(a: Assembly) -> Optional[np.ndarray]:
    """The oriented tangent the next step from here takes (None where there
    is none: a step landed on a bifurcation)."""
    try:
        return a.tangent()
    except KinError:
        return None


def _bifurcations_passed(start: Assembly, ls: List[float], frames: List[np.ndarray],
                         tangents: List[Optional[np.ndarray]], regular: List[bool], delta: float
                         ) -> Tuple[List[Tuple[int, float, float]], Optional[Tuple[float, str]]]:
    """The bifurcations on the followed path (frames 0 .. n), found by the
    library's detector: kin_follow_event (`Assembly.follow_event`, what
    `libkin locate` and `libkin explore` use: the signed test function, the
    turn of v_r, then location, which must bring v_r to zero) on a copy of
    the start. Each event is placed between two frames by where the copy
    stands; the copy then goes on from the first regular frame past it (so
    the detector follows the frames' own path through each bifurcation).
    Only located bifurcations count: a sign change of the test function
    alone is not one (nor a near miss, a closed loop). Returns the
    bifurcations as (k, ls[k - 1], ls[k]) and, if the detector failed, the
    path length it reached and why."""
    n = len(frames) - 1
    passed: List[Tuple[int, float, float]] = []
    if n == 0:
        return passed, None
    d = start.clone()
    sgn = 1.0 if ls[n] >= ls[0] else -1.0
    steps = [abs(ls[k] - ls[k - 1]) for k in range(1, n + 1)]
    slack = max(steps)  # the detector does not look at the step that ends at its length budget
    i = 0
    while i < n:
        t = tangents[i]
        if t is None or not (regular[i] or i == 0):
            i += 1
            continue
        d.coords = frames[i]
        d.reset_path()
        ev = d.follow_event(t, delta=delta, max_length=abs(ls[n] - ls[i]) + slack, max_steps=max(1000, 10 * n))
        k, u = _place(frames, ls, i, ls[i] + sgn * ev.length, d.coords, sgn)
        if ev.event == "failed":
            return passed, (ls[i] + sgn * ev.length, ev.message or ev.status)
        if k > n:
            break  # past the last frame
        if ev.event == "bifurcation":
            passed.append((k, ls[k - 1], ls[k]))
        elif ev.event == "length-limit":
            break
        # go on from the first regular frame past the event
        i = k if u < 1.0 - _AT_FRAME else k + 1
        while i < n and (not regular[i] or tangents[i] is None):
            i += 1
    return passed, None


#: an event this close to a frame (relative to the step's chord) is at that frame
_AT_FRAME = 1e-9


def _place(frames: List[np.ndarray], ls: List[float], i: int, l_e: float, x: np.ndarray, sgn: float
           ) -> Tuple[int, float]:
    """Between which frames k - 1 and k (i < k <= n; n + 1: past the last)
    the configuration x lies, found near path length l_e (the detector's
    length, which counts its own chords): (k, u) with u the position of x's
    projection on the chord from frame k - 1 to frame k (0 at k - 1, 1 at k)."""
    n = len(frames) - 1
    k = next((j for j in range(i + 1, n + 1) if sgn * (ls[j] - l_e) >= 0.0), n)

    def u_of(j: int) -> float:
        c = (frames[j] - frames[j - 1]).ravel()
        cc = float(c @ c)
        return float(c @ (x - frames[j - 1]).ravel()) / cc if cc > 0.0 else 1.0

    u = u_of(k)
    for _ in range(n):
        if u < 0.0 and k > i + 1:
            k -= 1
        elif u > 1.0 + _AT_FRAME and k < n:
            k += 1
        else:
            break
        u = u_of(k)
    if k == n and u > 1.0 + _AT_FRAME:
        return n + 1, u
    return k, u


def _generic_start(a: Assembly, args: argparse.Namespace) -> None:
    # a generic start near the model: lift the free coordinates of the last
    # axis (z in 3D, y in 2D) pseudo-randomly and relax to zero strain
    rng = np.random.default_rng(args.seed)
    xyz = a.coords
    free = a.free_map()[:, -1] >= 0
    xyz[free, -1] += args.perturb * (rng.random(free.sum()) - 0.5)
    a.coords = xyz
    a.relax(max_iter=200)


def _add_start_arguments(s: argparse.ArgumentParser) -> None:
    """Where `follow` and `locate` start: a generic point (--perturb,
    --seed) or a branch out of a bifurcation (--branch, --sign); the input
    options (--fold-dim, --resolution)."""
    s.add_argument("--perturb", type=finite, default=0.0,
                   help="start from a generic point: lift free nodes by up to this amount and relax")
    s.add_argument("--seed", type=int, default=1, help="seed of --perturb")
    s.add_argument("--branch", type=count(0), default=None, metavar="K",
                   help="at a bifurcation: leave along directed branch K (real second-order solution K // 2 of the "
                        "complete solver in their canonical order, the same on every machine; sign + for even K, - for odd)")
    s.add_argument("--sign", type=int, default=None, choices=[1, -1], help="the sign of --branch's direction")
    add_input_arguments(s)


def cmd_locate(args: argparse.Namespace) -> int:
    a, _ = _regular_start(args)
    if a is None:
        return EXIT_USAGE
    if args.direction is not None:
        # out of a bifurcation along a branch: follow it to its next event
        return _print_event(a, a.follow_event(args.direction, vr_tol=args.vr_tol, delta=args.delta,
                                              max_steps=args.max_steps), args)
    try:
        info = a.locate(method=args.method, delta=args.delta, vr_tol=args.vr_tol, max_steps=args.max_steps)
    except NotFoundError as exc:
        if args.method != "fast":
            raise
        # vr_tol out of reach here, or a near miss: kin_follow_event locates to
        # the accuracy reachable (up to 1e-6) or says it is a near miss
        print(f"the fast locator gave up ({exc});\nfollowing on from the last regular point to the next event:")
        return _print_event(a, a.follow_event(vr_tol=args.vr_tol, delta=args.delta, max_steps=args.max_steps), args)
    events = {1: "test function changed sign", 2: "paper's switch rule", 3: "a step landed on it", 4: "v_r turned near zero"}
    print(f"bifurcation after {info.steps} steps ({events.get(info.event, info.event)}), located by the "
          f"{args.method} method with {info.factorizations} factorizations ({info.forward} forward "
          f"calculations): v_r / v_max = {info.v_r_rel:.3g}"
          f"{' (proven <= %.3g)' % info.v_r_bound[2] if info.v_r_bound else ''}, m = {info.m_internal}, s = {info.s}, "
          f"path kept: {'yes' if info.path_kept else 'no'}, path length {a.path_length:.9g}")
    if args.out:
        a.to_json(args.out)
        print("wrote", args.out)
    return 0


def _print_event(a: Assembly, ev: FollowEvent, args: argparse.Namespace) -> int:
    """One line on a kin_follow_event result (and --out); the exit status."""
    print(f"{ev.event} after {ev.steps} steps, path length {ev.length:.9g}: v_r / v_max = {ev.v_r_rel:.3g}"
          + (f" (located to {ev.vr_tol_used:.0e})" if ev.event == "bifurcation" else "")
          + f", m = {ev.m_internal}, s = {ev.s}" + (f": {ev.message}" if ev.message else ""))
    if args.out:
        a.to_json(args.out)
        print("wrote", args.out)
    return 0 if ev.event != "failed" else EXIT_ERROR


def cmd_draw(args: argparse.Namespace) -> int:
    from . import plot
    a = load_model_spec(args.model)
    plot.draw(a, plane=args.plane, path=args.png)
    print("wrote", args.png)
    return 0


def cmd_models(args: argparse.Namespace) -> int:
    out = pathlib.Path(args.dir)
    out.mkdir(parents=True, exist_ok=True)
    for spec, name in [("threebar:RA", "threebar_RA"), ("threebar:RB", "threebar_RB"),
                       ("threebar:RC", "threebar_RC"), ("sail:4:1", "square_sail"), ("sail:6:2", "hex_sail")]:
        a = load_model_spec(spec)
        a.name = name
        a.to_json(out / f"{name}.json")
        print("wrote", out / f"{name}.json")
    return 0


def cmd_fold_export(args: argparse.Namespace) -> int:
    from .io.fold import write_fold
    a = _load(args)
    frames = [a.coords]
    stopped = False
    if args.follow:
        an = a.analyse()
        if an.m_internal != 1:
            what = ("is rigid here (no internal mechanism)" if an.m_internal == 0 else
                    f"has {an.m_internal} internal mechanisms here: not on a single path")
            print(f"{a.name} {what}; nothing to follow", file=sys.stderr)
            return EXIT_USAGE
        try:
            for _ in a.follow(steps=args.follow, delta=args.delta, progress=not args.quiet):
                frames.append(a.coords)
        except KinError as exc:
            stopped = True
            print(f"stopped after {len(frames) - 1} of {args.follow} steps: {exc}", file=sys.stderr)
    faces = "triangles" if args.faces == "triangles" else None
    write_fold(args.out, a, path_coords=frames, faces=faces)
    print(f"wrote {args.out} ({len(frames)} frame{'s' if len(frames) > 1 else ''}"
          + (f" of {args.follow + 1} asked: the path stopped early)" if stopped else ")"))
    return EXIT_PARTIAL if stopped else 0


class _OneLineParser(argparse.ArgumentParser):
    """A usage error is one line on stderr (with where to get help), exit 2."""

    def error(self, message: str) -> NoReturn:
        self.exit(EXIT_USAGE, f"{self.prog}: {message} (see '{self.prog} --help')\n")


def _parser() -> argparse.ArgumentParser:
    p = _OneLineParser(prog="libkin", description=(
        "Kinematic analysis of pin-jointed bar assemblies. MODEL is a JSON model file "
        "(schema: python/README.md) or a built-in: threebar:RA|RB|RC, sail:N_SIDES:N_LOOPS."),
        epilog="exit status: 0 success, 1 libkin or file error, 2 usage error, 3 study stopped early, "
               "4 path stopped early (fewer frames than asked), 5 explore's store unusable (damaged, full disk), "
               "130 interrupted")
    p.add_argument("--version", action="version", version=f"libkin {__version__}")
    sub = p.add_subparsers(dest="cmd", required=True, parser_class=_OneLineParser)
    s = sub.add_parser("analyse", help="first-order analysis: rank, mechanisms, self-stresses")
    s.add_argument("model")
    s.add_argument("--singular-values", action="store_true", help="print all singular values")
    add_input_arguments(s)
    s.set_defaults(fn=cmd_analyse)
    s = sub.add_parser("follow", help="follow the path from a regular configuration")
    s.add_argument("model")
    s.add_argument("--steps", type=count(1), default=50, help="number of steps (default 50)")
    s.add_argument("--delta", type=finite, default=0.0, help="step amplitude (0 = largest allowed)")
    s.add_argument("--plot", help="write the singular values along the path (v_r, v_max, bifurcations) to this PNG")
    s.add_argument("--count", type=count(1), default=15, help="how many of the lowest singular values to plot")
    s.add_argument("--gif", help="write an animation of the path to this GIF (3D models in 3D, supports, legend)")
    s.add_argument("--plane", default="xy", choices=["xy", "xz", "yz"], help="unused: the GIF draws 3D models in 3D")
    s.add_argument("--out", help="write the final configuration as a JSON model")
    s.add_argument("--quiet", action="store_true", help="no progress bar")
    _add_start_arguments(s)
    s.set_defaults(fn=cmd_follow)
    s = sub.add_parser("locate", help="follow the path to the next bifurcation and converge onto it")
    s.add_argument("model")
    s.add_argument("--method", default="fast", choices=["fast", "paper", "illinois"],
                   help="fast: Hermite interpolation (default); paper: the paper's quadratic (eq. 23-26); "
                        "illinois: regula falsi on the signed test function")
    s.add_argument("--delta", type=finite, default=0.0,
                   help="step amplitude while following (0 = largest allowed, negative = backwards)")
    s.add_argument("--vr-tol", type=positive, default=1e-10, help="located when v_r / v_max <= this (default 1e-10)")
    s.add_argument("--max-steps", type=count(1), default=1000, help="steps to look for a bifurcation")
    s.add_argument("--out", help="write the located configuration as a JSON model")
    _add_start_arguments(s)
    s.set_defaults(fn=cmd_locate)
    s = sub.add_parser("draw", help="draw a model to a PNG")
    s.add_argument("model")
    s.add_argument("png")
    s.add_argument("--plane", default="xy", choices=["xy", "xz", "yz"])
    s.set_defaults(fn=cmd_draw)
    # the subcommands of the packages that own them
    studies_cli.register(sub)
    atlas_cli.register(sub)
    s = sub.add_parser("fold-export", help="write a model, or a path followed from it, as a FOLD file")
    s.add_argument("model", help="MODEL as above, or a .fold file")
    s.add_argument("--follow", type=count(0), default=0, help="steps to follow; each is a frame (default 0)")
    s.add_argument("--delta", type=finite, default=0.0, help="step amplitude (0 = largest allowed)")
    s.add_argument("--faces", choices=["file", "triangles"], default="file",
                   help="faces: the .fold file's (default) or the bar graph's triangles")
    s.add_argument("--out", required=True, help="the .fold file to write")
    s.add_argument("--quiet", action="store_true", help="no progress bar")
    add_input_arguments(s)
    s.set_defaults(fn=cmd_fold_export)
    s = sub.add_parser("models", help="write the built-in models as JSON files")
    s.add_argument("dir")
    s.set_defaults(fn=cmd_models)
    return p


def _one_line(exc: BaseException) -> str:
    text = " ".join(str(exc).split()) or type(exc).__name__
    return f"libkin: {text}"


def main(argv: Optional[List[str]] = None) -> int:
    """Run the command line.

    Parameters
    ----------
    argv : list of str, optional
        The arguments (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit status (see the module docstring); usage errors exit via
        SystemExit(2) from argparse.
    """
    args = _parser().parse_args(argv)
    try:
        with terminate_on_sigterm():  # SIGTERM: the orderly stop of Ctrl-C
            rc: Any = args.fn(args)
        return int(rc)
    except KeyboardInterrupt as exc:
        print("libkin: terminated" if isinstance(exc, Terminated) else "libkin: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except BrokenPipeError:
        # the reader of stdout went away (e.g. `| head`): stop quietly, and keep
        # the interpreter's final flush from failing again
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return EXIT_ERROR
    except StoreError as exc:
        print(_one_line(exc), file=sys.stderr)
        return EXIT_STORE
    except (KinError, OSError, ImportError, ValueError) as exc:
        print(_one_line(exc), file=sys.stderr)
        return EXIT_ERROR
