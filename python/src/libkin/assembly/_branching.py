"""The paths out of a bifurcation (paper Section 3.4).

`BranchingMixin` holds the branching methods of `libkin.Assembly`:
second-order matrices, the solvers of the second-order equations, and the
following of every solution. `solve_quadrics` is the solver on its own.
"""
from __future__ import annotations

import dataclasses
from typing import Any, Dict, List, Optional, Tuple

import numpy as np
import numpy.typing as npt

from .._native._arrays import read_ptr, write_ptr
from ._base import AssemblyBase, FloatArray
from ._canonical import canonical
from .._native._lib import default_struct, ffi, lib, new_struct
from .._native._progress import Progress, reporting
from ..errors import InvalidArgumentError, StateError, check

_WEIGHTINGS = {"exact": "KIN_Q_EXACT", "paper": "KIN_Q_PAPER_EQ17"}
_SOLVERS = ("homotopy", "scan")


@dataclasses.dataclass(frozen=True)
class BranchPath:
    """One directed candidate path out of a bifurcation.

    Attributes
    ----------
    beta : int
        Index of the second-order solution it starts along.
    sign : int
        +1 or -1: the direction along that solution.
    exists : bool
        Whether a finite path was followed from the bifurcation.
    tangent_ok : bool
        Whether the path left along the predicted tangent (eq. 21-22).
    tangent_cos : float
        Cosine between the path's chord and the predicted tangent.
    path_id : int
        Paths with the same id coincide (distinct-path grouping).
    length : float
        Path length followed.
    final_coords : ndarray, shape (njoints, dim)
        Where the path ended.
    """

    beta: int
    sign: int
    exists: bool
    tangent_ok: bool
    tangent_cos: float
    path_id: int
    length: float
    final_coords: FloatArray


@dataclasses.dataclass(frozen=True)
class Branches:
    """Every path out of a bifurcation.

    Attributes
    ----------
    betas : ndarray, shape (nsol, m_internal)
        Real second-order solutions (unit vectors), in the canonical order
        and sign of their directions (`libkin.assembly.canonical_order`).
    directions : ndarray, shape (nsol, nfree)
        Their first-order directions ``U_m @ beta``.
    paths : list of BranchPath
        Two directed candidate paths per solution.
    distinct : int
        How many of them are distinct paths.
    accounting : dict
        The solver's counts (see `solve_quadrics`).
    """

    betas: FloatArray
    directions: FloatArray
    paths: List[BranchPath]
    distinct: int
    accounting: Dict[str, int]


# KIN_HOMOTOPY_MAX_PATHS (kin_branch.h): the homotopy's default path limit
_MAX_PATHS_DEFAULT = 1 << 20
# the symmetry found at a configuration is given to the complete solver from
# this many self-stresses on (2^8 = 256 paths take ~0.1 s plainly), where a
# cyclic subgroup permutes mechanisms and equations alike (the equivariant
# route: the plain solver's roots, one path per orbit of start roots)
SYMMETRIC_SOLVE_MIN_S = 8


# the complete solver's accounting (kin_homotopy_info): the tracker's counts,
# then the interval certificates' (issue 38)
HOMOTOPY_ACCOUNTING = ("paths", "real", "real_distinct", "nonreal", "singular", "failed", "duplicates", "unpaired",
                       "retracked", "proven_real", "proven_nonreal", "unproven", "proven_all", "proven_refined",
                       "proven_overlap", "unproven_nopoint", "unproven_refused")


def equivariant_order(Q: FloatArray, R: FloatArray, seed: int = 1) -> int:
    """The order of the cyclic subgroup of R (k, m, m) that the symmetric
    solver's equivariant route uses on Q (kin_quadrics_equivariant_form);
    0 if none qualifies or the system is not one it takes."""
    s, m = Q.shape[0], Q.shape[1]
    if R.ndim != 3 or R.shape[1:] != (m, m) or m != s + 1:
        return 0
    Qc = np.ascontiguousarray(Q, dtype=np.float64)
    Rc = np.ascontiguousarray(R.transpose(0, 2, 1))  # column-major matrices
    Qt, U, perm = np.empty((s, m, m)), np.empty((m, m)), np.empty(m, dtype=np.intc)
    order, norbits = ffi.new("int *"), ffi.new("long *")
    rc = lib.kin_quadrics_equivariant_form(m, s, read_ptr(Qc, "double *"), R.shape[0], read_ptr(Rc, "double *"),
                                           int(seed), write_ptr(Qt, "double *"), write_ptr(U, "double *"),
                                           write_ptr(perm, "int *"), order, norbits, ffi.NULL, 0)
    return int(order[0]) if rc == 0 else 0

def solve_quadrics(Q: npt.ArrayLike, solver: str = "homotopy", starts: int = 1024, seed: int = 1,
                   threads: int = 2, progress: Progress = None,
                   max_paths: Optional[int] = None,
                   group: Optional[npt.ArrayLike] = None,
                   basis: Optional[npt.ArrayLike] = None) -> Tuple[FloatArray, Dict[str, int]]:
    """Real solutions of the second-order equations ``beta^T Q_j beta = 0``, ``|beta| = 1``.

    Parameters
    ----------
    Q : array_like, shape (s, m, m)
        Symmetric second-order matrices, with m = s + 1.
    solver : {'homotopy', 'scan'}, optional
        'homotopy': the complete solver (total-degree homotopy continuation
        with certified endpoints, accounting for all 2^s paths); 'scan': the
        paper's root scan from `starts` points.
    starts : int, optional
        Starting points of the scan.
    seed : int, optional
        Seed of the random start system or scan.
    threads : int, optional
        Threads of the homotopy solver, at most the online processors (the
        answer does not depend on it).
    progress : None, bool or callable, optional
        Progress of the homotopy (see `libkin._progress`): True shows a tqdm
        bar, a callable gets ``(done, total)`` and cancels by returning true.
        Ctrl-C stops the solver within about 0.1 s and raises KeyboardInterrupt.
    max_paths : int, optional
        Refuse more than this many homotopy paths 2^s (None: the library's 2^20).
    group : array_like, shape (k, m, m), optional
        'homotopy' only: a symmetry group of the system acting on beta by
        orthogonal matrices (``q(R b) = S q(b)``; closed under products up to
        sign; the identity may be left out), e.g. from
        `libkin.symmetry.automorphisms.mechanism_group`. The solver then tracks one
        path per orbit (kin_quadrics_homotopy_sym: the total-degree homotopy
        in coordinates where a cyclic subgroup permutes the mechanisms and
        the equations alike, one path per orbit of start roots, e.g. 10944
        instead of 32768 on the hexagonal sail's flat state; for other
        groups monodromy in the equivariant family, then one path per orbit
        to Q) with the same certified accounting of all 2^s roots; the
        accounting gains 'group', 'orbits', 'found', 'monodromy_paths' (0 on
        the first route) and 'final_paths'.
    basis : array_like, shape (n, m), optional
        The mechanism basis U the system is written in
        (``analyse().internal_mechanisms``): the solutions are then ordered
        and signed by their physical directions U beta (`canonical_order`),
        the same on every machine whatever basis the SVD gave. None: by
        beta itself (the same for this Q whatever the solver's route,
        threads or path order).

    Returns
    -------
    betas : ndarray, shape (nsol, m)
        The real solutions, one of each ``+-beta`` pair, in the canonical
        order and with the canonical sign (`libkin.assembly.canonical_order`).
    accounting : dict
        'homotopy': paths, real, real_distinct, nonreal, singular, failed,
        duplicates, unpaired, retracked, and the interval certificates
        (kin_homotopy_info, docs/branches.md "What certified means"):
        proven_real, proven_nonreal, unproven (= unproven_nopoint +
        unproven_refused + proven_overlap), proven_all (1: all 2^s solutions
        proven distinct and simple, so there are no others), proven_refined;
        'scan': starts, converged, distinct.

    Raises
    ------
    InvalidArgumentError
        `Q` has the wrong shape or `solver` is unknown (a ValueError).
    StateError
        m is not s + 1.
    LimitError
        2^s is more than `max_paths`.
    CancelledError
        The `progress` callable asked to stop.
    KinError
        As the C solver reports (e.g. `GslError`); with `group`, an
        InvalidArgumentError if a matrix is not orthogonal, the set is not a
        group or the system is not equivariant, NotConvergedError if the
        monodromy could not find 2^s roots.
    """
    Qa = np.asarray(Q, dtype=np.float64)
    if Qa.ndim != 3 or Qa.shape[1] != Qa.shape[2]:
        raise InvalidArgumentError(f"Q: expected shape (s, m, m), got {Qa.shape}")
    if solver not in _SOLVERS:
        raise InvalidArgumentError(f"solver: expected one of {list(_SOLVERS)}, got {solver!r}")
    s, m = Qa.shape[0], Qa.shape[1]
    if m != s + 1:
        raise StateError(f"the solvers need m = s + 1; here m = {m}, s = {s}")
    Qc = np.ascontiguousarray(Qa)
    # room for every real solution the solver can return (2^s for the
    # homotopy within its path limit, at most `starts` for the scan); the
    # pages the solver does not write are never touched
    limit = _MAX_PATHS_DEFAULT if max_paths is None else max(1, int(max_paths))
    maxsol = max(1, min(int(starts), 1 << min(s, 30))) if solver == "scan" else \
        (1 << s if s < 62 and (1 << s) <= limit else 1)
    betas = np.empty((maxsol, m))
    nsol = ffi.new("int *")
    accounting: Dict[str, int]
    if group is not None:
        if solver != "homotopy":
            raise InvalidArgumentError("group: only with solver='homotopy'")
        found, accounting = _solve_symmetric(Qc, np.asarray(group, dtype=np.float64), seed, threads, progress,
                                             max_paths, betas, nsol)
        return canonical(found, basis), accounting
    if solver == "scan":
        info: Any = new_struct("kin_solve_info")
        check(lib.kin_quadrics_scan(m, s, read_ptr(Qc, "double *"), int(starts), int(seed),
                                    write_ptr(betas, "double *"), maxsol, nsol, info), what="scan")
        accounting = {"starts": info.starts, "converged": info.converged, "distinct": info.distinct}
    else:
        info = new_struct("kin_homotopy_info")
        opt = default_struct("kin_homotopy_options")
        opt.seed = int(seed)
        opt.nthreads = int(threads)
        if max_paths is not None:
            opt.max_paths = int(max_paths)
        with reporting(progress, f"homotopy 2^{s}", "path") as rep:
            opt.progress = rep.c_callback
            rc = lib.kin_quadrics_homotopy_ex(m, s, read_ptr(Qc, "double *"), opt, write_ptr(betas, "double *"),
                                              maxsol, nsol, ffi.NULL, info)
        check(rc, what="homotopy")
        accounting = {k: getattr(info, k) for k in HOMOTOPY_ACCOUNTING}
    return canonical(betas[: nsol[0]], basis), accounting


def _solve_symmetric(Qc: FloatArray, R: FloatArray, seed: int, threads: int, progress: Progress,
                     max_paths: Optional[int], betas: FloatArray, nsol: Any) -> Tuple[FloatArray, Dict[str, int]]:
    s, m = Qc.shape[0], Qc.shape[1]
    if R.ndim != 3 or R.shape[1:] != (m, m):
        raise InvalidArgumentError(f"group: expected shape (k, {m}, {m}), got {R.shape}")
    Rc = np.ascontiguousarray(R.transpose(0, 2, 1))  # column-major matrices
    info: Any = new_struct("kin_homotopy_info")
    sinfo: Any = new_struct("kin_homotopy_sym_info")
    opt: Any = default_struct("kin_homotopy_options")
    opt.seed = int(seed)
    opt.nthreads = int(threads)
    if max_paths is not None:
        opt.max_paths = int(max_paths)
    err = ffi.new("char[]", 256)
    with reporting(progress, f"homotopy 2^{s} with symmetry", "path") as rep:
        opt.progress = rep.c_callback
        rc = lib.kin_quadrics_homotopy_sym(m, s, read_ptr(Qc, "double *"), R.shape[0], read_ptr(Rc, "double *"),
                                           opt, write_ptr(betas, "double *"), betas.shape[0], nsol, ffi.NULL,
                                           info, sinfo, err, 256)
    check(rc, what="homotopy with symmetry: " + ffi.string(err).decode(errors="replace"))
    accounting = {k: getattr(info, k) for k in HOMOTOPY_ACCOUNTING}
    accounting.update({k: getattr(sinfo, k) for k in ("group", "orbits", "found", "monodromy_paths",
                                                      "final_paths")})
    return betas[: nsol[0]].copy(), accounting


class BranchingMixin(AssemblyBase):
    """Branching methods of `libkin.Assembly`."""

    def second_order(self, weighting: str = "exact", normalise: bool = True) -> FloatArray:
        """The second-order matrices Q_j at this bifurcation (eq. 17).

        Parameters
        ----------
        weighting : {'exact', 'paper'}, optional
            'exact' includes the 1/L_i factor of eq. 12; 'paper' omits it, as
            the printed eq. 17 does (see ``docs/branches.md``).
        normalise : bool, optional
            Orthonormalise the matrices (eq. 18).

        Returns
        -------
        ndarray, shape (k, m_internal, m_internal)
            Symmetric matrices, one per state of self-stress that the second
            order uses: the s - s_trivial with no force in the bars between
            fixed joints (`Analysis.s_trivial`); k = s - s_trivial, or fewer
            after normalisation where some are dependent.

        Raises
        ------
        InvalidArgumentError
            Unknown `weighting` (a ValueError).
        StateError
            Not a bifurcation point: fewer than 2 internal mechanisms or no
            self-stress but those of bars between fixed joints.
        """
        if weighting not in _WEIGHTINGS:
            raise InvalidArgumentError(f"weighting: expected 'exact' or 'paper', got {weighting!r}")
        an = self.analyse()
        m, s = an.m_internal, an.s - an.s_trivial
        if m < 2 or s < 1:
            raise StateError("not a bifurcation point: need at least 2 internal mechanisms and 1 self-stress "
                             f"(here m = {m}, s = {an.s}" + (f", {an.s_trivial} of them of bars between fixed joints"
                                                            if an.s_trivial else "") + ")")
        Q = np.zeros((s, m, m))
        s_out = ffi.new("int *")
        self._check(lib.kin_second_order(self._h, getattr(lib, _WEIGHTINGS[weighting]), int(bool(normalise)),
                                         write_ptr(Q, "double *"), Q.size, s_out), "second order")
        # each block is column-major m x m; Q_j is symmetric so the layout is immaterial
        return Q[: s_out[0]]

    def branches(self, solver: str = "homotopy", starts: int = 1024, length: float = 1.0, seed: int = 1,
                 weighting: str = "exact", threads: int = 2, progress: Progress = None,
                 max_paths: Optional[int] = None, group: Optional[npt.ArrayLike] = None,
                 symmetry: bool = True) -> Branches:
        """Every path out of this bifurcation.

        Solves the second-order equations (`solve_quadrics`), then follows
        each real solution in both directions (`follow_branches`).

        Parameters
        ----------
        solver : {'homotopy', 'scan'}, optional
            See `solve_quadrics`.
        starts : int, optional
            Starting points of the scan.
        length : float, optional
            Path length to follow each candidate path.
        seed : int, optional
            Seed of the solver.
        weighting : {'exact', 'paper'}, optional
            See `second_order`.
        threads : int, optional
            Threads of the homotopy solver.
        progress : None, bool or callable, optional
            Progress of the homotopy and then of the following (see
            `solve_quadrics`).
        max_paths : int, optional
            See `solve_quadrics`.
        group : array_like, shape (k, m, m), optional
            The symmetry group acting on beta, e.g.
            ``libkin.symmetry.automorphisms.mechanism_group(self, method="c")``: see
            `solve_quadrics` (one homotopy path per orbit where it can); used
            as given. None (default): found here when `symmetry` is true.
        symmetry : bool, optional
            True (default) with group None: the structure's symmetries at
            this configuration (kin_mechanism_group) are given to the
            homotopy solver where that pays and gives the plain solver's
            roots: s >= SYMMETRIC_SOLVE_MIN_S (8) and a cyclic subgroup
            that permutes mechanisms and equations alike (the equivariant
            route); the accounting then has 'group' and 'orbits'. False:
            the plain solver (unless a group is given).

        Returns
        -------
        Branches
            Solutions, directions, followed paths and the solver's accounting.

        Raises
        ------
        InvalidArgumentError
            Unknown `solver` or `weighting`.
        StateError
            Not a bifurcation point, or m_internal != s + 1.
        """
        Q = self.second_order(weighting=weighting)
        if group is None and symmetry and solver == "homotopy":
            group = self.solver_group(Q, seed)
        betas, accounting = solve_quadrics(Q, solver, starts, seed, threads, progress=progress,
                                           max_paths=max_paths, group=group,
                                           basis=self.analyse().internal_mechanisms)
        return self.follow_branches(betas, length=length, accounting=accounting, progress=progress)

    def solver_group(self, Q: FloatArray, seed: int = 1) -> Optional[FloatArray]:
        """The symmetry group that `branches` gives the solver by default.

        Parameters
        ----------
        Q : ndarray, shape (s, m, m)
            The second-order matrices at this configuration (`second_order`).
        seed : int, optional
            Seed of the equivariant form (as the solver's).

        Returns
        -------
        ndarray, shape (k, m, m), or None
            The group at this configuration acting on beta
            (kin_mechanism_group) if the symmetric solver pays on Q: s >=
            SYMMETRIC_SOLVE_MIN_S and a cyclic subgroup permutes mechanisms
            and equations alike (the equivariant route); else None (also
            where the group cannot be formed: no symmetry, or a mechanism
            space it does not keep).
        """
        s, m = Q.shape[0], Q.shape[1]
        if s < SYMMETRIC_SOLVE_MIN_S or m != s + 1:
            return None
        n = ffi.new("int *")
        one = np.empty((1, m, m))
        rc = lib.kin_mechanism_group(self._h, 1, write_ptr(one, "double *"), n)
        if rc not in (0, lib.KIN_ERANGE) or n[0] < 2:
            return None
        R = np.empty((n[0], m, m))  # each block column-major: stored transposed
        if lib.kin_mechanism_group(self._h, n[0], write_ptr(R, "double *"), n) != 0:
            return None
        R = np.ascontiguousarray(R[: n[0]].transpose(0, 2, 1))
        return R if equivariant_order(Q, R, seed) >= 2 else None

    def follow_branches(self, betas: npt.ArrayLike, length: float = 1.0,
                        accounting: Optional[Dict[str, int]] = None, progress: Progress = None) -> Branches:
        """Follow given second-order solutions out of this bifurcation.

        Parameters
        ----------
        betas : array_like, shape (nsol, m_internal)
            Second-order solutions (kin_branch_paths follows each in both
            directions).
        length : float, optional
            Path length to follow each candidate path.
        accounting : dict, optional
            Carried into the result.
        progress : None, bool or callable, optional
            See `solve_quadrics`; Ctrl-C stops the following and raises
            KeyboardInterrupt with the assembly unchanged.

        Returns
        -------
        Branches
            The followed paths, grouped into distinct ones.

        Raises
        ------
        InvalidArgumentError
            `betas` has the wrong number of columns.
        """
        b = np.ascontiguousarray(np.atleast_2d(np.asarray(betas, dtype=np.float64)))
        U = self.analyse().internal_mechanisms
        if b.ndim != 2 or b.shape[1] != U.shape[1]:
            raise InvalidArgumentError(f"betas: expected shape (nsol, {U.shape[1]}), got {b.shape}")
        nsol = b.shape[0]
        paths: List[BranchPath] = []
        distinct = 0
        if nsol:
            cp = new_struct("kin_branch_path", 2 * nsol)
            ends = np.empty((2 * nsol, self.njoints, self.dim))
            nd = ffi.new("int *")
            with reporting(progress, "branches", "path", self._h):
                rc = lib.kin_branch_paths(self._h, read_ptr(b, "double *"), nsol, float(length), cp,
                                          write_ptr(ends, "double *"), nd)
            self._check(rc, "branch paths")
            distinct = nd[0]
            paths = [BranchPath(p.beta, p.sign, bool(p.exists), bool(p.tangent_ok), p.tangent_cos, p.path_id,
                                p.length, ends[k]) for k, p in enumerate(cp)]
        return Branches(b, b @ U.T, paths, distinct, accounting or {})
