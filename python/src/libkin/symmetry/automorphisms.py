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

Candidates come from the automorphisms of the bar graph with the supports
and rest lengths as labels (networkx's VF2 GraphMatcher); each is kept if an
orthogonal Procrustes fit (SVD, Kabsch without the det correction) matches
the configurations with zero residual. When the joints span fewer
dimensions than the space (a flat sail in 3D), the fit is not unique: the
reflections through the missing directions are added (the mirror z -> -z of
a flat sail is a symmetry with the identity permutation).

The C library finds the same symmetries (kin_symmetries, kin_mechanism_group
in include/libkin/kin_symmetry.h: nauty's Traces on the coloured bar graph
instead of VF2, the same Procrustes test): ``method="c"`` in
detect_symmetries and mechanism_group uses it.
"""
from __future__ import annotations

import dataclasses
import itertools
from typing import TYPE_CHECKING, Any, Dict, List, Optional, Tuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InvalidArgumentError

if TYPE_CHECKING:
    from ..assembly import Assembly

# coordinates agree when they differ by less than this times the model size
_REL_TOL = 1e-9
# stop enumerating graph automorphisms after this many (a structure with more
# is reported with the ones found; see detect_symmetries)
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


def _scale(X: NDArray[np.float64]) -> float:
    return max(1.0, float(np.abs(X - X.mean(axis=0)).max()))


def _bar_graph(bars: NDArray[Any], rest: NDArray[np.float64], fixed: NDArray[np.bool_], scale: float) -> Any:
    import networkx as nx
    G = nx.Graph()
    for i in range(fixed.shape[0]):
        G.add_node(i, nfixed=int(fixed[i].sum()))
    for k, (i, j) in enumerate(bars):
        # rest lengths as integers of the tolerance so equal lengths compare equal
        G.add_edge(int(i), int(j), length=int(round(rest[k] / (1e-7 * scale))))
    return G


def _orthogonal_fits(Xc: NDArray[np.float64], Yc: NDArray[np.float64]) -> List[NDArray[np.float64]]:
    """Orthogonal Q with Yc = Xc Q^T, if any: the Procrustes optimum, plus its
    products with the reflections through the directions Xc does not span."""
    H = Xc.T @ Yc
    U, sv, Vt = np.linalg.svd(H)
    Q = Vt.T @ U.T
    scale = max(1.0, float(np.abs(Xc).max()))
    if np.abs(Xc @ Q.T - Yc).max() > _REL_TOL * 100 * scale:
        return []
    # directions Xc does not span: null space of Xc (right singular vectors)
    _, s2, v2 = np.linalg.svd(Xc, full_matrices=True)
    s2 = np.concatenate([s2, np.zeros(Xc.shape[1] - s2.size)])
    null = v2[s2 <= _REL_TOL * scale * max(1, Xc.shape[0])]
    fits = [Q]
    for r in range(1, len(null) + 1):
        for combo in itertools.combinations(range(len(null)), r):
            R = np.eye(Xc.shape[1])
            for c in combo:
                n = null[c]
                R = R @ (np.eye(Xc.shape[1]) - 2.0 * np.outer(n, n))
            fits.append(Q @ R)
    # make entries that are zero to rounding exactly zero (cleaner P matrices)
    return [np.where(np.abs(F) < 1e-12, 0.0, F) for F in fits]


def _keeps_supports(Q: NDArray[np.float64], perm: Tuple[int, ...], fixed: NDArray[np.bool_]) -> bool:
    for i, j in enumerate(perm):
        # fixed axes of i must go into fixed axes of j (counts are equal)
        for a in np.flatnonzero(fixed[i]):
            img = Q[:, a]
            if np.abs(img[~fixed[j]]).max(initial=0.0) > 1e-9:
                return False
    return True


def graph_automorphisms(assembly: Assembly, max_candidates: int = MAX_CANDIDATES) -> List[Tuple[int, ...]]:
    """The permutations of the joints that map bars to bars of the same rest
    length and joints to joints with as many fixed coordinates (networkx's
    VF2 matcher on the bar graph): the candidates for symmetries, whatever
    the configuration. At most max_candidates, in the matcher's order."""
    from networkx.algorithms.isomorphism import GraphMatcher
    rest = assembly.rest_lengths
    G = _bar_graph(assembly.bars, rest, assembly.fixed, max(1.0, float(rest.max())))
    gm = GraphMatcher(G, G, node_match=lambda a, b: a["nfixed"] == b["nfixed"],
                      edge_match=lambda a, b: a["length"] == b["length"])
    perms = []
    for n, iso in enumerate(gm.isomorphisms_iter()):
        if n >= max_candidates:
            break
        perms.append(tuple(int(iso[i]) for i in range(assembly.njoints)))
    return perms


def symmetries_at(assembly: Assembly, perms: List[Tuple[int, ...]], coords: ArrayLike) -> List[Symmetry]:
    """The candidates `perms` (graph_automorphisms) that are symmetries of
    the configuration coords, each with every isometry that realises it;
    identity first, then by perm and Q. Raises InvalidArgumentError if
    coords has the wrong shape."""
    X = np.asarray(coords, dtype=float)
    if X.shape != (assembly.njoints, assembly.dim):
        raise InvalidArgumentError(f"coords: expected shape {(assembly.njoints, assembly.dim)}, got {X.shape}")
    fixed = assembly.fixed
    scale = _scale(X)
    c = X.mean(axis=0)
    Xc = X - c
    found: List[Symmetry] = []
    for perm in perms:
        Yc = X[list(perm)] - c
        for Q in _orthogonal_fits(Xc, Yc):
            if not _keeps_supports(Q, perm, fixed):
                continue
            g = Symmetry(perm, Q, c - Q @ c)
            if np.abs(g.apply(X) - X).max() <= 100 * _REL_TOL * scale:
                found.append(g)
    found.sort(key=lambda g: (not g.is_identity, g.perm, tuple(np.round(g.Q, 9).ravel())))
    return found


def detect_symmetries(assembly: Assembly, coords: Optional[ArrayLike] = None,
                      max_candidates: int = MAX_CANDIDATES, method: str = "python") -> List[Symmetry]:
    """Every symmetry of `assembly` in the configuration `coords` (default:
    its current one): symmetries_at(graph_automorphisms(...)). A symmetry
    of one configuration is one of the structure: it maps every
    configuration to another.

    method="c" asks the C library (kin_symmetries: nauty's Traces; at most
    KIN_SYMMETRY_MAX_CANDIDATES graph automorphisms, beyond which it raises
    LimitError; max_candidates is not used); the assembly is then moved to
    `coords` if given (and left there). Raises InvalidArgumentError for
    another method."""
    if method == "c":
        if coords is not None:
            assembly.coords = np.asarray(coords, dtype=float)
        return c_symmetries(assembly)
    if method != "python":
        raise InvalidArgumentError(f"method: expected 'python' or 'c', got {method!r}")
    X = assembly.coords if coords is None else coords
    return symmetries_at(assembly, graph_automorphisms(assembly, max_candidates), X)


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
        As for detect_symmetries.
    method : {'python', 'c'}, optional
        'c': the C library's kin_mechanism_group (the same group, found with
        nauty; the order of matrices of equal trace may differ).

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
