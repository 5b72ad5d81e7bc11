"""Systems of quadrics and the complete solver's raw endpoints, shared by
the independent re-proofs of its certificates (test_homotopy_prove_exact.py:
exact rationals in Python; test_homotopy_prove_m2.py: Macaulay2's
NumericalCertification)."""
from typing import Tuple

import numpy as np

from libkin import Assembly
from libkin.homotopy.shards import range_task

# the paper's Figure 5(b): x1 = +-x0, x2^2 = +-x0^2 (2 real + 2 non-real)
FIG5B = np.array([[[1, 0, 0], [0, -1, 0], [0, 0, 0]], [[0, -0.5, 0], [-0.5, 0, 0], [0, 0, 1]]], dtype=float)


def random_system(s: int, seed: int) -> np.ndarray:
    """s symmetric Gaussian (s + 1) x (s + 1) matrices"""
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((s, s + 1, s + 1))
    return np.ascontiguousarray(A + A.transpose(0, 2, 1))


def endpoints(Q: np.ndarray, seed: int = 1) -> Tuple[np.ndarray, np.ndarray]:
    """(z, kind): every path's endpoint (2^s, m) complex in homogeneous
    coordinates and its record's class (0 real, 1 non-real, > 1 singular or
    lost), from kin_quadrics_homotopy_range over all paths"""
    from libkin._native._lib import ffi
    s, m = Q.shape[0], Q.shape[1]
    n = 1 << s
    part = range_task({"Q": Q, "first": 0, "count": n, "seed": seed})
    z = np.frombuffer(part["z"]).reshape(n, 2, m)
    ends = ffi.from_buffer("kin_homotopy_endpoint[]", bytearray(part["ends"]))
    kind = np.array([ends[p].kind for p in range(n)])
    return z[:, 0] + 1j * z[:, 1], kind


def square_sail() -> np.ndarray:
    """the square sail's flat state: s = 4, 16 real solutions"""
    return np.ascontiguousarray(Assembly.sail(4, 1).second_order())


def hex_rb_rc() -> Tuple[np.ndarray, np.ndarray]:
    """Q at the hexagonal sail's R^B (s = 3) and at R^C (s = 5, the
    bifurcation with m = 6 that a path out of R^B reaches), as
    tests/test_homotopy_shard.c builds them"""
    from libkin.studies.readings import rb_coords
    a = Assembly.sail(6, 2)
    a.coords = rb_coords(a)
    Qb = np.ascontiguousarray(a.second_order())
    br = a.branches(solver="homotopy", length=0.5, threads=1)
    for p in br.paths:
        if not (p.exists and p.tangent_ok):
            continue
        c = a.clone()
        fe = c.follow_event(br.directions[p.beta] * p.sign, max_steps=800)
        if fe.event == "bifurcation" and c.analyse().m_internal == 6:
            return Qb, np.ascontiguousarray(c.second_order())
    raise AssertionError("no path out of R^B reaches R^C")
