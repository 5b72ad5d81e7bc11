"""The Assembly class: a pin-jointed bar assembly owned by a libkin handle.

Units: coordinates and lengths are in the caller's length unit; singular
values and mechanisms are dimensionless (H holds direction cosines);
mechanism vectors have one entry per free coordinate, ordered joint by joint
and x, y, z within a joint (see Assembly.free_index).
"""
import dataclasses
import math

import numpy as np

from ._arrays import as_c_array, read_ptr, write_ptr
from ._lib import ffi, lib, new_struct
from ._progress import reporting
from .errors import ModelFormatError, StateError, check


@dataclasses.dataclass(frozen=True)
class Analysis:
    """First-order analysis (paper 3.1) of one configuration.

    singular_values: (min(nfree, nbars),) descending. internal_mechanisms:
    (nfree, m_internal), rigid_mechanisms: (nfree, m_rigid), self_stresses:
    (nbars, s); all with orthonormal columns."""

    rank: int
    m: int
    m_rigid: int
    m_internal: int
    s: int
    v_max: float
    v_r: float
    singular_values: np.ndarray
    internal_mechanisms: np.ndarray
    rigid_mechanisms: np.ndarray
    self_stresses: np.ndarray


@dataclasses.dataclass(frozen=True)
class StepInfo:
    """What one predictor-corrector step did (see kin_step_info in kin_path.h).
    l: signed path length (length unit); delta: amplitude used; v_r: lowest
    non-zero singular value at the new point; residual: max |L-L0|/L0."""

    l: float
    delta: float
    v_r: float
    residual: float
    cos_turn: float
    iterations: int
    halvings: int
    factorizations: int
    m_internal: int


@dataclasses.dataclass
class Options:
    """Tolerances of a handle (kin_options).

    factorization: how a step factorizes at each new point (kin_path.h):
    0 = lib.KIN_STEP_SVD (default: the full SVD analysis of every point),
    1 = lib.KIN_STEP_LU (LU/QR of the bordered matrix, the SVD only near a
    bifurcation: the same points to rounding, a step costs a fraction of an
    SVD; StepInfo.v_r is then an upper-bound estimate)."""

    rank_tol: float = 1e-9
    corrector_tol: float = 1e-12
    corrector_max_iter: int = 60
    step_fraction: float = 0.1
    max_halvings: int = 12
    direction_tol: float = 0.9
    max_correction: float = 0.5
    factorization: int = 0


_OPTION_FIELDS = [f.name for f in dataclasses.fields(Options)]


class Assembly:
    """A pin-jointed bar assembly in 2D or 3D.

    Assembly(coords, bars, fixed=None, lengths=None)
      coords  (njoints, dim) float, dim 2 or 3
      bars    (nbars, 2) int joint indices (0-based)
      fixed   (njoints, dim) bool, True = that coordinate is a support; None = all free
      lengths (nbars,) rest lengths; None = the initial lengths
    Use as a context manager or call close(); the handle is also freed when
    the object is garbage-collected."""

    def __init__(self, coords, bars, fixed=None, lengths=None, *, labels=None, name=None):
        coords_a = as_c_array(coords, np.float64, (None, None), "coords")
        if coords_a.ndim != 2 or coords_a.shape[1] not in (2, 3):
            raise ModelFormatError(f"coords: expected shape (njoints, 2 or 3), got {coords_a.shape}")
        nj, dim = coords_a.shape
        bars_a = as_c_array(bars, np.int32, (None, 2), "bars")
        fixed_a = None if fixed is None else as_c_array(fixed, np.uint8, (nj, dim), "fixed")
        len_a = None if lengths is None else as_c_array(lengths, np.float64, (bars_a.shape[0],), "lengths")
        out = ffi.new("kin_assembly **")
        err = ffi.new("char[512]")
        rc = lib.kin_assembly_create(
            dim, nj, read_ptr(coords_a, "double *"),
            ffi.NULL if fixed_a is None else read_ptr(fixed_a, "unsigned char *"),
            bars_a.shape[0], read_ptr(bars_a, "int *"),
            ffi.NULL if len_a is None else read_ptr(len_a, "double *"), out, err, 512)
        if rc:
            from .errors import error_class
            raise error_class(rc)(ffi.string(err).decode(), rc)
        self._adopt(out[0])
        self.labels = list(labels) if labels is not None else None
        self.name = name

    # ---- lifetime ------------------------------------------------------
    def _adopt(self, ptr):
        self._p = ffi.gc(ptr, lib.kin_assembly_free)

    @classmethod
    def _from_handle(cls, ptr, labels=None, name=None):
        obj = cls.__new__(cls)
        obj._adopt(ptr)
        obj.labels = labels
        obj.name = name
        return obj

    def close(self):
        """Free the C handle now. Further use raises StateError."""
        if getattr(self, "_p", None) is not None:
            ffi.release(self._p)
            self._p = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    @property
    def _h(self):
        p = getattr(self, "_p", None)
        if p is None:
            raise StateError("the assembly is closed")
        return p

    def _check(self, rc, what=""):
        check(rc, self._h, what)

    # ---- built-in models -------------------------------------------------
    @classmethod
    def threebar(cls, state="RC"):
        """The paper's three-bar linkage at 'RA', 'RB' or 'RC'."""
        states = {"RA": lib.KIN_THREEBAR_RA, "RB": lib.KIN_THREEBAR_RB, "RC": lib.KIN_THREEBAR_RC}
        if state not in states:
            raise ModelFormatError(f"state: expected one of {sorted(states)}, got {state!r}")
        out = ffi.new("kin_assembly **")
        check(lib.kin_model_threebar(states[state], out), what="threebar")
        return cls._from_handle(out[0], ["J1", "J2", "S1", "S2"], f"threebar_{state}")

    @classmethod
    def sail(cls, n_sides=6, n_loops=2, side=1.0, widths=None, support="auto", diagonal="forward"):
        """A member of the wrapping-fold solar-sail family (kin_model_sail):
        (4, 1) is the paper's square-hub sail, (6, 2) the hexagonal one."""
        p = new_struct("kin_sail_params")
        lib.kin_sail_params_default(p, int(n_sides), int(n_loops))
        p.side = float(side)
        supports = {"auto": lib.KIN_SAIL_SUPPORT_AUTO, "opposite": lib.KIN_SAIL_SUPPORT_OPPOSITE,
                    "centre": lib.KIN_SAIL_SUPPORT_CENTRE}
        diagonals = {"forward": lib.KIN_SAIL_DIAG_FORWARD, "backward": lib.KIN_SAIL_DIAG_BACKWARD}
        if support not in supports:
            raise ModelFormatError(f"support: expected one of {sorted(supports)}, got {support!r}")
        if diagonal not in diagonals:
            raise ModelFormatError(f"diagonal: expected one of {sorted(diagonals)}, got {diagonal!r}")
        p.support = supports[support]
        p.diagonal = diagonals[diagonal]
        keep = None
        if widths is not None:
            keep = as_c_array(widths, np.float64, (int(n_loops),), "widths")
            p.widths = read_ptr(keep, "double *")
        out = ffi.new("kin_assembly **")
        err = ffi.new("char[512]")
        rc = lib.kin_model_sail(p, out, err, 512)
        if rc:
            from .errors import error_class
            raise error_class(rc)(ffi.string(err).decode(), rc)
        centre = supports[support] == lib.KIN_SAIL_SUPPORT_CENTRE or (
            supports[support] == lib.KIN_SAIL_SUPPORT_AUTO and n_sides != 4)
        labels = (["C"] if centre else []) + [f"V{k}" for k in range(n_sides)]
        for q in range(1, n_loops + 1):
            labels += [f"{chr(ord('A') + q - 1) if q <= 26 else 'L' + str(q)}{k}" for k in range(n_sides)]
        return cls._from_handle(out[0], labels, f"sail_{n_sides}x{n_loops}")

    def clone(self):
        """Deep copy: model, configuration, options and path state."""
        out = ffi.new("kin_assembly **")
        self._check(lib.kin_assembly_clone(self._h, out), "clone")
        return Assembly._from_handle(out[0], self.labels, self.name)

    # ---- model ---------------------------------------------------------
    @property
    def dim(self):
        return lib.kin_dim(self._h)

    @property
    def njoints(self):
        return lib.kin_njoints(self._h)

    @property
    def nbars(self):
        return lib.kin_nbars(self._h)

    @property
    def nfree(self):
        """Number of free coordinates = rows of H = length of a mechanism."""
        return lib.kin_nfree(self._h)

    def free_index(self, joint, axis):
        """Row of H of coordinate `axis` (0=x, 1=y, 2=z) of `joint`, or -1 if fixed."""
        return lib.kin_free_index(self._h, int(joint), int(axis))

    def free_map(self):
        """(njoints, dim) int array: row of H of each coordinate, -1 where fixed."""
        return np.array([[self.free_index(j, c) for c in range(self.dim)] for j in range(self.njoints)])

    @property
    def coords(self):
        """Current joint coordinates, (njoints, dim) float64 (a copy)."""
        out = np.empty((self.njoints, self.dim))
        self._check(lib.kin_get_coords(self._h, write_ptr(out, "double *")))
        return out

    @coords.setter
    def coords(self, value):
        arr = as_c_array(value, np.float64, (self.njoints, self.dim), "coords")
        self._check(lib.kin_set_coords(self._h, read_ptr(arr, "double *")), "set coords")

    @property
    def bars(self):
        out = np.empty((self.nbars, 2), dtype=np.int32)
        self._check(lib.kin_get_bars(self._h, write_ptr(out, "int *")))
        return out

    @property
    def rest_lengths(self):
        out = np.empty(self.nbars)
        self._check(lib.kin_get_rest_lengths(self._h, write_ptr(out, "double *")))
        return out

    @property
    def lengths(self):
        """Current bar lengths, (nbars,)."""
        out = np.empty(self.nbars)
        self._check(lib.kin_get_lengths(self._h, write_ptr(out, "double *")))
        return out

    @property
    def fixed(self):
        out = np.empty((self.njoints, self.dim), dtype=np.uint8)
        self._check(lib.kin_get_fixed(self._h, write_ptr(out, "unsigned char *")))
        return out.astype(bool)

    @property
    def max_strain(self):
        """max |L - L0| / L0 over the bars (dimensionless)."""
        return lib.kin_max_strain(self._h)

    def equilibrium_matrix(self):
        """H, (nfree, nbars): column k holds bar k's direction cosines."""
        out = np.empty((self.nfree, self.nbars), order="F")
        self._check(lib.kin_get_equilibrium_matrix(self._h, write_ptr(out, "double *"), self.nfree))
        return out

    # ---- analysis --------------------------------------------------------
    def analyse(self):
        """Factorize H here and return an Analysis."""
        an = new_struct("kin_analysis")
        self._check(lib.kin_analyse(self._h, an), "analyse")
        nf, nb = self.nfree, self.nbars
        sv = np.empty(min(nf, nb))
        self._check(lib.kin_get_singular_values(self._h, write_ptr(sv, "double *"), sv.size))

        def mech(kind, cols):
            out = np.empty((nf, cols), order="F")
            if cols:
                self._check(lib.kin_get_mechanisms(self._h, kind, write_ptr(out, "double *"), nf, cols))
            return out

        ws = np.empty((nb, an.s), order="F")
        if an.s:
            self._check(lib.kin_get_self_stresses(self._h, write_ptr(ws, "double *"), nb, an.s))
        return Analysis(an.rank, an.m, an.m_rigid, an.m_internal, an.s, an.v_max, an.v_r, sv,
                        mech(lib.KIN_MECH_INTERNAL, an.m_internal), mech(lib.KIN_MECH_RIGID, an.m_rigid), ws)

    # ---- path ------------------------------------------------------------
    @property
    def options(self):
        o = new_struct("kin_options")
        self._check(lib.kin_get_options(self._h, o))
        return Options(**{k: getattr(o, k) for k in _OPTION_FIELDS})

    @options.setter
    def options(self, value):
        if not isinstance(value, Options):
            raise TypeError("options must be a libkin.Options")
        o = new_struct("kin_options")
        for k in _OPTION_FIELDS:
            setattr(o, k, getattr(value, k))
        self._check(lib.kin_set_options(self._h, o), "options")

    def step(self, delta=0.0):
        """One predictor-corrector step of amplitude delta (length unit;
        0 = the largest allowed, negative = backwards). Returns StepInfo;
        raises NotConvergedError / PathJumpError with the assembly unchanged."""
        if not isinstance(delta, (int, float)) or not math.isfinite(delta):
            raise ModelFormatError(f"delta: expected a finite number, got {delta!r}")
        info = new_struct("kin_step_info")
        self._check(lib.kin_step(self._h, float(delta), info), "step")
        return StepInfo(info.l, info.delta, info.v_r, info.residual, info.cos_turn,
                        info.iterations, info.halvings, info.factorizations, info.m_internal)

    def follow(self, steps=None, length=None, delta=0.0, progress=False):
        """Yield StepInfo for `steps` steps, or until the path length has grown
        by `length`. progress=True shows a progress bar (tqdm, if installed)."""
        if steps is None and length is None:
            raise ValueError("give steps or length")
        start = self.path_length
        bar = None
        if progress:
            try:
                from tqdm import tqdm
                bar = tqdm(total=steps if steps is not None else float(length), unit="step" if steps else "len")
            except ImportError:
                bar = None
        k = 0
        try:
            while (steps is None or k < steps) and (length is None or abs(self.path_length - start) < length):
                info = self.step(delta)
                k += 1
                if bar is not None:
                    bar.update(1 if steps is not None else abs(info.l - start) - bar.n)
                yield info
        finally:
            if bar is not None:
                bar.close()

    @property
    def path_length(self):
        """Signed path length travelled (sum of step chords, length unit)."""
        return lib.kin_path_length(self._h)

    def set_direction(self, direction):
        """Choose the direction of motion: a (nfree,) first-order mechanism,
        e.g. internal_mechanisms @ beta at a bifurcation."""
        arr = as_c_array(direction, np.float64, (self.nfree,), "direction")
        self._check(lib.kin_path_set_direction(self._h, read_ptr(arr, "double *"), arr.size), "direction")

    def tangent(self):
        """The oriented unit tangent the next step uses, (nfree,)."""
        out = np.empty(self.nfree)
        self._check(lib.kin_get_tangent(self._h, write_ptr(out, "double *"), self.nfree), "tangent")
        return out

    def relax(self, max_iter=100):
        """Move to a nearby strain-free configuration; returns the residual."""
        res = ffi.new("double *")
        self._check(lib.kin_relax(self._h, int(max_iter), res), "relax")
        return res[0]

    def reset_path(self):
        self._check(lib.kin_path_reset(self._h))

    def __repr__(self):
        if getattr(self, "_p", None) is None:
            return "<libkin.Assembly (closed)>"
        return f"<libkin.Assembly {self.name or ''} dim={self.dim} joints={self.njoints} bars={self.nbars} free={self.nfree}>"


@dataclasses.dataclass(frozen=True)
class BranchPath:
    """One directed candidate path out of a bifurcation (paper 3.4)."""

    beta: int
    sign: int
    exists: bool
    tangent_ok: bool
    tangent_cos: float
    path_id: int
    length: float
    final_coords: np.ndarray


@dataclasses.dataclass(frozen=True)
class Branches:
    """All paths out of a bifurcation: the second-order solutions `betas`
    (nsol, m_internal), their directions U_m beta (nsol, nfree), the directed
    candidate paths and how many are distinct, and the solver's accounting."""

    betas: np.ndarray
    directions: np.ndarray
    paths: list
    distinct: int
    accounting: dict


def _second_order(self, weighting="exact", normalise=True):
    """The s second-order matrices Q_j (s, m, m) at this bifurcation (eq. 17
    with the 1/L_i factor of eq. 12; weighting='paper' omits it, as the
    printed eq. 17 does). normalise applies eq. 18."""
    an = self.analyse()
    w = {"exact": lib.KIN_Q_EXACT, "paper": lib.KIN_Q_PAPER_EQ17}
    if weighting not in w:
        raise ModelFormatError(f"weighting: expected 'exact' or 'paper', got {weighting!r}")
    m, s = an.m_internal, an.s
    if m < 2 or s < 1:
        raise StateError("not a bifurcation point: need at least 2 internal mechanisms and 1 self-stress")
    Q = np.zeros((s, m, m))
    s_out = ffi.new("int *")
    self._check(lib.kin_second_order(self._h, w[weighting], int(bool(normalise)), write_ptr(Q, "double *"),
                                     Q.size, s_out), "second order")
    # each block is column-major m x m; Q_j is symmetric so the layout is immaterial
    return Q[: s_out[0]]


def solve_quadrics(Q, solver="homotopy", starts=1024, seed=1, threads=2, progress=None, max_paths=None):
    """Real solutions beta (nsol, m) of beta^T Q_j beta = 0 (j < s), |beta| = 1,
    for Q of shape (s, m, m) with m = s + 1, and the solver's accounting
    (see _branches). The homotopy: `threads` at most the online processors,
    at most `max_paths` paths 2^s (None: the library's 2^20; more raises
    LimitError), progress as in libkin._progress (Ctrl-C stops it within
    about 0.1 s and raises KeyboardInterrupt)."""
    Q = np.asarray(Q, dtype=np.float64)
    if Q.ndim != 3 or Q.shape[1] != Q.shape[2]:
        raise ModelFormatError(f"Q: expected shape (s, m, m), got {Q.shape}")
    s, m = Q.shape[0], Q.shape[1]
    if m != s + 1:
        raise StateError(f"the solvers need m = s + 1; here m = {m}, s = {s}")
    Qc = np.ascontiguousarray(Q)
    maxsol = 1 << min(s, 16)
    betas = np.empty((maxsol, m))
    nsol = ffi.new("int *")
    if solver == "scan":
        info = new_struct("kin_solve_info")
        check(lib.kin_quadrics_scan(m, s, read_ptr(Qc, "double *"), int(starts), int(seed),
                                    write_ptr(betas, "double *"), maxsol, nsol, info), what="scan")
        accounting = {"starts": info.starts, "converged": info.converged, "distinct": info.distinct}
    elif solver == "homotopy":
        info = new_struct("kin_homotopy_info")
        opt = new_struct("kin_homotopy_options")
        lib.kin_homotopy_options_default(opt)
        opt.seed = int(seed)
        opt.nthreads = int(threads)
        if max_paths is not None:
            opt.max_paths = int(max_paths)
        with reporting(progress, f"homotopy 2^{s}", "path") as rep:
            opt.progress = rep.c_callback
            rc = lib.kin_quadrics_homotopy_ex(m, s, read_ptr(Qc, "double *"), opt, write_ptr(betas, "double *"),
                                              maxsol, nsol, ffi.NULL, info)
        check(rc, what="homotopy")
        accounting = {k: getattr(info, k) for k in ("paths", "real", "real_distinct", "nonreal", "singular", "failed",
                                                    "duplicates", "unpaired", "retracked")}
    else:
        raise ModelFormatError(f"solver: expected 'homotopy' or 'scan', got {solver!r}")
    return betas[: nsol[0]].copy(), accounting


def _branches(self, solver="homotopy", starts=1024, length=1.0, seed=1, weighting="exact", threads=2,
              progress=None, max_paths=None):
    """Every path out of this bifurcation: solve the second-order equations
    (solver 'homotopy': the complete solver, accounting for all 2^s paths;
    'scan': the paper's root scan from `starts` points), then follow each
    real solution in both directions to path length `length` and group
    coinciding paths. `accounting` holds the solver's counts. progress (see
    libkin._progress) covers the homotopy and the following, one after the
    other; max_paths: see solve_quadrics."""
    betas, accounting = solve_quadrics(self.second_order(weighting=weighting), solver, starts, seed, threads,
                                       progress=progress, max_paths=max_paths)
    return self.follow_branches(betas, length=length, accounting=accounting, progress=progress)


def _follow_branches(self, betas, length=1.0, accounting=None, progress=None):
    """Follow the second-order solutions `betas` (nsol, m_internal) in both
    directions to path length `length` (kin_branch_paths) and group
    coinciding paths. progress: see libkin._progress (Ctrl-C stops the
    following and raises KeyboardInterrupt; the assembly is unchanged)."""
    betas = np.ascontiguousarray(np.atleast_2d(np.asarray(betas, dtype=np.float64)))
    nsol = [betas.shape[0]]
    U = self.analyse().internal_mechanisms
    if betas.shape[1] != U.shape[1]:
        raise ModelFormatError(f"betas: expected {U.shape[1]} columns, got {betas.shape[1]}")
    paths = []
    distinct = 0
    if nsol[0]:
        cp = new_struct("kin_branch_path", 2 * nsol[0])
        ends = np.empty((2 * nsol[0], self.njoints, self.dim))
        nd = ffi.new("int *")
        with reporting(progress, "branches", "path", self._h):
            rc = lib.kin_branch_paths(self._h, read_ptr(betas, "double *"), nsol[0], float(length), cp,
                                      write_ptr(ends, "double *"), nd)
        self._check(rc, "branch paths")
        distinct = nd[0]
        paths = [BranchPath(p.beta, p.sign, bool(p.exists), bool(p.tangent_ok), p.tangent_cos, p.path_id,
                            p.length, ends[k]) for k, p in enumerate(cp)]
    return Branches(betas, betas @ U.T, paths, distinct, accounting or {})


Assembly.second_order = _second_order
Assembly.branches = _branches
Assembly.follow_branches = _follow_branches


@dataclasses.dataclass(frozen=True)
class LocateInfo:
    """How kin_locate_next found a bifurcation: event (0 none, 1 sign change
    of the test function, 2 paper's switch rule, 3 a step landed on it, 4 v_r
    turned near zero without a sign change),
    steps before detection, factorizations and forward calculations after it,
    the vanishing singular value (absolute and relative to v_max), distance
    moved while locating, whether the located point continues the path it was
    approached on (eq. 26), and m, s at the final point."""

    event: int
    located: bool
    steps: int
    factorizations: int
    forward: int
    v_r: float
    v_r_rel: float
    distance: float
    path_kept: bool
    m_internal: int
    s: int
    zero_order: int = 0


def _locate(self, method="fast", delta=0.0, vr_tol=1e-10, max_steps=1000, progress=None):
    """Follow the path (delta > 0 forwards, < 0 backwards, 0 = largest step)
    until a bifurcation is detected and converge onto it: method 'fast'
    (Hermite interpolation of the path and of the signed vanishing singular
    value), 'illinois' (Illinois on the signed test function) or 'paper'
    (eq. 23-26). Raises
    NotFoundError if none is found or location gives up (the assembly then
    stays on the path). progress: see libkin._progress (done: steps and
    forward calculations; Ctrl-C or a cancel leaves the assembly at the last
    regular point reached on the path)."""
    methods = {"fast": lib.KIN_LOCATE_FAST, "paper": lib.KIN_LOCATE_PAPER, "illinois": lib.KIN_LOCATE_ILLINOIS}
    if method not in methods:
        raise ModelFormatError(f"method: expected one of {sorted(methods)}, got {method!r}")
    o = new_struct("kin_locate_options")
    lib.kin_locate_options_default(o)
    o.method = methods[method]
    o.delta = float(delta)
    o.vr_tol = float(vr_tol)
    o.max_steps = int(max_steps)
    info = new_struct("kin_locate_info")
    with reporting(progress, "locate", "step", self._h):
        rc = lib.kin_locate_next(self._h, o, info)
    self._check(rc, "locate")
    return LocateInfo(info.event, bool(info.located), info.steps, info.factorizations, info.forward,
                      info.v_r, info.v_r_rel, info.distance, bool(info.path_kept), info.m_internal, info.s,
                      info.zero_order)


def _test_function(self):
    """Signed test function tau = sign(det [C; t^T; R^T]) * v_r here."""
    tau = ffi.new("double *")
    self._check(lib.kin_test_function(self._h, tau), "test function")
    return tau[0]


Assembly.locate = _locate
Assembly.test_function = _test_function
