"""Symmetries of a bar assembly, found automatically.

A symmetry g = (perm, Q, t) of an assembly in a configuration X is a
permutation of the joints and an isometry x -> Q x + t (Q orthogonal, proper
or not) such that
  - bars go to bars of the same rest length: {i, j} -> {perm[i], perm[j]},
  - supports go to supports: Q maps the fixed axes of joint i onto the fixed
    axes of joint perm[i] (so free coordinates go to free coordinates),
  - the configuration is kept: X[perm[i]] = Q X[i] + t for every joint.
Such a g maps every configuration of the structure to another one,
g.X'[perm[i]] = Q X'[i] + t, and paths to paths, so the paths out of g.X'
are the images of those out of X'.

The search is the C library's (kin_symmetries, kin_mechanism_group in
include/libkin/kin_symmetry.h; docs/branches.md): the candidates are the
automorphisms of the bar graph coloured by supports and rest lengths, found
by nauty's Traces, and each is kept if an orthogonal Procrustes fit matches
the configurations with zero residual and maps fixed axes onto fixed axes.
When the joints span fewer dimensions than the space (a flat sail in 3D),
the fit is not unique: the reflections through the missing directions are
tried too (the mirror z -> -z of a flat sail is a symmetry with the
identity permutation). Every function here calls that search through cffi;
a structure whose coloured bar graph has more than MAX_CANDIDATES
automorphisms is refused with LimitError.
"""
from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING, Any, Dict, List, Optional, Tuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InvalidArgumentError

if TYPE_CHECKING:
    from ..assembly import Assembly

# a Q entry below this counts as zero in the action on free coordinates
_REL_TOL = 1e-9
# the C search's cap on graph automorphisms (KIN_SYMMETRY_MAX_CANDIDATES): a
# structure with more is refused with LimitError
MAX_CANDIDATES = 20000


@dataclasses.dataclass(frozen=True)
class Symmetry:
    """One symmetry: joint i goes to perm[i], a point x to Q @ x + t."""

    perm: Tuple[int, ...]
    Q: np.ndarray
    t: np.ndarray

    @property
    def proper(self) -> bool:
        """True for a rotation (det Q = +1), False for a reflection."""
        return bool(np.linalg.det(self.Q) > 0)

    @property
    def is_identity(self) -> bool:
        return (all(i == p for i, p in enumerate(self.perm)) and np.allclose(self.Q, np.eye(len(self.Q)))
                and np.allclose(self.t, 0.0))

    def apply(self, X: ArrayLike) -> NDArray[np.float64]:
        """The image g.X of a configuration X (njoints, dim)."""
        X = np.asarray(X, dtype=float)
        Y = np.empty_like(X)
        Y[list(self.perm)] = X @ self.Q.T + self.t
        return Y

    def free_matrix(self, free_map: NDArray[Any]) -> NDArray[np.float64]:
        """The action on free-coordinate vectors (mechanisms): P (nfree, nfree)
        with (P v) the velocity of g.X when v is the velocity of X."""
        nfree = int(free_map.max()) + 1
        P = np.zeros((nfree, nfree))
        nj, dim = free_map.shape
        for i in range(nj):
            j = self.perm[i]
            for a in range(dim):
                fi = free_map[i, a]
                if fi < 0:
                    continue
                for b in range(dim):
                    if abs(self.Q[b, a]) > _REL_TOL:
                        P[free_map[j, b], fi] = self.Q[b, a]
        return P

    def to_dict(self) -> Dict[str, Any]:
        return {"perm": [int(p) for p in self.perm], "Q": self.Q.round(15).tolist(), "t": self.t.round(15).tolist(),
                "proper": self.proper}


def _assembly_at(assembly: Assembly, coords: ArrayLike) -> Assembly:
    """A copy of `assembly` in the configuration coords (a new assembly with
    the same bars, supports and rest lengths if coords moves a support).
    Raises InvalidArgumentError if coords has the wrong shape."""
    X = np.asarray(coords, dtype=float)
    if X.shape != (assembly.njoints, assembly.dim):
        raise InvalidArgumentError(f"coords: expected shape {(assembly.njoints, assembly.dim)}, got {X.shape}")
    b = assembly.clone()
    try:
        b.coords = X
    except InvalidArgumentError:  # a support moved: kin_set_coords keeps supports
        from ..assembly import Assembly
        b.close()
        b = Assembly(X, assembly.bars, assembly.fixed, assembly.rest_lengths)
    return b


def graph_automorphisms(assembly: Assembly, max_candidates: int = MAX_CANDIDATES) -> List[Tuple[int, ...]]:
    """The joint permutations of the symmetries of `assembly` at its current
    configuration (the C search, detect_symmetries), each once, in its order,
    at most max_candidates. The search over the automorphisms of the bar
    graph itself runs inside the C library (nauty's Traces, which colours
    the graph by the configuration too); symmetries_at(assembly, None, X)
    searches at another configuration X. Raises LimitError beyond
    MAX_CANDIDATES graph automorphisms."""
    perms: List[Tuple[int, ...]] = []
    for g in c_symmetries(assembly):
        if g.perm not in perms:
            perms.append(g.perm)
    return perms[:max_candidates]


def symmetries_at(assembly: Assembly, perms: Optional[List[Tuple[int, ...]]], coords: ArrayLike) -> List[Symmetry]:
    """The symmetries of the configuration coords (the C search at coords;
    the assembly is not moved), each with every isometry that realises it,
    only those whose permutation is in `perms` unless perms is None;
    identity first, then by perm and Q. Raises InvalidArgumentError if
    coords has the wrong shape, LimitError beyond MAX_CANDIDATES graph
    automorphisms."""
    b = _assembly_at(assembly, coords)
    try:
        found = c_symmetries(b)
    finally:
        b.close()
    if perms is not None:
        keep = set(perms)
        found = [g for g in found if g.perm in keep]
    return _in_order(found)


def _in_order(found: List[Symmetry]) -> List[Symmetry]:
    """Identity first, then by perm and Q (the C order, made explicit for
    the isometries of one permutation)."""
    return sorted(found, key=lambda g: (not g.is_identity, g.perm, tuple(np.round(g.Q, 9).ravel())))


def detect_symmetries(assembly: Assembly, coords: Optional[ArrayLike] = None,
                      max_candidates: int = MAX_CANDIDATES, method: str = "python") -> List[Symmetry]:
    """Every symmetry of `assembly` in the configuration `coords` (default:
    its current one), found by the C library (kin_symmetries: nauty's
    Traces; at most MAX_CANDIDATES graph automorphisms, beyond which it
    raises LimitError; max_candidates is not used). A symmetry of one
    configuration is one of the structure: it maps every configuration to
    another.

    method="python" (default) leaves the assembly where it is
    (symmetries_at); method="c" moves it to `coords` if given (and leaves it
    there). Both run the same search. Raises InvalidArgumentError for
    another method."""
    if method == "c":
        if coords is not None:
            assembly.coords = np.asarray(coords, dtype=float)
        return c_symmetries(assembly)
    if method != "python":
        raise InvalidArgumentError(f"method: expected 'python' or 'c', got {method!r}")
    if coords is None:  # kin_symmetries does not move the assembly
        return _in_order(c_symmetries(assembly))
    return symmetries_at(assembly, None, coords)


def _c_count(call: Any, assembly: "Assembly", what: str) -> int:
    """How many entries a kin_symmetries-like call has: asked with room for
    one (KIN_ERANGE reports the count)."""
    from .._native._lib import ffi, lib
    n = ffi.new("int *")
    rc = call(1, n)
    if rc == lib.KIN_ERANGE:
        return int(n[0])
    assembly._check(rc, what)
    return int(n[0])


def c_symmetries(assembly: "Assembly") -> List[Symmetry]:
    """detect_symmetries(assembly, method="c"): the C library's
    kin_symmetries at the current configuration, in its order (the
    identity first, then by permutation)."""
    from .._native._lib import ffi, lib
    h, nj, d = assembly._h, assembly.njoints, assembly.dim
    count = _c_count(lambda k, n: lib.kin_symmetries(h, k, ffi.NULL, ffi.NULL, ffi.NULL, n), assembly, "symmetries")
    perm = np.zeros((count, nj), dtype=np.int32)
    Q = np.zeros((count, d, d))  # each block column-major: stored transposed
    t = np.zeros((count, d))
    n = ffi.new("int *")
    assembly._check(lib.kin_symmetries(h, count, ffi.cast("int *", ffi.from_buffer(perm, require_writable=True)),
                                       ffi.cast("double *", ffi.from_buffer(Q, require_writable=True)),
                                       ffi.cast("double *", ffi.from_buffer(t, require_writable=True)), n),
                    "symmetries")
    return [Symmetry(tuple(int(p) for p in perm[k]), Q[k].T.copy(), t[k].copy()) for k in range(int(n[0]))]


def same_symmetry(g: Symmetry, h: Symmetry) -> bool:
    """g and h are the same map (permutation and isometry)."""
    return g.perm == h.perm and bool(np.allclose(g.Q, h.Q, atol=1e-9)) and bool(np.allclose(g.t, h.t, atol=1e-9))


def invariant_subspace(U: NDArray[np.float64], matrices: List[NDArray[np.float64]]) -> NDArray[np.float64]:
    """Orthonormal basis G (m, k) of the beta with U beta invariant under
    every P in `matrices` (free-coordinate actions); U has orthonormal
    columns."""
    m = U.shape[1]
    if not matrices:
        return np.eye(m)
    A = np.vstack([U.T @ P @ U - np.eye(m) for P in matrices])
    _, sv, vt = np.linalg.svd(A)
    sv = np.concatenate([sv, np.zeros(m - sv.size)])
    return vt[sv < 1e-9 * max(1.0, sv[0] if sv.size else 1.0)].T


def mechanism_group(assembly: "Assembly", coords: Optional[ArrayLike] = None,
                    max_candidates: int = MAX_CANDIDATES, method: str = "python") -> NDArray[np.float64]:
    """The symmetry group acting on the internal-mechanism coordinates beta.

    For each symmetry g of the assembly at `coords` (detect_symmetries;
    default: its current configuration), R_g = U^T P_g U with U the internal
    mechanisms (``analyse().internal_mechanisms``) and P_g its action on
    free coordinates (`Symmetry.free_matrix`): the second-order system
    ``beta^T Q_j beta`` at that configuration is then equivariant under
    R_g, which is what ``solve_quadrics(Q, group=...)`` takes.

    Parameters
    ----------
    assembly : Assembly
        Moved to `coords` if given (and left there).
    coords : array_like, shape (njoints, dim), optional
    max_candidates : int, optional
        As for detect_symmetries (not used).
    method : {'python', 'c'}, optional
        'python': the R_g formed here from the C search's symmetries
        (detect_symmetries), ordered by decreasing trace; 'c': the C
        library's kin_mechanism_group (the same group; the order of
        matrices of equal trace may differ).

    Returns
    -------
    ndarray, shape (k, m_internal, m_internal)
        Orthogonal matrices, the identity first.

    Raises
    ------
    InvalidArgumentError
        A symmetry does not map the mechanism space to itself (R_g not
        orthogonal to 1e-8): the configuration is not the one the
        symmetries were found at. Also an unknown method.
    StateError
        method='c': as InvalidArgumentError above (KIN_ESTATE).
    NoMechanismError
        method='c': the assembly has no internal mechanism.
    LimitError
        More than MAX_CANDIDATES graph automorphisms.
    """
    if method not in ("python", "c"):
        raise InvalidArgumentError(f"method: expected 'python' or 'c', got {method!r}")
    if coords is not None:
        assembly.coords = np.asarray(coords, dtype=float)
    if method == "c":
        return c_mechanism_group(assembly)
    syms = detect_symmetries(assembly, None, max_candidates)
    U = assembly.analyse().internal_mechanisms
    fm = assembly.free_map()
    mats = []
    for g in syms:
        R = U.T @ g.free_matrix(fm) @ U
        if np.abs(R.T @ R - np.eye(len(R))).max() > 1e-8:
            raise InvalidArgumentError("a symmetry does not preserve the internal mechanisms")
        mats.append(R)
    mats.sort(key=lambda R: -float(np.trace(R)))
    return np.array(mats) if mats else np.eye(U.shape[1])[None]


def c_mechanism_group(assembly: "Assembly") -> NDArray[np.float64]:
    """mechanism_group(assembly, method="c"): the C library's
    kin_mechanism_group at the current configuration, shape (k, m, m)."""
    from .._native._lib import ffi, lib, new_struct
    h = assembly._h
    an = new_struct("kin_analysis")
    if lib.kin_get_analysis(h, an) != 0:  # none current: make it (kin_mechanism_group would)
        assembly._check(lib.kin_analyse(h, an), "analyse")
    m = int(an.m_internal)
    # kin_symmetries is cheap next to the R_g (m x m products over nfree): the count first
    count = _c_count(lambda k, n: lib.kin_symmetries(h, k, ffi.NULL, ffi.NULL, ffi.NULL, n), assembly,
                     "mechanism group")
    R = np.zeros((max(count, 1), m, m))  # each block column-major: stored transposed
    n = ffi.new("int *")
    assembly._check(lib.kin_mechanism_group(h, max(count, 1),
                                            ffi.cast("double *", ffi.from_buffer(R, require_writable=True)), n),
                    "mechanism group")
    return np.ascontiguousarray(R[: int(n[0])].transpose(0, 2, 1))
